"""The front door: a path (or bytes) in, a report out.

Pinocchio is imported only here, on first use, so that ``import cspace`` and the
command-line tool's start-up stay fast for commands that do not load a robot.
"""

from __future__ import annotations

from .errors import NotARobotError
from .report import Report
from .xmlio import SourceFile, line_of, parse_xml, read_source

FORMATS_BY_ROOT_TAG = {"robot": "urdf"}
"""The root element of each supported format."""


def inspect_source(source: SourceFile, root_joint: str | None = None) -> Report:
    """Analyse a robot file already read into memory.

    Args:
        source: The file's bytes and name.
        root_joint: None, ``"floating"`` or ``"planar"``: a joint to add above the
            root link (URDFs of mobile and legged robots have none).

    Returns:
        The report.

    Raises:
        RobotFileError: The file is not a valid robot description (a subclass says why).
        InvalidRootJointError: ``root_joint`` is not a supported name.
    """
    root = parse_xml(source)
    tag = root.tag if isinstance(root.tag, str) else ""
    fmt = FORMATS_BY_ROOT_TAG.get(tag)
    if fmt is None:
        expected = ", ".join(f"<{t}> ({f.upper()})" for t, f in FORMATS_BY_ROOT_TAG.items())
        raise NotARobotError(
            source.path,
            f"root element <{tag}> is not a robot description (expected {expected})",
            line=line_of(root),
            element=tag,
        )
    from .adapter import build_urdf_model
    from .analysis import analyse
    from .urdf import read_urdf

    description = read_urdf(source.path, root)
    has_mimic = any(j.mimic is not None for j in description.joints)
    model = build_urdf_model(source.path, source.text, root_joint, has_mimic=has_mimic)
    return analyse(source, fmt, description, model, root_joint)


def inspect(path: str, root_joint: str | None = None) -> Report:
    """Analyse the robot file at ``path``.

    Args:
        path: A URDF file.
        root_joint: None, ``"floating"`` or ``"planar"``.

    Returns:
        The report; ``report.to_dict()`` is the JSON document of ``cspace inspect``.

    Raises:
        RobotFileError: The file cannot be read or is not a valid robot description.
        InvalidRootJointError: ``root_joint`` is not a supported name.
    """
    return inspect_source(read_source(path), root_joint)
