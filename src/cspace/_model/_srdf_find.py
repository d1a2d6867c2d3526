"""``--srdf auto``: the SRDF of a URDF's robot, where its project lays it out.

Where (`_places`), nearest first, each only inside the folders cspace may read for the
robot (`srdf_folders`) and in no version-control folder, links followed only inside
them (`cspace._reach`: a place or a file that leads outside is never opened, listed or
named):

1. the URDF's folder;
2. ``../srdf`` (example-robot-data: ``robots/`` or ``urdf/`` next to ``srdf/``);
3. ``srdf/`` and ``config/`` in the URDF's folder, then ``../config`` (a ROS package's
   ``urdf/`` next to its ``config/``);
4. the MoveIt configuration packages beside the robot's package (the nearest folder at
   or above the URDF's that holds a ``package.xml``, else the URDF folder's parent):
   each ``*_moveit_config`` folder there, its ``config/``, its ``srdf/`` and itself;
   first the one named after the robot (``panda_moveit_config`` for robot ``panda``),
   then the one named after the package (``panda_description``), then the others by name.

What: each place's ``NAME.srdf`` (``NAME`` the URDF file's name less ``.urdf``,
``.urdf.xacro``, ``.xacro``, ``.xml``; an ``erd:`` robot's name too), then every other
``*.srdf`` file of the places (and ``*.xml`` in a folder named ``srdf``), each read up to
`MAX_LOOK_BYTES` for its ``<robot name>`` and the links and joints it names; a file is a
candidate only when its content is an SRDF's (`srdf.kind`: a ``.srdf`` file that holds
a link is a URDF). Which (`_choose`), the first of:

- an SRDF that names the URDF's robot (``<robot name>``), wherever it is among the
  places: a ``NAME.srdf``, nearest first; then the one whose file name is the longest
  beginning of the URDF's, up to a ``_``, ``-`` or ``.`` (``talos.srdf`` for
  ``talos_reduced.urdf``, ``ur5.srdf`` for ``ur5_robot.urdf``), then the nearest; two
  alike in one place: none (the note names both: give one with ``--srdf FILE``);
- when none names the robot, an SRDF every link and joint of which the robot has (in
  groups, states, passive joints, collision pairs, end effectors; a virtual joint, and
  ``root_joint``, the root joint Pinocchio adds, are no joints of the URDF's): a
  ``NAME.srdf``, nearest first (example-robot-data's ``bolt.srdf`` names ``finger_edu``);
  then one whose file name so begins the URDF's, the longest first (``icub.srdf`` for
  ``icub_reduced.urdf``, whose robot is ``iCub``). The report then says that the SRDF
  names another robot (``srdf-other-robot``); a ``NAME.srdf`` not taken for a name the
  robot lacks is said in the note (example-robot-data's ``z1.srdf`` chains from a link
  ``base``).

Bounded: `MAX_LISTED` names read of a folder's listing, `MAX_PACKAGES` MoveIt packages,
`MAX_LOOKED` files looked at, each up to `MAX_LOOK_BYTES`. When none is chosen, `Search`
says where it looked (and why none: several alike, a bound met, a ``.srdf`` file that
could not be read).
"""

import os
from collections.abc import Sequence

from cspace._formats.shared.roots import file_stem
from cspace._reach import Folders
from cspace._record import NamedTuple

MAX_LISTED = 1_000
"""Most names read of one folder's listing (the first ones the file system gives)."""

MAX_PACKAGES = 8
"""Most ``*_moveit_config`` packages looked into."""

MAX_LOOKED = 32
"""Most files looked at as SRDF candidates, in all."""

MAX_LOOK_BYTES = 1 << 20
"""Most bytes read of a candidate (example-robot-data's largest SRDF, PR2's, is 120 kB);
a larger one is no candidate (the note says so of a ``.srdf`` file)."""

_PLACES = (".", "../srdf", "srdf", "config", "../config")
_SEPARATORS = ("_", "-", ".")
"""What may follow an SRDF's file name where it begins the URDF's (``talos_reduced``)."""
_ADDED_ROOT = "root_joint"
"""The root joint Pinocchio and cspace add (`adapter.ROOT_JOINT_NAME`), which Pinocchio's
SRDF states and groups may name (example-robot-data's ``icub.srdf``, ``go2.srdf``)."""
_MOVEIT = "_moveit_config"
_NAMING = {
    "disable_collisions": ("link1", "link2"),
    "enable_collisions": ("link1", "link2"),
    "disable_default_collisions": ("link",),
    "end_effector": ("parent_link",),
    "link_sphere_approximation": ("link",),
    "joint_property": ("joint_name",),
}
"""The SRDF elements `parse_srdf` skips, and their attributes that name a link or joint."""


class Search(NamedTuple):
    """What ``--srdf auto`` found for one robot.

    Attributes:
        path: The SRDF, named from the URDF's folder as the URDF is named, or None.
        looked: The folders looked in, so named (those that exist, inside).
        problem: Why none was chosen, when not for want of one (several alike), the
            bounds met and the ``.srdf`` files not read; or None.
    """

    path: str | None
    looked: tuple[str, ...]
    problem: str | None = None


class _Candidate(NamedTuple):
    shown: str
    place: int
    stem: str
    robot: str | None  # its <robot name>; None when unread
    parts: frozenset[str] | None  # the links and joints it names; None when unread


def srdf_folders(file: str, allow_dirs: Sequence[str | os.PathLike[str]] = ()) -> tuple[str, ...]:
    """The real folders ``--srdf auto`` may read for the robot file ``file``.

    Those of its includes (`cspace._project.include_folders`: its project, or its own
    folder, and ``allow_dirs``); and when its project is a ROS package (its folder holds
    ``package.xml``), the project that holds that package's folder, when one is marked
    (a version-control root, a ROS package or metapackage): the repository of the
    robot's packages, where its MoveIt configuration package lies.

    Raises:
        FileUnreadableError: An ``allow_dirs`` folder is reached through a link out of
            its folder.
    """
    from cspace._project import PROJECT_MARKERS, include_folders, project_folder

    folders = include_folders(file, allow_dirs)
    project = project_folder(file)
    if project is None or not os.path.isfile(os.path.join(project, "package.xml")):
        return folders
    outer = project_folder(os.path.join(os.path.dirname(project), "-"))
    if outer is None or not any(os.path.lexists(os.path.join(outer, m)) for m in PROJECT_MARKERS):
        return folders
    return (*folders, outer)


def search_srdf(
    file: str,
    robot: str | None,
    folders: Sequence[str],
    name: str | None = None,
    parts: frozenset[str] = frozenset(),
) -> Search:
    """The SRDF of the robot in the URDF ``file`` (see the module).

    Args:
        file: The URDF (or xacro) file, as named.
        robot: An ``erd:`` robot's name (example-robot-data names SRDFs after it).
        folders: The real folders it may read (`srdf_folders`).
        name: The URDF's robot name (``<robot name>``), or None.
        parts: The names of the URDF's links and joints.
    """
    from cspace._paths import real_path

    folder = os.path.dirname(file)
    own = real_path(os.path.dirname(os.path.abspath(file)))
    walk = _Walk(Folders(folders), folders)
    stem = file_stem(file)
    stems = [stem] + ([robot] if robot and robot != stem else [])
    places = [
        (folder if rest == "." else os.path.join(folder, rest), real)
        for rest, real in _places(walk, own, name)
    ]
    looked = tuple(shown or "." for shown, _ in places)
    for index, (shown, real) in enumerate(places):  # NAME.srdf: no listing needed
        for each in stems:
            count = len(walk.found)
            walk.look(os.path.join(shown, f"{each}.srdf"), real, f"{each}.srdf", index)
            if len(walk.found) > count and name is not None and walk.found[-1].robot == name:
                return Search(walk.found[-1].shown, looked)
    for index, (shown, real) in enumerate(places):
        srdf_folder = os.path.basename(real) == "srdf"
        for entry in walk.listing(real):
            lower = entry.lower()
            if lower.endswith(".srdf") or (srdf_folder and lower.endswith(".xml")):
                walk.look(os.path.join(shown, entry), real, entry, index)
    chosen, problem = _choose(walk.found, stems, name, parts)
    said = "; ".join(p for p in (problem, *walk.bounds) if p)
    return Search(chosen, looked, said or None)


def _choose(
    found: list[_Candidate], stems: list[str], name: str | None, parts: frozenset[str]
) -> tuple[str | None, str | None]:
    """The SRDF chosen among the candidates (see the module), and why none, if so."""
    urdf = stems[0]

    def prefix(c: _Candidate) -> int:  # the URDF's name up to a separator: talos_reduced
        begins = urdf.startswith(c.stem) and urdf[len(c.stem) : len(c.stem) + 1] in _SEPARATORS
        return len(c.stem) if begins and c.stem else 0

    def rank(c: _Candidate) -> tuple[int, int]:
        return (-prefix(c), c.place)

    same = [c for c in found if name is not None and c.robot == name]
    named = [c for c in same if c.stem in stems]  # found nearest first
    if named:
        return named[0].shown, None
    robots = sorted(same, key=rank)
    alike = [c.shown for c in robots if rank(c) == rank(robots[0])]
    if len(alike) > 1:
        shown = ", ".join(alike)
        return None, f"several SRDF files name robot '{name}': {shown} (give one: --srdf FILE)"
    if robots:
        return robots[0].shown, None
    fits = [c for c in found if c.parts and c.parts <= parts]  # each names another robot
    by_name = [c for c in fits if c.stem in stems]
    if by_name:
        return by_name[0].shown, None
    begins = sorted((c for c in fits if prefix(c)), key=rank)
    if begins:
        return begins[0].shown, None
    return None, next((_misfit(c, parts) for c in found if c.stem in stems), None)


def _misfit(c: _Candidate, parts: frozenset[str]) -> str:
    """Why ``NAME.srdf`` naming another robot was not taken: the names the robot lacks."""
    robot = f"robot '{c.robot}'" if c.robot else "no robot"
    if c.parts is None:
        return f"{c.shown} names {robot}, and is no SRDF cspace reads"
    if not c.parts:
        return f"{c.shown} names {robot} and no link or joint to match the robot by"
    lacks = sorted(c.parts - parts)
    said = ", ".join(f"'{n}'" for n in lacks[:3]) + (", ..." if len(lacks) > 3 else "")
    return f"{c.shown} names {robot} and {said}, which the robot lacks: --srdf FILE reads it"


def _places(walk: "_Walk", own: str, name: str | None) -> list[tuple[str, str]]:
    """The places looked in, as paths from the URDF's folder and real paths (see module)."""
    rests = list(_PLACES)
    package = walk.package(own)
    parent = os.path.dirname(package)
    if walk.inside(parent):
        up = os.path.relpath(parent, own)
        own_name = os.path.basename(package).removesuffix("_description")
        preferred = [f"{name}{_MOVEIT}" if name else "", f"{own_name}{_MOVEIT}"]
        packages = sorted(
            (e for e in walk.listing(parent) if e.lower().endswith(_MOVEIT)),
            key=lambda e: (preferred.index(e) if e in preferred else 2, e),
        )
        if len(packages) > MAX_PACKAGES:
            walk.bounds.append(f"looked into {MAX_PACKAGES} of {len(packages)} MoveIt packages")
        for each in packages[:MAX_PACKAGES]:
            package_folder = os.path.join(up, each)
            rests += [os.path.join(package_folder, "config"), os.path.join(package_folder, "srdf")]
            rests.append(package_folder)
    out, seen = [], set()
    for rest in rests:
        real = walk.folder(own, rest)
        if real is not None and real not in seen:
            seen.add(real)
            out.append((rest, real))
    return out


class _Walk:
    """What the search looked at, inside the folders it may read."""

    def __init__(self, inside: Folders, folders: Sequence[str]) -> None:
        self.within, self.folders = inside, tuple(folders)
        self.found: list[_Candidate] = []
        self.seen: set[str] = set()
        self.looked = 0
        self.bounds: list[str] = []

    def inside(self, real: str) -> bool:
        from cspace._paths import in_version_control

        return self.within.holding(real) is not None and not in_version_control(real, self.folders)

    def folder(self, base: str, rest: str) -> str | None:
        """The real folder ``rest`` leads to from ``base``, inside, or None."""
        real = self.within.reach(base, rest).real
        if real is None or not self.inside(real) or not os.path.isdir(real):
            return None
        return real

    def package(self, own: str) -> str:
        """The robot's package folder, real: the nearest at or above ``own``, inside.

        The nearest that holds a ``package.xml``; with none, ``own``'s parent.
        """
        folder = own
        while self.inside(folder):
            if os.path.isfile(os.path.join(folder, "package.xml")):
                return folder
            if os.path.dirname(folder) == folder:
                break
            folder = os.path.dirname(folder)
        return os.path.dirname(own)

    def listing(self, real: str) -> list[str]:
        """The names in the real folder ``real`` (not hidden), the first `MAX_LISTED`."""
        names: list[str] = []
        try:
            with os.scandir(real) as entries:
                for entry in entries:
                    if len(names) >= MAX_LISTED:
                        self.bounds.append(f"read the first {MAX_LISTED:,} names of {real}")
                        break
                    if not entry.name.startswith("."):
                        names.append(entry.name)
        except OSError:
            return []
        return sorted(names)

    def look(self, shown: str, base: str, entry: str, place: int) -> None:
        """Look at the candidate ``entry`` of the real folder ``base`` (see `_candidate`)."""
        from cspace._paths import in_version_control

        real = self.within.reach(base, entry).real
        if real is None or real in self.seen or not os.path.isfile(real):
            return
        if self.within.holding(real) is None or in_version_control(real, self.folders):
            return
        self.seen.add(real)
        if self.looked >= MAX_LOOKED:
            if self.looked == MAX_LOOKED:
                self.bounds.append(f"looked at the first {MAX_LOOKED} SRDF files")
            self.looked += 1
            return
        self.looked += 1
        candidate = _candidate(shown, real, place)
        if isinstance(candidate, str):
            self.bounds.append(candidate)
        elif candidate is not None:
            self.found.append(candidate)


def _candidate(shown: str, real: str, place: int) -> _Candidate | str | None:
    """A candidate as read: its robot's name and the names it gives; None: no SRDF.

    Read up to `MAX_LOOK_BYTES`, and an SRDF only by its content (`srdf.kind`: a
    ``.srdf`` name decides only a ``<robot>`` of neither a robot's elements nor an
    SRDF's). A ``.srdf`` file too large or not XML is none: why, for the note.
    """
    from cspace._formats.shared.roots import named_srdf
    from cspace._formats.shared.xmlio import parse_xml, source_from_bytes
    from cspace._formats.srdf.kind import srdf_tree
    from cspace._formats.srdf.reader import parse_srdf
    from cspace.errors import CspaceError
    from cspace.files import open_input

    stem, named = file_stem(shown), named_srdf(shown)
    try:
        with open_input(real, max_bytes=None, what="SRDF file") as stream:
            data = stream.read(MAX_LOOK_BYTES + 1)
        if len(data) > MAX_LOOK_BYTES:
            return f"{shown} is larger than {MAX_LOOK_BYTES >> 20} MiB: not read" if named else None
        source = source_from_bytes(shown, data)
        root = parse_xml(source)
    except (CspaceError, OSError):
        return f"{shown} could not be read as XML" if named else None
    if not srdf_tree(root, named=named):
        return None
    try:
        srdf = parse_srdf(source)
    except CspaceError:
        return _Candidate(shown, place, stem, root.get("name"), None)
    parts = {v.child_link for v in srdf.virtual_joints} | {p.name for p in srdf.passive}
    for group in srdf.groups:
        parts.update(j.name for j in (*group.joints, *group.links))
        parts.update(n for c in group.chains for n in (c.base, c.tip))
    parts.update(v.joint for s in srdf.states for v in s.values)
    for element in root.iterchildren(*_NAMING):  # collisions, end effectors: names too
        parts.update(str(element.get(a)) for a in _NAMING[element.tag] if element.get(a))
    virtual = {v.name for v in srdf.virtual_joints} | {_ADDED_ROOT}  # no joint of the URDF's
    return _Candidate(shown, place, stem, srdf.robot, frozenset(parts - virtual))


def moveit_places(file: str, folders: Sequence[str], name: str | None) -> list[tuple[str, str]]:
    """The places ``--srdf auto`` looks in for the robot file ``file``, nearest first.

    Each as its path from the URDF's folder (as the URDF is named) and its real path,
    only inside ``folders`` (`srdf_folders`) and in no version-control folder; for
    ``--limits auto``, which looks for MoveIt's ``joint_limits.yaml`` where the SRDF
    would be.
    """
    from cspace._paths import real_path

    folder = os.path.dirname(file)
    own = real_path(os.path.dirname(os.path.abspath(file)))
    walk = _Walk(Folders(folders), folders)
    return [
        (folder if rest == "." else os.path.join(folder, rest), real)
        for rest, real in _places(walk, own, name)
    ]


def found_in(place: str, entry: str, folders: Sequence[str]) -> str | None:
    """The real file ``entry`` of the real folder ``place``, when it is one inside ``folders``.

    Links are followed only inside them; a file in a version-control folder is none.
    """
    from cspace._paths import in_version_control

    walk = _Walk(Folders(folders), folders)
    real = walk.within.reach(place, entry).real
    if real is None or not os.path.isfile(real) or not walk.inside(real):
        return None
    return real if not in_version_control(real, walk.folders) else None
