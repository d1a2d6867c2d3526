"""MJCF collision geometry and MuJoCo's contact filters, held to MuJoCo's own ``mj_collision``.

`mjcf_collision` reads the geoms MuJoCo compiles (in cspace's confined child) and
decides, body pair by body pair, whether MuJoCo checks them. The oracle is MuJoCo
itself, loading the same files here with their meshes:

- on real robots (dm_control's humanoid, walker and Jaco arm, Gymnasium Robotics' Shadow
  hand and the Franka Panda of its kitchen), seeded samples of cspace's sampler, mapped to
  MuJoCo's qpos by cspace's own conventions (``to_mujoco``), are run through
  ``mj_kinematics`` + ``mj_collision`` with every margin and gap 0; the body pairs MuJoCo
  finds in penetration (``dist < 0``) are compared, sample by sample, with the pairs
  cspace's engine (`SelfCollision` over the pairs the filters let through) finds. Then
  with MuJoCo's filters off (every geom's bits 0 and an explicit ``<pair>`` for every
  two shapes' geoms, which MuJoCo checks whatever its other rules say) against the
  engine over all pairs. A disagreement is *grazing* when MuJoCo's distance or coal's
  signed distance of the pair is within `GRAZE` (1e-6 m) of 0; every other one is
  counted and must be none where coal's own signed distance disagrees with MuJoCo
  (the shapes or the filters would be wrong);
- each filter rule on small files written here, whose geoms all overlap at ``qpos0``:
  the pairs MuJoCo finds in contact are exactly the pairs cspace says it checks, and
  each pair's reason and line are the rule's;
- on the same robots, with every margin 10 m (MuJoCo then makes contacts for every geom
  pair it checks), the body pairs in contact are exactly the pairs cspace says it checks;
- each mesh's convex hull against MuJoCo's own (``mesh_graph``), with ``refpos``,
  ``refquat``, ``scale`` and ``maxhullvert``, from STL and OBJ files and inline
  vertices; the geoms cspace does not check are problems at their lines, the bounds one
  line each.
"""

from __future__ import annotations

import shutil
import struct
from pathlib import Path
from typing import Any

import mujoco
import numpy as np
import pinocchio as pin
import pytest

import cspace
from cspace._formats.mjcf._geom_facts import MAX_GEOMS
from cspace._model._collision_mjcf import (
    BITS,
    CONTACT_OFF,
    EXCLUDE,
    PAIR,
    PARENT,
    SAME_WELD,
    STATIC,
    MjcfCollision,
    PairFilter,
    mjcf_collision,
)
from cspace._model._collision_pairs import SelfCollision, link_pair, link_pairs, samples
from cspace._model.loader import _build, _open
from cspace._model.options import LoadOptions

SITE = Path(mujoco.__file__).resolve().parent.parent
GRAZE = 1e-6
"""Metres within which a pair grazes: MuJoCo and coal may then disagree."""

SAMPLES = 500
SEED = 42


def built_of(path: Path | str) -> Any:
    """The loader's ``_Built`` of a robot file."""
    source, file, default = _open(str(path), ())
    return _build(source, LoadOptions(), file=file, default_root=default)


def collision_of(path: Path | str) -> tuple[Any, MjcfCollision]:
    built = built_of(path)
    return built, mjcf_collision(built)


@pytest.fixture(scope="module")
def panda(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Gymnasium Robotics' Franka Panda alone: its kitchen's robot files, in a folder."""
    folder = tmp_path_factory.mktemp("panda")
    kitchen = SITE / "gymnasium_robotics/envs/assets/kitchen_franka/franka_assets"
    shutil.copytree(kitchen, folder / "franka_assets")
    path = folder / "panda.xml"
    path.write_text(
        '<mujoco model="panda">\n  <include file="franka_assets/assets.xml"/>\n'
        '  <worldbody>\n    <include file="franka_assets/chain.xml"/>\n  </worldbody>\n'
        "</mujoco>\n"
    )
    return path


ROBOTS = {
    "humanoid": "dm_control/suite/humanoid.xml",
    "walker": "dm_control/suite/walker.xml",
    "jaco": "dm_control/third_party/kinova/jaco_arm.xml",
    "shadow_hand": "gymnasium_robotics/envs/assets/hand/reach.xml",
    "panda": None,
}


@pytest.fixture(params=list(ROBOTS))
def robot(request: pytest.FixtureRequest, panda: Path) -> Path:
    relative = ROBOTS[request.param]
    return panda if relative is None else SITE / relative


def _unfiltered(path: Path, found: MjcfCollision) -> Any:
    """MuJoCo's model of ``path`` with its filters off for the shapes' geoms.

    Every geom's bits are 0 and every two shapes' geoms of different bodies an explicit
    ``<pair>`` (checked whatever the other rules say); excludes and flags gone.
    """
    spec = mujoco.MjSpec.from_file(str(path))
    geoms = spec.geoms
    for k, geom in enumerate(geoms):
        if not geom.name:
            geom.name = f"cspace_oracle_{k}"
    spec.compile()
    named = {geom.id: geom.name for geom in geoms}
    for geom in geoms:
        geom.contype = geom.conaffinity = 0
    for element in [*spec.excludes, *spec.pairs]:
        spec.delete(element)
    spec.option.disableflags = 0
    bodies = {g: found.shapes.links[i] for i, g in enumerate(found.geoms)}
    for i, one in enumerate(found.geoms):
        for other in found.geoms[i + 1 :]:
            if bodies[one] != bodies[other]:
                spec.add_pair(geomname1=named[one], geomname2=named[other])
    return spec.compile()


def _mujoco_pairs(model: Any, data: Any, qpos: Any, names: Any, wanted: set[int]) -> dict:
    """The body pairs MuJoCo finds in penetration at ``qpos``, with their deepest dist."""
    data.qpos[:] = qpos
    mujoco.mj_kinematics(model, data)
    mujoco.mj_collision(model, data)
    found: dict[tuple[str, str], float] = {}
    for k in range(data.ncon):
        contact = data.contact[k]
        g1, g2 = int(contact.geom1), int(contact.geom2)
        if contact.dist >= 0 or g1 not in wanted or g2 not in wanted:
            continue
        pair = link_pair(names[model.geom_bodyid[g1]], names[model.geom_bodyid[g2]])
        found[pair] = min(found.get(pair, 0.0), float(contact.dist))
    return found


def _coal_distance(model: Any, found: MjcfCollision, q: Any, pair: tuple[str, str]) -> float:
    """coal's signed distance of two bodies' shapes at ``q`` (the least of their pairs)."""
    geometry = found.shapes.geometry.copy()
    links = found.shapes.links
    for i, a in enumerate(links):
        for j, b in enumerate(links):
            if i < j and {a, b} == set(pair):
                geometry.addCollisionPair(pin.CollisionPair(i, j))
    data = pin.GeometryData(geometry)
    pin.computeDistances(model, model.createData(), geometry, data, q)
    return min(r.min_distance for r in data.distanceResults)


def _compare(path: Path, found: MjcfCollision, built: Any, filtered: bool) -> dict[str, int]:
    """Sample by sample: MuJoCo's colliding pairs against the engine's (see the module)."""
    model = built.model.pinocchio
    names = built.reading.geometry.bodies
    conventions = cspace.load(str(path)).conventions()
    qs = samples(model, SEED, 0, SAMPLES)
    qpos = conventions.to_mujoco(conventions.from_pinocchio(qs))
    if filtered:
        oracle = mujoco.MjModel.from_xml_path(str(path))
        pairs = [p for p, f in found.filters.items() if f.checked]
    else:
        oracle = _unfiltered(path, found)
        pairs = link_pairs(found.shapes.with_geometry)
    assert list(oracle.geom_bodyid) == [g.body for g in built.reading.geometry.geoms]
    oracle.geom_margin[:] = 0
    oracle.geom_gap[:] = 0
    oracle.pair_margin[:] = 0
    oracle.pair_gap[:] = 0
    data = mujoco.MjData(oracle)
    engine = SelfCollision(model, found.shapes, pairs)
    wanted = set(found.geoms)
    counts = {"hits": 0, "exact": 0, "agree": 0, "grazing": 0, "engine": 0, "shapes": 0}
    wrong = []
    for k in range(SAMPLES):
        mine = {engine.pairs[i] for i in engine.colliding(qs[k])}
        theirs = _mujoco_pairs(oracle, data, qpos[k], names, wanted)
        counts["hits"] += len(theirs)
        counts["exact"] += not mine ^ set(theirs)
        grazing = 0
        for pair in mine ^ set(theirs):
            depth = theirs.get(pair, 0.0)
            distance = _coal_distance(model, found, qs[k], pair)
            if abs(depth) < GRAZE or abs(distance) < GRAZE:
                grazing += 1
            elif (distance < 0) == (pair in theirs):  # coal's geometry agrees: its query missed
                counts["engine"] += 1
            else:
                counts["shapes"] += 1
                wrong.append((k, pair, pair in mine, depth, distance))
        counts["grazing"] += grazing
        counts["agree"] += grazing == len(mine ^ set(theirs))
    assert not wrong, wrong[:5]
    return counts


@pytest.mark.parametrize("filtered", [True, False], ids=["filters", "no-filters"])
def test_engine_agrees_with_mujoco_sample_by_sample(robot: Path, filtered: bool) -> None:
    """The engine's pairs in collision are MuJoCo's, but grazing ones, on every sample.

    Measured (500 samples, seed 42; pairs in penetration MuJoCo finds with filters / without;
    disagreements): humanoid 268 / 4,848, none; walker 0 / 3,101, 413 grazing without
    filters (its two legs side by side touch at exactly 0 m); Jaco 28 / 3,028, none;
    Shadow hand 782 / 11,628, none (seed 7 gave 6 of 200 samples without filters where
    coal's query without contacts, Pinocchio's default, misses a 1 mm box inside a capsule
    while coal's signed distance agrees with MuJoCo: counted as ``engine``); Panda
    127 / 3,127, none.
    """
    built, found = collision_of(robot)
    assert found.problems == ()
    counts = _compare(robot, found, built, filtered)
    print(robot.name, "filters" if filtered else "no filters", counts)
    assert counts["agree"] >= 0.95 * SAMPLES, counts
    assert counts["engine"] == 0, counts  # coal's query from the default guess, with contact


def test_the_pairs_let_through_are_the_pairs_mujoco_checks(robot: Path) -> None:
    """With every margin 10 m, MuJoCo makes contacts for every geom pair it checks.

    So the body pairs in contact at ``qpos0`` are the pairs its filters let through,
    whatever their shapes: exactly the pairs `mjcf_collision` says are checked.
    """
    built, found = collision_of(robot)
    spec = mujoco.MjSpec.from_file(str(robot))
    for element in [*spec.geoms, *spec.pairs]:  # compiled in: the broad phase's bounds too
        element.margin = 10.0
    oracle = spec.compile()
    data = mujoco.MjData(oracle)
    data.qpos[:] = oracle.qpos0
    mujoco.mj_kinematics(oracle, data)
    mujoco.mj_collision(oracle, data)
    names, wanted = built.reading.geometry.bodies, set(found.geoms)
    theirs = {
        link_pair(names[oracle.geom_bodyid[c.geom1]], names[oracle.geom_bodyid[c.geom2]])
        for c in (data.contact[k] for k in range(data.ncon))
        if c.geom1 in wanted and c.geom2 in wanted
    }
    assert {pair for pair, f in found.filters.items() if f.checked} == theirs
    assert set(found.filters) == set(link_pairs(found.shapes.with_geometry))


# --- each rule on small files: every geom overlaps every other at qpos0 ---------------


def line_of(text: str, marker: str) -> int:
    """The 1-based line of the first line holding ``marker``."""
    return next(k for k, line in enumerate(text.splitlines(), 1) if marker in line)


def _write(folder: Path, text: str, name: str = "rules.xml") -> Path:
    path = folder / name
    path.write_text(text)
    return path


def _mujoco_checks(path: Path, found: MjcfCollision, names: Any) -> set[tuple[str, str]]:
    """The body pairs MuJoCo finds in contact at ``qpos0``, among the shapes' geoms."""
    model = mujoco.MjModel.from_xml_path(str(path))
    model.geom_margin[:] = 0
    data = mujoco.MjData(model)
    return set(_mujoco_pairs(model, data, model.qpos0, names, set(found.geoms)))


def _held_to_mujoco(path: Path) -> tuple[Any, MjcfCollision]:
    """The file's filters, after checking their pairs are the ones MuJoCo checks."""
    built, found = collision_of(path)
    names = built.reading.geometry.bodies
    checked = {pair for pair, f in found.filters.items() if f.checked}
    assert checked == _mujoco_checks(path, found, names)
    return built, found


WELDS = """<mujoco>
  <worldbody>
    <body name="base"><geom size=".1"/>
      <body name="a"><joint/><geom size=".1"/>
        <body name="b"><joint/><geom size=".1"/> <!-- b -->
          <body name="b_welded"><geom size=".1"/></body> <!-- welded -->
          <body name="c"><joint/><geom size=".1"/></body> <!-- c -->
        </body>
      </body>
    </body>
    <body name="static2"><geom size=".1"/></body>
    <body name="mocap" mocap="true"><geom size=".1"/></body> <!-- mocap -->
  </worldbody>
</mujoco>
"""


def test_welds_static_bodies_and_the_parent_filter_as_mujoco(tmp_path: Path) -> None:
    """One weld body, static bodies, parent and child: MuJoCo's broad phase rules."""
    _, found = _held_to_mujoco(_write(tmp_path, WELDS))
    f = found.filters
    assert f["a", "base"] == PairFilter(True, BITS, line_of(WELDS, '"a"'))  # parent weld 0
    assert f["a", "b"] == PairFilter(False, PARENT, line_of(WELDS, "<!-- b -->"))
    assert f["b", "b_welded"] == PairFilter(False, SAME_WELD, line_of(WELDS, "welded -->"))
    assert f["a", "b_welded"] == PairFilter(False, PARENT, line_of(WELDS, "<!-- b -->"))
    assert f["b_welded", "c"] == PairFilter(False, PARENT, line_of(WELDS, "<!-- c -->"))
    assert f["a", "c"].checked  # grandparent
    assert f["base", "static2"].reason == SAME_WELD  # both welded to the world
    assert f["base", "mocap"] == PairFilter(False, STATIC, line_of(WELDS, '"base"'))
    assert f["a", "mocap"].checked
    off = WELDS.replace("<worldbody>", '<option><flag filterparent="disable"/></option><worldbody>')
    _, found = _held_to_mujoco(_write(tmp_path, off, "off.xml"))
    assert found.filters["a", "b"].checked and found.filters["b_welded", "c"].checked
    assert found.filters["b", "b_welded"].reason == SAME_WELD


BITS_FILE = """<mujoco>
  <worldbody>
    <body name="p"><freejoint/><geom name="pg" size=".1"/>
      <geom name="visual" size=".1" contype="0" conaffinity="0"/></body>
    <body name="q"><freejoint/><geom name="qg" size=".1" contype="2" conaffinity="2"/></body>
    <body name="r"><freejoint/><geom name="rg" size=".1" contype="1" conaffinity="0"/></body>
    <body name="s"><freejoint/><geom size=".1"/><geom size=".1" contype="2" conaffinity="2"/>
    </body>
    <body name="t"><freejoint/><geom name="tg" size=".1" contype="0" conaffinity="0"/></body>
    <body name="u"><freejoint/><geom name="ug" size=".1"/></body>
    <body name="v"><freejoint/><geom name="vg" size=".1"/></body>
    <body name="w"><freejoint/><geom name="wg" size=".1"/></body>
  </worldbody>
  <contact>
    <pair geom1="tg" geom2="pg"/> <!-- tp -->
    <exclude body1="w" body2="p"/> <!-- wp -->
    <exclude body1="u" body2="v"/>
    <pair geom1="ug" geom2="vg"/> <!-- uv -->
  </contact>
</mujoco>
"""


def test_bits_excludes_and_explicit_pairs_as_mujoco(tmp_path: Path) -> None:
    """contype/conaffinity body and geom by geom, <exclude>, and <pair> over them all."""
    built, found = _held_to_mujoco(_write(tmp_path, BITS_FILE))
    f = found.filters
    visual = built.reading.geometry.geoms.index(
        next(g for g in built.reading.geometry.geoms if g.name == "visual")
    )
    assert visual not in found.geoms  # contype and conaffinity 0, in no <pair>: visual
    assert f["p", "q"] == PairFilter(False, BITS, line_of(BITS_FILE, '"pg"'))
    assert f["p", "r"] == PairFilter(True, BITS, line_of(BITS_FILE, '"pg"'))
    assert f["q", "r"] == PairFilter(False, BITS, line_of(BITS_FILE, '"qg"'))
    assert f["p", "s"].checked and f["q", "s"].checked
    p, s = found.shapes.links.index("p"), found.shapes.links.index("s")
    assert found.partial["p", "s"] == ((p, s),)  # s's second geom meets none of p's
    assert f["p", "t"] == PairFilter(True, PAIR, line_of(BITS_FILE, "<!-- tp -->"))
    assert f["q", "t"] == PairFilter(False, BITS, line_of(BITS_FILE, '"tg"'))  # t meets nothing
    assert f["p", "w"] == PairFilter(False, EXCLUDE, line_of(BITS_FILE, "<!-- wp -->"))
    assert f["u", "v"] == PairFilter(True, PAIR, line_of(BITS_FILE, "<!-- uv -->"))


@pytest.mark.parametrize("flag", ["contact", "constraint"])
def test_contacts_disabled_check_nothing(tmp_path: Path, flag: str) -> None:
    text = BITS_FILE.replace(
        "<worldbody>", f'<option>\n    <flag {flag}="disable"/>\n  </option>\n  <worldbody>'
    )
    _, found = _held_to_mujoco(_write(tmp_path, text))
    assert set(found.filters.values()) == {
        PairFilter(False, CONTACT_OFF, line_of(text, f'{flag}="disable"'))
    }


PARTS = """<mujocoinclude>
  <body name="i1"><freejoint/><geom name="i1g" size=".1"/></body>
  <body name="i2"><freejoint/><geom name="i2g" size=".1" contype="2" conaffinity="2"/></body>
  <body name="i3"><freejoint/><geom size=".1" contype="4" conaffinity="4"/></body>
</mujocoinclude>
"""

MAIN = """<mujoco>
  <!-- a comment
       over three lines -->
  <worldbody>
    <include file="parts/parts.xml"/>
    <body name="m"
          pos="0 0 0"><freejoint/><geom name="mg" size=".1" contype="9" conaffinity="9"/></body>
    <body name="n"><freejoint/><geom size=".1" contype="2" conaffinity="2"/></body>
  </worldbody>
  <contact><exclude name="x" body1="i1" body2="m"/></contact>
</mujoco>
"""


def test_lines_of_an_included_file_and_after_a_comment(tmp_path: Path) -> None:
    """A named element of an included file is found in it; an unnamed one has no line.

    The main file's lines are its own although its comments do not reach MuJoCo.
    """
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "parts.xml").write_text(PARTS)
    _, found = _held_to_mujoco(_write(tmp_path, MAIN))
    f = found.filters
    assert f["i1", "i2"] == PairFilter(False, BITS, line_of(PARTS, '"i1g"'), "parts/parts.xml")
    assert f["i2", "i3"] == PairFilter(False, BITS, line_of(PARTS, '"i2g"'), "parts/parts.xml")
    assert f["i3", "m"] == PairFilter(False, BITS, None)  # i3's geom has no name
    assert f["i1", "m"] == PairFilter(False, EXCLUDE, line_of(MAIN, "<exclude"))
    assert f["i2", "m"] == PairFilter(False, BITS, line_of(PARTS, '"i2g"'), "parts/parts.xml")
    assert f["m", "n"] == PairFilter(False, BITS, line_of(MAIN, '"mg"'))
    assert f["i2", "n"].checked


# --- meshes: MuJoCo's own convex hulls ---------------------------------------------------


def _cloud(seed: int, count: int) -> Any:
    rng = np.random.default_rng(seed)
    return rng.normal(size=(count, 3)) * [0.1, 0.05, 0.02] + [0.02, -0.01, 0.03]


def _write_stl(path: Path, points: Any) -> None:
    triangles = points[: len(points) // 3 * 3].reshape(-1, 3, 3)
    data = bytearray(b"\0" * 80 + struct.pack("<I", len(triangles)))
    for triangle in triangles:
        data += struct.pack("<12fH", 0, 0, 0, *triangle.ravel(), 0)
    path.write_bytes(bytes(data))


def _write_obj(path: Path, points: Any) -> None:
    lines = [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in points]
    lines += [f"f {k + 1} {k + 2} {k + 3}" for k in range(0, len(points) - 2, 3)]
    path.write_text("\n".join(lines) + "\n")


def _hull_file(folder: Path) -> Path:
    _write_stl(folder / "cloud.stl", _cloud(1, 300))
    _write_obj(folder / "cloud.obj", _cloud(2, 240))
    inline = " ".join(f"{x:.9g}" for x in _cloud(3, 60).ravel())
    return _write(
        folder,
        f"""<mujoco>
  <compiler angle="degree"/>
  <asset>
    <mesh name="stl" file="cloud.stl" scale="1.5 0.5 2" refpos="0.01 -0.02 0.03"
          refquat="0.9 0.1 0.3 -0.2"/>
    <mesh name="obj" file="cloud.obj" maxhullvert="12"/>
    <mesh name="inline" vertex="{inline}" refquat="0 0 0 1"/>
  </asset>
  <worldbody>
    <body name="a" pos="0.3 0.1 0.2" euler="10 20 30"><joint axis="0 1 0"/>
      <geom type="mesh" mesh="stl" pos=".1 .2 .3" euler="5 -10 40"/>
      <geom type="mesh" mesh="obj" pos="-.1 0 .05" quat="0.5 0.5 -0.5 0.5"/>
      <geom type="mesh" mesh="inline" pos="0 0 -.2"/>
    </body>
  </worldbody>
</mujoco>
""",
        "hulls.xml",
    )


def test_each_mesh_is_mujocos_own_convex_hull(tmp_path: Path) -> None:
    """STL, OBJ and inline vertices; refpos, refquat, scale and maxhullvert, as MuJoCo."""
    path = _hull_file(tmp_path)
    built, found = collision_of(path)
    assert found.problems == () and len(found.geoms) == 3
    oracle = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(oracle)
    mujoco.mj_kinematics(oracle, data)
    model = built.model.pinocchio
    pin_data = model.createData()
    pin.forwardKinematics(model, pin_data, pin.neutral(model))
    for k, g in enumerate(found.geoms):
        mesh = int(oracle.geom_dataid[g])
        at, count = (
            int(oracle.mesh_graphadr[mesh]),
            int(oracle.mesh_graph[oracle.mesh_graphadr[mesh]]),
        )
        ids = oracle.mesh_graph[at + 2 + count : at + 2 + 2 * count]
        vertices = oracle.mesh_vert[oracle.mesh_vertadr[mesh] + ids].astype(float)
        theirs = vertices @ data.geom_xmat[g].reshape(3, 3).T + data.geom_xpos[g]
        item = found.shapes.geometry.geometryObjects[k]
        placement = pin_data.oMi[item.parentJoint] * item.placement
        points = np.asarray(item.geometry.points())
        mine = points @ placement.rotation.T + placement.translation
        assert len(mine) == len(theirs) == (12 if k == 1 else len(theirs))
        gaps = np.linalg.norm(mine[:, None] - theirs[None], axis=2)
        assert gaps.min(axis=1).max() < 1e-6 and gaps.min(axis=0).max() < 1e-6


PROBLEMS = """<mujoco>
  <asset>
    <mesh name="flat" vertex="0 0 0 1 0 0 0 1 0 1 1 0"/>
    <mesh name="gone" file="missing.stl"/>
    <mesh name="ok" vertex="0 0 0 1 0 0 0 1 0 0 0 1"/>
    <hfield name="h" nrow="2" ncol="2" size="1 1 1 0.1"/>
  </asset>
  <worldbody>
    <geom type="plane" size="1 1 1"/>
    <body name="floor"><geom type="plane" size="1 1 1"/></body> <!-- plane -->
    <body name="a"><joint/>
      <geom type="hfield" hfield="h"/> <!-- hfield -->
      <geom type="mesh" mesh="flat"/> <!-- flat -->
      <geom type="mesh" mesh="gone"/> <!-- gone -->
      <geom type="box" mesh="ok"/> <!-- fitted -->
      <geom size=".1"/>
    </body>
  </worldbody>
</mujoco>
"""


def test_geoms_not_checked_are_problems_at_their_lines(tmp_path: Path) -> None:
    """Planes, height fields, a mesh MuJoCo makes no hull of, one not found, a fitted box."""
    _, found = collision_of(_write(tmp_path, PROBLEMS))
    lines = {problem.line: problem for problem in found.problems}
    assert len(found.problems) == 5  # the world's plane is the environment: left out
    assert "plane" in lines[line_of(PROBLEMS, "<!-- plane")].problem
    assert "hfield" in lines[line_of(PROBLEMS, "<!-- hfield")].problem
    assert "coplanar" in lines[line_of(PROBLEMS, "<!-- flat")].problem
    assert "no such file" in lines[line_of(PROBLEMS, "<!-- gone")].problem
    assert "fits to mesh 'ok'" in lines[line_of(PROBLEMS, "<!-- fitted")].problem
    assert all(problem.body in ("floor", "a") for problem in found.problems)
    assert all("\n" not in problem.problem for problem in found.problems)
    assert found.shapes.with_geometry == ("a",)


@pytest.mark.bounded
def test_more_geoms_than_read_is_one_line(tmp_path: Path) -> None:
    text = (
        '<mujoco><worldbody><body><joint/><replicate count="'
        f'{MAX_GEOMS + 1}" offset=".01 0 0"><geom size=".1"/></replicate></body>'
        "</worldbody></mujoco>"
    )
    built = built_of(_write(tmp_path, text))
    with pytest.raises(ValueError, match=f"{MAX_GEOMS + 1:,} geoms, more than"):
        mjcf_collision(built)


@pytest.mark.bounded
def test_more_inline_vertices_than_read_is_a_problem(tmp_path: Path) -> None:
    numbers = " ".join(["0 0 0 1 0 0 0 1 0 0 0 1"] * 25_001)  # 300,012 numbers
    text = (
        f'<mujoco><asset><mesh name="big" vertex="{numbers}"/></asset><worldbody>'
        '<body><joint/><geom type="mesh" mesh="big"/></body></worldbody></mujoco>'
    )
    _, found = collision_of(_write(tmp_path, text))
    assert [p.problem for p in found.problems] == [
        "mesh 'big': more numbers written inline (vertex) than cspace reads"
    ]


def test_a_robot_of_another_format_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "arm.urdf"
    path.write_text('<robot name="arm"><link name="base"/></robot>')
    with pytest.raises(ValueError, match="MJCF robot only"):
        mjcf_collision(built_of(path))
