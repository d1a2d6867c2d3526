"""The front door: a path (or bytes) in, a report out.

The format is detected from the content: the root element (``<robot>`` URDF,
``<mujoco>`` MJCF, ``<sdf>`` SDF), and a ``<robot>`` that uses xacro's namespace (or a
``.xacro`` file name) is xacro, expanded to URDF first. ``erd:NAME`` names a robot
bundled with example-robot-data.

Pinocchio is imported only here, on first use, so that ``import cspace`` and the
command-line tool's start-up stay fast for commands that do not load a robot.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from lxml import etree

from .description import RobotDescription
from .errors import NotARobotError
from .report import Report
from .xmlio import SourceFile, line_of, parse_xml, read_source

if TYPE_CHECKING:
    from .xacrofile import XacroOptions

XACRO_NAMESPACE = "http://www.ros.org/wiki/xacro"
"""The namespace of xacro's elements (``xmlns:xacro``)."""

FORMATS_BY_ROOT_TAG = {"robot": "urdf", "mujoco": "mjcf", "sdf": "sdf"}
"""The root element of each supported format (xacro files are ``<robot>`` too)."""

FORMATS = ("urdf", "xacro", "mjcf", "sdf")
"""Every format reported in ``source.format``."""


def detect_format(path: str, root: etree._Element) -> str:
    """The format of a parsed robot file, from its root element and xacro's namespace.

    Raises:
        NotARobotError: The root element is not one of a robot format.
    """
    tag = root.tag if isinstance(root.tag, str) else ""
    fmt = FORMATS_BY_ROOT_TAG.get(tag)
    if fmt is None:
        expected = ", ".join(f"<{t}> ({f.upper()})" for t, f in FORMATS_BY_ROOT_TAG.items())
        raise NotARobotError(
            path,
            f"root element <{tag}> is not a robot description (expected {expected})",
            line=line_of(root),
            element=tag,
        )
    if fmt == "urdf" and (path.endswith(".xacro") or _uses_xacro(root)):
        return "xacro"
    return fmt


def _uses_xacro(root: etree._Element) -> bool:
    """True when an element is in xacro's namespace or an attribute substitutes.

    Declaring ``xmlns:xacro`` alone does not count: URDF that xacro generated keeps the
    declaration and is plain URDF.
    """
    prefix = f"{{{XACRO_NAMESPACE}}}"
    for element in root.iter():
        if not isinstance(element.tag, str):
            continue
        if element.tag.startswith(prefix):
            return True
        if any("${" in value or "$(" in value for value in element.attrib.values()):
            return True
    return False


def _without_lines(description: RobotDescription) -> RobotDescription:
    """The description with line numbers dropped (they point into xacro's output)."""
    return RobotDescription(
        name=description.name,
        format=description.format,
        root_link=description.root_link,
        links=tuple(link._replace(line=None) for link in description.links),
        joints=tuple(joint._replace(line=None) for joint in description.joints),
        findings=description.findings,
        model_source=description.model_source,
    )


def inspect_source(
    source: SourceFile,
    root_joint: str | None = None,
    *,
    xacro: XacroOptions | None = None,
    file: str | None = None,
) -> Report:
    """Analyse a robot file already read into memory.

    Args:
        source: The file's bytes and name.
        root_joint: None, ``"floating"`` or ``"planar"``: a joint to add above the
            root link (URDFs of mobile and legged robots have none).
        xacro: Package folders and arguments for xacro files (defaults: none).
        file: The file on disk holding ``source``'s bytes, or None (standard input):
            xacro includes and MJCF paths resolve from its folder.

    Returns:
        The report.

    Raises:
        RobotFileError: The file is not a valid robot description (a subclass says why).
        InvalidRootJointError: ``root_joint`` is not a supported name.
    """
    root = parse_xml(source)
    fmt = detect_format(source.path, root)
    from .adapter import build_mjcf_model, build_model, build_urdf_model
    from .analysis import analyse

    path = source.path
    if fmt in ("urdf", "xacro"):
        from .urdf import read_urdf

        urdf = source
        if fmt == "xacro":
            from .xacrofile import XacroOptions, expand

            urdf = expand(source, xacro or XacroOptions(), file)
            path = f"{source.path} (expanded by xacro)"
            root = parse_xml(urdf._replace(path=path))
        description = read_urdf(path, root)
        if fmt == "xacro":
            description = _without_lines(description)
        has_mimic = any(j.mimic is not None for j in description.joints)
        model = build_urdf_model(
            path,
            description.model_source or urdf.text,  # numbers Pinocchio refuses rewritten
            root_joint,
            has_mimic=has_mimic,
            description=description,
        )
    elif fmt == "mjcf":
        from .mjcf import flatten_composites, read_mjcf
        from .mjcf_include import splice_includes

        spliced = splice_includes(path, root, file)
        robot = read_mjcf(path, root if spliced is None else spliced)
        description = robot.description
        if spliced is None:
            built = build_mjcf_model(path, source.data, root_joint, file=file)
        else:  # Pinocchio reads the spliced document, from a temporary file
            built = build_mjcf_model(path, etree.tostring(spliced), root_joint)
        model = flatten_composites(path, robot, built)
    else:
        from .sdf import read_sdf

        sdf = read_sdf(path, root)
        description = sdf.description
        model = build_model(description.name, sdf.joints, root_joint)
    return analyse(source, fmt, description, model, root_joint)


def inspect(
    path: str, root_joint: str | None = None, *, xacro: XacroOptions | None = None
) -> Report:
    """Analyse the robot file at ``path``.

    Args:
        path: A URDF, xacro, MJCF or SDF file; or ``erd:NAME``, a robot bundled with
            example-robot-data (with the floating base its own loader gives it, unless
            ``root_joint`` says otherwise).
        root_joint: None, ``"floating"`` or ``"planar"``.
        xacro: Package folders and arguments for xacro files.

    Returns:
        The report; ``report.to_dict()`` is the JSON document of ``cspace inspect``.

    Raises:
        RobotFileError: The file cannot be read or is not a valid robot description.
        InvalidRootJointError: ``root_joint`` is not a supported name.
        CspaceError: An unknown ``erd:`` name.
    """
    file = path
    if path.startswith("erd:"):  # example-robot-data (imported only then: it is slow)
        from .erd import resolve

        found, default_root = resolve(path[len("erd:") :])
        file = str(found)
        root_joint = root_joint or default_root
    source = read_source(file)._replace(path=path)
    return inspect_source(source, root_joint, xacro=xacro, file=file)
