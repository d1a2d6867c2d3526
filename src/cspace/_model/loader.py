"""The front door: a path (or bytes) in, a report out.

The format is told from the content, by the format table (`cspace._formats.table`): a
format that is not XML by its first bytes, an XML format by its root element and, for
xacro, which runs code, by the user asking for it (`cspace._formats.detect`). The
format's reader reads the file; ``erd:NAME`` names a robot bundled with
example-robot-data.

Every file is read once: the model is built from the bytes read (and, for MJCF, the
files the pre-scan read), never from the path again.

Pinocchio (through `adapter`) is imported on first use, so that ``import
cspace`` and the command-line tool's start-up stay fast for commands that do not load a
robot.
"""

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from cspace._formats.shared.description import RobotDescription
from cspace._formats.shared.erd import ERD_PREFIX, resolve
from cspace._formats.shared.reading import Reading, ReadRequest
from cspace._formats.shared.reading import read as read_with
from cspace._formats.shared.xmlio import (
    ReadBudget,
    SourceFile,
    parse_xml,
    path_text,
    read_source,
)
from cspace._joint_kind import JointKind
from cspace._model.options import LoadOptions
from cspace._record import NamedTuple
from cspace._reports.report import Report
from cspace.errors import (
    InvalidElementError,
    ModelBuildError,
)

if TYPE_CHECKING:
    from cspace._findings import Diagnostic
    from cspace._formats.srdf.reader import Srdf
    from cspace._formats.xacro.expand import XacroOptions
    from cspace._model.adapter import PinModel
    from cspace._model.closure import LoopModel


def inspect_source(
    source: SourceFile,
    root_joint: str | None = None,
    *,
    xacro: "XacroOptions | None" = None,
    file: str | os.PathLike[str] | None = None,
    force_xacro: bool = False,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
    srdf: str | os.PathLike[str] | bool | None = None,
    group: str | None = None,
    hold: str | None = None,
    limits: str | os.PathLike[str] | bool | None = None,
    default_root: str | None = None,
) -> Report:
    """Analyse a robot file already read into memory.

    Args:
        source: The file's bytes and name.
        root_joint: As for `inspect`.
        xacro: As for `inspect`.
        file: The file on disk holding ``source``'s bytes, or None (standard input):
            xacro includes and MJCF includes resolve from its folder, and
            ``srdf=True`` looks for the SRDF beside it.
        force_xacro: As for `inspect`.
        allow_dirs: As for `inspect`.
        srdf: As for `inspect`.
        group: As for `inspect`.
        hold: As for `inspect`.
        limits: As for `inspect`.
        default_root: The root joint to add when neither ``root_joint`` nor the SRDF
            says (``erd:`` robots).

    Returns:
        The report.

    Raises:
        RobotFileError: The file is not a valid robot description (a subclass says why).
        InvalidRootJointError: ``root_joint`` is not a supported name.
    """
    options = LoadOptions(root_joint, xacro, force_xacro, allow_dirs, srdf, group, hold, limits)
    return report_of(source, options, file=file, default_root=default_root)


def report_of(
    source: SourceFile,
    options: LoadOptions,
    *,
    file: str | os.PathLike[str] | None = None,
    default_root: str | None = None,
) -> Report:
    """`inspect_source` with the loading options as one record (see `LoadOptions`)."""
    return _report_and_loops(source, options, file=file, default_root=default_root)[0]


def _report_and_loops(
    source: SourceFile,
    options: LoadOptions,
    *,
    file: str | os.PathLike[str] | None = None,
    default_root: str | None = None,
) -> "tuple[Report, LoopModel | None]":
    """`report_of`, and what its mechanism's constraints were searched with.

    The second is None for a tree, a group's report, or a mechanism not searched.
    """
    built = _build(source, options, file=file, default_root=default_root)
    return _analyse_built(source, options, built, file)


def _analyse_built(
    source: SourceFile, options: LoadOptions, built: "_Built", file: str | os.PathLike[str] | None
) -> "tuple[Report, LoopModel | None]":
    """The report of a robot file read and built (`_report_and_loops`)."""
    from cspace._model.analysis import analyse

    reading = built.reading
    applied, limits_note = None, None
    if options.limits is not None and options.limits is not False:
        from cspace._model._beside import limits_of

        srdf_path = None if built.srdf is None else built.srdf.path
        applied, limits_note = limits_of(
            options, built.format, built.reading.description, srdf_path, file, source.path
        )
    report = analyse(
        source,
        built.format,
        reading.description if applied is None else applied.description,
        built.model,
        built.root_joint,
        reading.addresses,
        reading.poses,
        placed=getattr(reading.recipe, "unplaced", None) is None,
    )
    if reading.actuators:
        report = report._replace(actuators=reading.actuators)
    if applied is not None:
        from cspace._model._limits_file import relocated

        diagnostics = relocated(report.diagnostics, applied)
        report = report._replace(diagnostics=diagnostics, limits_file=applied.summary)
    elif limits_note is not None:
        report = report._replace(diagnostics=(*report.diagnostics, limits_note))
    if built.srdf is not None:
        from cspace._model.semantics import with_srdf

        report = with_srdf(report, built.srdf, built.virtual)
    elif built.srdf_note is not None:
        report = report._replace(diagnostics=(*report.diagnostics, built.srdf_note))
    loops = None
    if reading.description.cuts:
        from cspace._model.closure_analysis import with_closure

        report, loops = with_closure(report, reading.description, built.model)
    if options.group is not None:  # the loops are the whole robot's, its model too
        loops = None
        from cspace._model.semantics import group_report

        report = group_report(report, options.group, options.hold)
    elif options.hold is not None:
        raise InvalidElementError(source.path, "--hold applies with --group", code="srdf-hold")
    if built.srdf is not None:
        from cspace._model.semantics import listed

        report = listed(report)
    return report, loops


class _Built(NamedTuple):
    """A robot file read and its Pinocchio model built, before the analysis."""

    format: str
    reading: Reading
    model: "PinModel"
    root_joint: str | None = None
    srdf: "Srdf | None" = None
    virtual: str | None = None
    srdf_note: "Diagnostic | None" = None  # --srdf auto found none: where it looked


def _build(
    source: SourceFile,
    options: LoadOptions,
    *,
    file: str | os.PathLike[str] | None,
    default_root: str | None = None,
) -> _Built:
    """Read ``source`` in its format and build its Pinocchio model (see `inspect_source`)."""
    root_joint, srdf, allow_dirs = options.root_joint, options.srdf, options.allow_dirs
    on_disk = None if file is None else path_text(file)
    budget = ReadBudget(source.path)
    from cspace._formats.table import told_by_bytes

    root, named = None, False
    row = told_by_bytes(source.path, source.data)  # not XML (OpenUSD): limits of its own
    if row is None:
        budget.charge(source)
        root = parse_xml(source)
        from cspace._formats.detect import detect
        from cspace._formats.shared.roots import named_srdf
        from cspace._formats.srdf.kind import refuse_srdf

        named = named_srdf(source.path)  # decides only a <robot> of no robot's or SRDF's elements
        refuse_srdf(source.path, root, named=named)  # an SRDF is read with its URDF, never alone
        row = detect(source.path, root, force_xacro=options.force_xacro, data=source.data)
    if root is None and srdf is not None:  # told by its bytes: refused before its child reads
        from cspace._model._beside import refuse_srdf_for

        refuse_srdf_for(srdf, row, source.path)

    def meanwhile() -> None:
        from cspace._model import adapter  # noqa: F401  Pinocchio loads while a child reads

    request = ReadRequest(
        source.path,
        source,
        root,
        on_disk,
        budget,
        allow_dirs,
        options=options.xacro,
        named_srdf=named,
        meanwhile=meanwhile,
    )
    reading = read_with(row, request)
    path = reading.path or source.path
    semantics, virtual = None, None
    srdf_file, srdf_folders, srdf_note = None, allow_dirs, None
    if srdf is not None:
        from cspace._model._beside import srdf_to_read

        srdf_file, srdf_folders, srdf_note = srdf_to_read(
            srdf, row, on_disk, path, allow_dirs, reading.description
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
    return _Built(row.name, reading, model, root_joint, semantics, virtual, srdf_note)


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
    xacro: "XacroOptions | None" = None,
    force_xacro: bool = False,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
    srdf: str | os.PathLike[str] | bool | None = None,
    group: str | None = None,
    hold: str | None = None,
    limits: str | os.PathLike[str] | bool | None = None,
) -> Report:
    """Analyse the robot file at ``path``.

    Args:
        path: A robot file of any format cspace reads (``str`` or ``os.PathLike``); or
            ``erd:NAME``, a robot bundled with example-robot-data (with the floating
            base its own loader gives it, unless ``root_joint`` says otherwise).
        root_joint: None, ``"floating"`` or ``"planar"``: a joint to add above the
            root link (URDFs of mobile and legged robots have none).
        xacro: Package folders, arguments and limits for xacro files (defaults: none).
        force_xacro: Expand the file as xacro whatever its name (``--xacro``).
        allow_dirs: Folders, besides the file's own, that MJCF includes may be read from.
        srdf: A URDF's SRDF file (MoveIt's groups, states, virtual and passive joints);
            True looks for its robot's in its project (beside the file, in ``srdf/``,
            ``config/``, a ``*_moveit_config`` package; none found: an
            ``srdf-not-found`` note says where it looked); None or False reads none.
            Its virtual joint stands in for ``root_joint``.
        group: Report this SRDF group's own C-space, the other joints held.
        hold: The stored pose (a group state's name, or ``group/name``) the other joints
            are held at with ``group`` (default: neutral).
        limits: MoveIt's joint_limits.yaml (a URDF's): its ``min_position`` and
            ``max_position`` replace the URDF's position limits as MoveIt 2 applies
            them (the C-space is the one MoveIt plans in), its velocity, acceleration
            and jerk limits are shown; the report's ``limits_file`` says where each
            limit came from. True looks for ``config/joint_limits.yaml`` where
            ``srdf=True`` looks for the SRDF (beside the SRDF read first; none found:
            a ``limits-file-not-found`` note says where it looked); None or False
            reads none.

    Returns:
        The report; ``report.to_dict()`` is the JSON document of ``cspace inspect``.

    Raises:
        RobotFileError: The file cannot be read or is not a valid robot description.
        InvalidRootJointError: ``root_joint`` is not a supported name.
        CspaceError: An unknown ``erd:`` name.
    """
    options = LoadOptions(root_joint, xacro, force_xacro, allow_dirs, srdf, group, hold, limits)
    return inspect_with(path, options)


def inspect_with(path: str | os.PathLike[str], options: LoadOptions) -> Report:
    """`inspect` with the loading options as one record (see `LoadOptions`)."""
    source, file, default = _open(path, options.allow_dirs)
    return report_of(source, options, file=file, default_root=default)


def inspect_with_loops(
    path: str | os.PathLike[str], options: LoadOptions
) -> "tuple[Report, LoopModel | None]":
    """`inspect_with`, and what the mechanism's loop constraints were searched with.

    The second is None for a tree, for a group's report (``options.group``: its model is
    reduced, the loops are on the whole robot's), and when the report's closure has no
    samples because none was sought (no usable cut, a reader that does not place every
    joint, constraints larger than cspace projects with).
    """
    source, file, default = _open(path, options.allow_dirs)
    return _report_and_loops(source, options, file=file, default_root=default)


def built_and_report(
    path: str | os.PathLike[str], options: LoadOptions
) -> "tuple[_Built, Report, str]":
    """The robot file at ``path`` read and built, its report, and the file on disk."""
    source, file, default = _open(path, options.allow_dirs)
    built = _build(source, options, file=file, default_root=default)
    return built, _analyse_built(source, options, built, file)[0], file


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
    xacro: "XacroOptions | None" = None,
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
        root_joint: As for `inspect`.
        xacro: As for `inspect`.
        force_xacro: As for `inspect`.
        allow_dirs: As for `inspect`.
        srdf: As for `inspect`: the SRDF whose virtual joint is the root joint.

    Raises:
        RobotFileError: The file cannot be read or is not a valid robot description,
            or its joints cannot be placed (`ModelBuildError`): a model whose
            kinematics would be wrong is never returned.
    """
    options = LoadOptions(root_joint, xacro, force_xacro, allow_dirs, srdf)
    source, file, default = _open(path, options.allow_dirs)
    built = _build(source, options, file=file, default_root=default)
    unplaced = getattr(built.reading.recipe, "unplaced", None)
    if unplaced is not None:
        raise ModelBuildError(
            source.path,
            f"cspace cannot place this robot's joints as the file does ({unplaced}): "
            "its configuration space is reported, but no Pinocchio model is returned",
            (),
        )
    return built.model.pinocchio
