"""The front door: a path (or bytes) in, a report out.

The format is detected from the content: OpenUSD by its first bytes (`by_content`), an
XML format by its root element (``<robot>`` URDF, ``<mujoco>`` MJCF, ``<sdf>`` SDF).
xacro runs code, so a ``<robot>`` is expanded as
xacro only when the user asks for it: a ``.xacro`` file name, or ``force_xacro``
(``--xacro``); a ``<robot>`` that uses xacro without that is refused, never expanded
and never read as plain URDF. ``erd:NAME`` names a robot bundled with
example-robot-data.

Every file is read once: the model is built from the bytes read (and, for MJCF, the
files the pre-scan read), never from the path again.

Pinocchio (through `adapter`) is imported on first use, so that ``import
cspace`` and the command-line tool's start-up stay fast for commands that do not load a
robot.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, NamedTuple

from lxml import etree

from cspace._formats.shared.description import RobotDescription
from cspace._formats.shared.erd import ERD_PREFIX, resolve
from cspace._formats.shared.reading import Reading
from cspace._formats.shared.xmlio import (
    ReadBudget,
    SourceFile,
    line_of,
    parse_xml,
    path_text,
    read_source,
)
from cspace._joint_kind import JointKind
from cspace._reports.report import Report
from cspace.errors import (
    InvalidElementError,
    ModelBuildError,
    NotARobotError,
    XacroNotRequestedError,
)

if TYPE_CHECKING:
    from cspace._findings import Diagnostic
    from cspace._formats.srdf.reader import Srdf
    from cspace._formats.xacro.expand import XacroOptions
    from cspace._model.adapter import PinModel

XACRO_NAMESPACE = "http://www.ros.org/wiki/xacro"
"""The namespace of xacro's elements (``xmlns:xacro``)."""

FORMATS_BY_ROOT_TAG = {"robot": "urdf", "mujoco": "mjcf", "sdf": "sdf"}
"""The root element of each supported format (xacro files are ``<robot>`` too)."""


def detect_format(
    path: str, root: etree._Element, *, force_xacro: bool = False, data: bytes | None = None
) -> str:
    """The format of a parsed robot file, from its root element.

    Args:
        path: The file's name (a ``.xacro`` name asks for xacro expansion).
        root: The parsed root element.
        force_xacro: The user asked for xacro expansion whatever the name.
        data: The bytes ``root`` was parsed from, if at hand: a file in which no xacro
            use can hide (see `_may_use_xacro`) is not searched.

    Raises:
        NotARobotError: The root element is not one of a robot format, or xacro was
            asked for on a file that is not a ``<robot>``.
        XacroNotRequestedError: A ``<robot>`` uses xacro but expansion was not asked for.
    """
    tag = root.tag if isinstance(root.tag, str) else ""
    fmt = FORMATS_BY_ROOT_TAG.get(tag)
    from cspace._formats.shared.roots import FRAGMENT_ROOTS

    if tag in FRAGMENT_ROOTS:
        raise NotARobotError(
            path,
            f"an MJCF fragment (<{tag}>), checked as part of the model that includes it: "
            "inspect that model",
            code="mjcf-fragment",
            line=line_of(root),
            element=tag,
        )
    if fmt is None:
        expected = ", ".join(f"<{t}> ({f.upper()})" for t, f in FORMATS_BY_ROOT_TAG.items())
        raise NotARobotError(
            path,
            f"root element <{tag}> is not a robot description (expected {expected})",
            line=line_of(root),
            element=tag,
        )
    if fmt != "urdf":
        if force_xacro:
            raise NotARobotError(
                path,
                f"--xacro expands <robot> files, and this one is <{tag}>",
                line=line_of(root),
                element=tag,
            )
        return fmt
    if force_xacro or path.endswith(".xacro"):
        return "xacro"
    used = _xacro_use(root) if data is None or _may_use_xacro(root, data) else None
    if used is not None:
        element, what = used
        raise XacroNotRequestedError(
            path,
            f"the file uses xacro ({what}); xacro runs code, so cspace expands it only for "
            "files named *.xacro or with --xacro",
            line=line_of(element),
            element=str(element.tag),
        )
    return fmt


_ASCII_SUPERSETS = frozenset(
    ("utf-8", "utf8", "ascii", "us-ascii", "iso-8859-1", "latin1", "latin-1")
)
"""Encodings in which the ASCII markers of `_XACRO_MARKERS` are their ASCII bytes."""

_XACRO_MARKERS = (b"${", b"$(", XACRO_NAMESPACE.encode(), b"xacro:", b"&#")
"""What xacro use needs in a file's bytes: a substitution, xacro's namespace, an element
named ``xacro:...`` (xacro goes by the name, whatever namespace the prefix is bound to),
or a character reference that could spell any of them."""


def _may_use_xacro(root: etree._Element, data: bytes) -> bool:
    """False when the bytes rule out every use `_xacro_use` looks for.

    A search of the bytes in C is far cheaper than the XPath query over every attribute
    (25 ms at 4,000 joints). It rules out only what it can: in an encoding that is not
    ASCII's superset (UTF-16, say, declared or not) the markers are other bytes, so the
    query runs.
    """
    if b"\x00" in data:  # UTF-16 or UTF-32, which libxml2 detects with no declaration
        return True
    encoding = (root.getroottree().docinfo.encoding or "").lower().replace("_", "-")
    if encoding not in _ASCII_SUPERSETS:  # the declared encoding (UTF-8 when none)
        return True
    return any(marker in data for marker in _XACRO_MARKERS)


def _xacro_use(root: etree._Element) -> tuple[etree._Element, str] | None:
    """The first element of xacro's or attribute with a substitution, and what it is.

    Declaring ``xmlns:xacro`` alone does not count: URDF that xacro generated keeps the
    declaration and is plain URDF.
    """
    # One XPath query in libxml2 (document order) instead of a walk in Python: the first
    # element in xacro's namespace or named xacro:..., or the first attribute holding ${
    # or $(.
    found = _XACRO_USE(root, ns=XACRO_NAMESPACE)
    if not isinstance(found, list) or not found:
        return None
    first = found[0]
    if isinstance(first, etree._Element):
        tag = str(first.tag)
        return first, f"<xacro:{tag[tag.index('}') + 1 :]}>"
    if not isinstance(first, etree._ElementUnicodeResult):
        return None
    element = first.getparent()  # an attribute value (a "smart string") knows its element
    if element is None:
        return None
    text = str(first)
    start = min(i for i in (text.find("${"), text.find("$(")) if i >= 0)
    end = text.find("}" if text[start + 1] == "{" else ")", start)
    shown = text[start : end + 1] if 0 <= end - start < 60 else text[start : start + 60]
    return element, (
        f"attribute '{first.attrname!s}' of <{element.tag}> still holds the substitution "
        f"'{shown}': the file was meant to be processed by xacro (or roslaunch) first"
    )


_XACRO_USE = etree.XPath(
    "(//*[namespace-uri() = $ns or starts-with(name(), 'xacro:')]"
    " | //@*[contains(., '${') or contains(., '$(')])[1]",
    smart_strings=True,
)
"""The first element of xacro's (in its namespace, or named ``xacro:...`` as xacro finds
them: many files bind the prefix to ``http://ros.org/wiki/xacro``), or the first
attribute holding a substitution."""


def _without_lines(description: RobotDescription) -> RobotDescription:
    """The description with line numbers dropped (they point into xacro's output)."""
    return RobotDescription(
        name=description.name,
        format=description.format,
        root_link=description.root_link,
        links=tuple(link._replace(line=None) for link in description.links),
        joints=tuple(
            joint._replace(line=None, limit_line=None, axis_line=None)
            for joint in description.joints
        ),
        findings=tuple(d._replace(line=None) for d in description.findings),
    )


def inspect_source(
    source: SourceFile,
    root_joint: str | None = None,
    *,
    xacro: XacroOptions | None = None,
    file: str | os.PathLike[str] | None = None,
    force_xacro: bool = False,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
    srdf: str | os.PathLike[str] | bool | None = None,
    group: str | None = None,
    hold: str | None = None,
    default_root: str | None = None,
) -> Report:
    """Analyse a robot file already read into memory.

    Args:
        source: The file's bytes and name.
        root_joint: None, ``"floating"`` or ``"planar"``: a joint to add above the
            root link (URDFs of mobile and legged robots have none).
        xacro: Package folders, arguments and limits for xacro files (defaults: none).
        file: The file on disk holding ``source``'s bytes, or None (standard input):
            xacro includes and MJCF includes resolve from its folder.
        force_xacro: Expand the file as xacro whatever its name (``--xacro``).
        allow_dirs: Folders, besides the file's own, that MJCF includes may be read from.
        srdf: A URDF's SRDF file (MoveIt's groups, states, virtual and passive joints);
            True looks for its robot's in its project (beside ``file``, in ``srdf/``,
            ``config/``, a ``*_moveit_config`` package; none found: an
            ``srdf-not-found`` note says where it looked); None or False reads none.
            Its virtual joint stands in for ``root_joint``.
        group: Report this SRDF group's own C-space, the other joints held.
        hold: The stored pose (a group state's name, or ``group/name``) the other joints
            are held at with ``group`` (default: neutral).
        default_root: The root joint to add when neither ``root_joint`` nor the SRDF
            says (``erd:`` robots).

    Returns:
        The report.

    Raises:
        RobotFileError: The file is not a valid robot description (a subclass says why).
        InvalidRootJointError: ``root_joint`` is not a supported name.
    """
    built = _build(
        source,
        root_joint,
        xacro=xacro,
        file=file,
        force_xacro=force_xacro,
        allow_dirs=allow_dirs,
        srdf=srdf,
        default_root=default_root,
    )
    from cspace._model.analysis import analyse

    reading = built.reading
    report = analyse(
        source,
        built.format,
        reading.description,
        built.model,
        built.root_joint,
        reading.addresses,
        reading.poses,
        placed=getattr(reading.recipe, "unplaced", None) is None,
    )
    if built.srdf is not None:
        from cspace._model.semantics import with_srdf

        report = with_srdf(report, built.srdf, built.virtual)
    elif built.srdf_note is not None:
        report = report._replace(diagnostics=(*report.diagnostics, built.srdf_note))
    if group is not None:
        from cspace._model.semantics import group_report

        report = group_report(report, group, hold)
    elif hold is not None:
        raise InvalidElementError(source.path, "--hold applies with --group", code="srdf-hold")
    if built.srdf is not None:
        from cspace._model.semantics import listed

        report = listed(report)
    return report


class _Built(NamedTuple):
    """A robot file read and its Pinocchio model built, before the analysis."""

    format: str
    reading: Reading
    model: PinModel
    root_joint: str | None = None
    srdf: Srdf | None = None
    virtual: str | None = None
    srdf_note: Diagnostic | None = None  # --srdf auto found none: where it looked


def _build(
    source: SourceFile,
    root_joint: str | None,
    *,
    xacro: XacroOptions | None,
    file: str | os.PathLike[str] | None,
    force_xacro: bool,
    allow_dirs: Sequence[str | os.PathLike[str]],
    srdf: str | os.PathLike[str] | bool | None = False,
    default_root: str | None = None,
) -> _Built:
    """Read ``source`` in its format and build its Pinocchio model (see `inspect_source`)."""
    on_disk = None if file is None else path_text(file)
    budget = ReadBudget(source.path)
    from cspace._formats.shared.by_content import format_of

    told = format_of(source.path, source.data)
    if told is not None:  # not XML (OpenUSD): its reader, with limits of its own
        if srdf is not None and not isinstance(srdf, bool):  # auto: none for USD, as MJCF
            raise NotARobotError(
                source.path,
                f"an SRDF goes with a URDF, and this robot is {told.name.upper()}",
                code="srdf-format",
            )
        return _build_by_content(told, source, on_disk, root_joint or default_root, allow_dirs)
    budget.charge(source)
    root = parse_xml(source)
    from cspace._formats.shared.roots import named_srdf
    from cspace._formats.srdf.kind import refuse_srdf

    named = named_srdf(source.path)  # decides only a <robot> of no robot's or SRDF's elements
    refuse_srdf(source.path, root, named=named)  # an SRDF is read with its URDF, never alone
    fmt = detect_format(source.path, root, force_xacro=force_xacro, data=source.data)
    path = source.path
    if fmt == "mjcf":
        from cspace._formats.mjcf.reader import start_compile

        compiling = start_compile(path, source, root, on_disk, budget=budget, allow_dirs=allow_dirs)
        from cspace._model.adapter import build  # Pinocchio loads while MuJoCo compiles

        reading = compiling.finish()
    elif fmt in ("urdf", "xacro"):
        from cspace._formats.urdf.reader import read_urdf

        urdf = source
        if fmt == "xacro":
            from cspace._formats.xacro.expand import XacroOptions, expand_xacro

            urdf = expand_xacro(source, xacro or XacroOptions(), on_disk)
            budget.charge(urdf)  # xacro's output counts as one more file of the robot
            path = f"{source.path} (expanded by xacro)"
            written, root = root, parse_xml(urdf._replace(path=path))
            refuse_srdf(source.path, root, named=named, written=written)
        reading = read_urdf(path, root, urdf.text)
        if fmt == "xacro":
            reading = reading._replace(description=_without_lines(reading.description))
    else:
        from cspace._formats.sdf.reader import read_sdf

        reading = read_sdf(path, root)
    semantics, virtual = None, None
    srdf_file, srdf_folders, srdf_note = _srdf_file(
        srdf, fmt, on_disk, path, allow_dirs, reading.description
    )
    if srdf_file is not None:
        from cspace._formats.srdf.reader import parse_srdf
        from cspace._model.semantics import root_of

        read = read_source(srdf_file, budget=budget, allow_dirs=srdf_folders, what="SRDF file")
        semantics = parse_srdf(read)
        root_joint, virtual = root_of(
            semantics, reading.description.root_link, root_joint, default_root
        )
    else:
        root_joint = root_joint or default_root
    check_root_joint(path, reading.description, root_joint)
    from cspace._model.adapter import build

    model = build(path, reading, root_joint)
    return _Built(fmt, reading, model, root_joint, semantics, virtual, srdf_note)


def _build_by_content(
    told: Any,
    source: SourceFile,
    on_disk: str | None,
    root_joint: str | None,
    allow_dirs: Sequence[str | os.PathLike[str]],
) -> _Built:
    """Read a file of a format told by its bytes (`by_content`) and build its model."""
    from cspace._formats.shared.by_content import read

    if on_disk is None:
        raise NotARobotError(
            source.path, f"a {told.name.upper()} file is read from a file, not standard input"
        )
    folder = os.path.dirname(os.path.abspath(on_disk))
    reading = read(told, source.path, on_disk, [folder, *map(path_text, allow_dirs)])
    check_root_joint(source.path, reading.description, root_joint)
    from cspace._model.adapter import build

    return _Built(told.name, reading, build(source.path, reading, root_joint), root_joint)


def _srdf_file(
    srdf: str | os.PathLike[str] | bool | None,
    fmt: str,
    on_disk: str | None,
    path: str,
    allow_dirs: Sequence[str | os.PathLike[str]],
    description: RobotDescription,
) -> tuple[str | None, Sequence[str | os.PathLike[str]], Diagnostic | None]:
    """The SRDF to read (the one named, the one found, or None), its folders, a note.

    ``srdf=True`` (``--srdf auto``) looks in the robot's project for the SRDF of its
    robot (`cspace._model.semantics.find_srdf`); the one it finds may lead anywhere in
    the folders it may read, as MJCF includes do. When it finds none, the note
    (``srdf-not-found``) says where it looked.
    """
    if srdf is None or srdf is False or (srdf is True and fmt not in ("urdf", "xacro")):
        return None, allow_dirs, None
    if srdf is True:
        from cspace._model._srdf_find import Search, srdf_folders
        from cspace._model.semantics import not_found, search

        if on_disk is None:
            nowhere = Search(None, (), "the robot is read from standard input, in no folder")
            return None, allow_dirs, not_found(nowhere, path, description.name)
        folders = srdf_folders(on_disk, allow_dirs)
        robot = path.removeprefix(ERD_PREFIX) if path.startswith(ERD_PREFIX) else None
        parts = frozenset(
            [*(link.name for link in description.links), *(j.name for j in description.joints)]
        )
        found = search(on_disk, robot, folders, description.name or None, parts)
        note = None if found.path else not_found(found, on_disk, description.name)
        return found.path, (*allow_dirs, *folders), note
    if fmt not in ("urdf", "xacro"):
        raise NotARobotError(
            path, f"an SRDF goes with a URDF, and this robot is {fmt.upper()}", code="srdf-format"
        )
    if path_text(srdf).lower().endswith(".xacro"):  # its groups are xacro's to make
        raise NotARobotError(
            path_text(srdf),
            "an SRDF that xacro makes: --srdf reads an SRDF file (expand this one with "
            "xacro, then give what it writes)",
            code="srdf-format",
        )
    return path_text(srdf), allow_dirs, None


STACKING_KINDS = (JointKind.FLOATING, JointKind.PLANAR)
"""Joint types that already give the root a pose: a root joint on top would stack two."""


def check_root_joint(path: str, description: RobotDescription, root_joint: str | None) -> None:
    """Refuse ``root_joint`` when the file already gives its root a floating or planar joint.

    Raises:
        InvalidElementError: The root link's child joint is floating, free or planar
            (code ``root-joint-stacked``).
    """
    if root_joint is None:
        return
    for joint in description.joints:
        if joint.parent == description.root_link and joint.kind in STACKING_KINDS:
            raise InvalidElementError(
                path,
                f"joint '{joint.name}' is already a {joint.type} joint of the root; "
                f"--root-joint {root_joint} would put a second one on top of it",
                line=joint.line,
                element=joint.name,
                code="root-joint-stacked",
            )


def inspect(
    path: str | os.PathLike[str],
    root_joint: str | None = None,
    *,
    xacro: XacroOptions | None = None,
    force_xacro: bool = False,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
    srdf: str | os.PathLike[str] | bool | None = None,
    group: str | None = None,
    hold: str | None = None,
) -> Report:
    """Analyse the robot file at ``path``.

    Args:
        path: A URDF, xacro, MJCF, SDF or USD file (``str`` or ``os.PathLike``); or
            ``erd:NAME``, a robot bundled with example-robot-data (with the floating
            base its own loader gives it, unless ``root_joint`` says otherwise).
        root_joint: None, ``"floating"`` or ``"planar"``.
        xacro: Package folders, arguments and limits for xacro files.
        force_xacro: Expand the file as xacro whatever its name.
        allow_dirs: Folders, besides the file's own, that MJCF includes may be read from.
        srdf: As for `inspect_source` (True: the SRDF beside a URDF, if any).
        group: Report this SRDF group's own C-space, the other joints held.
        hold: The stored pose the other joints are held at (default: neutral).

    Returns:
        The report; ``report.to_dict()`` is the JSON document of ``cspace inspect``.

    Raises:
        RobotFileError: The file cannot be read or is not a valid robot description.
        InvalidRootJointError: ``root_joint`` is not a supported name.
        CspaceError: An unknown ``erd:`` name.
    """
    source, file, default = _open(path, allow_dirs)
    return inspect_source(
        source,
        root_joint,
        xacro=xacro,
        file=file,
        force_xacro=force_xacro,
        allow_dirs=allow_dirs,
        srdf=srdf,
        group=group,
        hold=hold,
        default_root=default,
    )


def _open(
    path: str | os.PathLike[str], allow_dirs: Sequence[str | os.PathLike[str]]
) -> tuple[SourceFile, str, str | None]:
    """Read the robot file ``path`` names (``erd:NAME`` too).

    Returns:
        Its bytes, its file, and the root joint example-robot-data's own loader adds to
        an ``erd:`` robot (None for any other file).
    """
    name = path_text(path)
    file = name
    default_root = None
    if name.startswith(ERD_PREFIX):
        found, default_root = resolve(name.removeprefix(ERD_PREFIX))
        file = str(found)
    return read_source(file, allow_dirs=allow_dirs)._replace(path=name), file, default_root


def pinocchio_model(
    path: str | os.PathLike[str],
    root_joint: str | None = None,
    *,
    xacro: XacroOptions | None = None,
    force_xacro: bool = False,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
    srdf: str | os.PathLike[str] | bool | None = None,
) -> Any:
    """The ``pinocchio.Model`` `cspace` builds for the robot file at ``path``.

    It is the model behind `inspect`'s report: the same joints, order and q/v
    layout, every joint placed and every link a ``BODY`` frame where the file puts it,
    so that its forward kinematics are the format's own tool's. URDF and xacro: built
    by Pinocchio's URDF parser. MJCF: assembled from MuJoCo's compiled model, a
    ``BODY`` frame per MuJoCo body (see `tree_model`). SDF and OpenUSD: assembled
    joint by joint from the file's poses, as Drake and OpenUSD compose them. A group's
    report (``group=``) is that of ``pinocchio.buildReducedModel`` of this model, the
    other joints locked.

    Args:
        path: As for `inspect`.
        root_joint: None, ``"floating"`` or ``"planar"``.
        xacro: Package folders, arguments and limits for xacro files.
        force_xacro: Expand the file as xacro whatever its name.
        allow_dirs: Folders, besides the file's own, that MJCF includes may be read from.
        srdf: As for `inspect`: the SRDF whose virtual joint is the root joint.

    Raises:
        RobotFileError: The file cannot be read or is not a valid robot description,
            or its joints cannot be placed (`ModelBuildError`): a model whose
            kinematics would be wrong is never returned.
    """
    source, file, default = _open(path, allow_dirs)
    built = _build(
        source,
        root_joint,
        xacro=xacro,
        file=file,
        force_xacro=force_xacro,
        allow_dirs=allow_dirs,
        srdf=srdf,
        default_root=default,
    )
    unplaced = getattr(built.reading.recipe, "unplaced", None)
    if unplaced is not None:
        raise ModelBuildError(
            source.path,
            f"cspace cannot place this robot's joints as the file does ({unplaced}): "
            "its configuration space is reported, but no Pinocchio model is returned",
            (),
        )
    return built.model.pinocchio
