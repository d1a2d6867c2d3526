"""SDF as SDFormat means it, with Drake's SDFormat reader as the oracle.

Every SDF file that pybullet's data, Drake's wheel and example-robot-data ship, the
repository's, and small files for each rule (free links float, a static model is
welded, worlds of several models, nested models, frames and ``__model__`` as a joint's
parent or child) is read by
Drake (``MultibodyPlant`` after ``Finalize``, which adds a floating joint to every free
body) and by cspace: the normal forms agree, and so do the names of the moving joints,
or both refuse the file for the same reason.

Drake refuses some of pybullet's files for elements SDFormat does not define (a link's
``<contact>``, a collision's ``concave``) or for two collisions of one name: cspace reads
no geometry and no such element, so the oracle is given the file without them (removed
or renamed as Drake's own message names them) and cspace the file as shipped.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pybullet_data
import pydrake
import pytest
from lxml import etree
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import JointIndex

import cspace
from cspace._formats.shared.erd import robots_dir

from conftest import REPO, measured, run_cli

DRAKE_MODELS = Path(pydrake.__file__).parent / "share" / "drake"
SHIPPED = sorted(
    [
        *Path(pybullet_data.getDataPath()).rglob("*.sdf"),
        *DRAKE_MODELS.rglob("*.sdf"),
        *(REPO / "robots").rglob("*.sdf"),
        *(REPO / "tests").rglob("*.sdf"),
        *robots_dir().rglob("*.sdf"),  # example-robot-data's: cassie, closed chains
    ]
)

SAME_REASON = {
    "reserved-name": "is reserved",
    "duplicate-name": "Non-unique name",
    "moving-joint-in-static-model": "Only fixed joints are permitted in static models",
    "moving-world-joint": "Only fixed joints are permitted in world joints",
    "unsupported-joint-type": "not supported",  # a gearbox
    "two-parents": "form one or more loops",  # a closed chain cspace does not cut
    "cycle": "form one or more loops",
}
"""cspace's code for a refusal -> the words of Drake's message for the same refusal."""

_UNDEFINED_ELEMENT = re.compile(r"XML Element\[(\w+)\], child of element\[(\w+)\]")
_UNDEFINED_ATTRIBUTE = re.compile(r"XML Attribute\[(\w+)\] in element\[(\w+)\]")
_GEOMETRY_NAME = re.compile(r"(collision|visual) with name\[[^\]]*\] already exists")


def drake_plant(path: Path, scratch: Path) -> tuple[MultibodyPlant, bytes] | str:
    """Drake's finalized plant of the file and the text it read, or Drake's refusal.

    What SDFormat does not define, and geometry names given twice (cspace reads no
    geometry), are taken out and the file read again.
    """
    text = path.read_bytes()
    for _ in range(10):
        plant = MultibodyPlant(0.0)
        copy = scratch / path.name
        copy.write_bytes(text)
        try:
            Parser(plant).AddModels(str(copy))
            plant.Finalize()
        except RuntimeError as error:
            message = str(error)
            root = etree.fromstring(text)
            element = _UNDEFINED_ELEMENT.search(message)
            attribute = _UNDEFINED_ATTRIBUTE.search(message)
            geometry = _GEOMETRY_NAME.search(message)
            if geometry:  # cspace reads no geometry: a name given twice is nothing to it
                for k, found in enumerate(root.iter(geometry.group(1))):
                    found.set("name", f"{found.get('name')}_{k}")
            elif element:  # not SDFormat: nothing to the C-space; read without it
                for found in root.iter(element.group(2)):
                    for child in found.findall(element.group(1)):
                        found.remove(child)
            elif attribute:
                for found in root.iter(attribute.group(2)):
                    found.attrib.pop(attribute.group(1), None)
            else:
                return message
            text = etree.tostring(root)
            continue
        return plant, text
    raise AssertionError(f"{path}: Drake kept refusing")


def _drake(path: Path, scratch: Path) -> Read | str:
    """Drake's (R, T, RP^3) counts, moving joints' names and q and v names, or its refusal."""
    read = drake_plant(path, scratch)
    if isinstance(read, str):
        return read
    plant, text = read
    return _counts(plant, etree.fromstring(text))


def _universal_limits(document: etree._Element, name: str) -> tuple[list[float], list[float]]:
    """A universal joint's limits as the file gives them: Drake does not read them."""
    (joint,) = [j for j in document.iter("joint") if j.get("name") == name]
    lower, upper = [], []
    for tag in ("axis", "axis2"):
        low, high = joint.findtext(f"{tag}/limit/lower"), joint.findtext(f"{tag}/limit/upper")
        lower.append(float(low) if low is not None and abs(float(low)) < 1e16 else -math.inf)
        upper.append(float(high) if high is not None and abs(float(high)) < 1e16 else math.inf)
    return lower, upper


Read = tuple[tuple[int, int, int], set[str], tuple[tuple[str, ...], tuple[str, ...]] | None]
"""A reading of a file: its (R, T, RP^3) counts, its moving joints' names (each within
its model), and its Drake q and v names (None when cspace does not know Drake's order)."""


def _counts(plant: MultibodyPlant, document: etree._Element) -> Read:
    r = t = rp3 = 0
    moving = set()
    for i in range(plant.num_joints()):
        joint = plant.get_joint(JointIndex(i))
        kind = joint.type_name()
        lower, upper = joint.position_lower_limits(), joint.position_upper_limits()
        if kind == "universal":
            lower, upper = _universal_limits(document, joint.name())
        # one finite bound is enough for an interval: the angle cannot wrap past it (R)
        bounded = [math.isfinite(a) or math.isfinite(b) for a, b in zip(lower, upper, strict=True)]
        if kind in ("revolute", "universal"):
            r, t = r + sum(bounded), t + len(bounded) - sum(bounded)
        elif kind in ("prismatic", "screw"):
            r += 1
        elif kind == "quaternion_floating":
            r, rp3 = r + 3, rp3 + 1
        elif kind == "ball_rpy":
            rp3 += 1
        elif kind == "planar":
            r, t = r + 2, t + 1
        else:
            assert kind == "weld", kind
            continue
        moving.add(joint.name())
    names = (tuple(plant.GetPositionNames(False)), tuple(plant.GetVelocityNames(False)))
    return (r, t, rp3), moving, names


def _ours(path: Path) -> Read | cspace.RobotFileError:
    try:
        report = cspace.inspect(path)
    except cspace.RobotFileError as error:
        return error
    form = report.manifold
    # Drake names a joint within its model: cspace's scoped name ends with it (and a
    # floating joint, named after its link, ends with the link's name)
    names = {j.name.rsplit("::", 1)[-1] for j in report.joints if j.nv}
    drake = None
    unassembled = any(d.code == "closure-not-assembled" for d in report.diagnostics)
    if form.dimension and not unassembled:  # the Drake convention, where cspace knows it
        conventions = cspace.ConfigurationSpace.from_report(report).conventions()
        try:
            drake = (conventions.names("drake"), conventions.names("drake", velocity=True))
        except cspace.JointMatchError as error:
            assert "two joints on one line" in str(error)  # these cases' one-line files
    return (form.r, form.t, form.rp3), names, drake


def without_cuts(path: Path, scratch: Path) -> Path | None:
    """A copy of an SDF file without the joints cspace cuts to open its loops (None: none).

    Drake's ball constraints stay: Drake reads them.

    Drake refuses a link with two parents; the tree cspace keeps is the file less those
    joints, which Drake reads.
    """
    closure = cspace.inspect(path).closure
    if closure is None:
        return None
    cut = {c.name for c in closure.cuts if c.kind != "drake:ball_constraint"}
    if not cut:  # Drake's own ball constraints only: Drake reads the file as it is
        return None
    document = etree.parse(str(path))
    for joint in list(document.iter("joint")):
        if joint.get("name") in cut:
            joint.getparent().remove(joint)
    copy = scratch / f"tree_{path.name}"
    copy.write_bytes(etree.tostring(document))
    return copy


def _check(path: Path, scratch: Path) -> None:
    drake, ours = _drake(path, scratch), _ours(path)
    tree = None if isinstance(ours, cspace.RobotFileError) else without_cuts(path, scratch)
    if tree is not None:  # Drake refuses the loops: it reads the tree cspace keeps
        assert isinstance(drake, str) and SAME_REASON["two-parents"] in drake, drake
        (scratch / "tree").mkdir()
        drake = _drake(tree, scratch / "tree")
    if isinstance(ours, cspace.RobotFileError):
        assert isinstance(drake, str), (ours, drake)
        assert SAME_REASON[ours.code] in drake, (ours, drake)
    else:
        assert not isinstance(drake, str), (ours, drake)
        assert ours[:2] == drake[:2]
        if ours[2] is not None:  # Drake's q and v, named and ordered as Drake does
            assert ours[2] == drake[2]


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.name)
def test_every_shipped_sdf_file_reads_as_drake_reads_it(path: Path, tmp_path: Path) -> None:
    _check(path, tmp_path)


def test_the_shipped_files_are_found() -> None:
    assert len(SHIPPED) >= 25
    assert any(p.name == "planar_gripper.sdf" for p in SHIPPED)


LIMITED = "<axis><xyz>0 0 1</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis>"
CASES = {
    "free_model": '<model name="m"><link name="a"/><link name="b"/>'
    f'<joint name="j" type="revolute"><parent>a</parent><child>b</child>{LIMITED}</joint>'
    "</model>",
    "bolted_model": '<model name="m"><link name="a"/><link name="b"/>'
    '<joint name="w" type="fixed"><parent>world</parent><child>a</child></joint>'
    f'<joint name="j" type="revolute"><parent>a</parent><child>b</child>{LIMITED}</joint>'
    "</model>",
    "static_model": '<model name="m"><static>true</static><link name="a"/><link name="b"/></model>',
    "static_moving_joint": '<model name="m"><static>1</static><link name="a"/><link name="b"/>'
    f'<joint name="j" type="revolute"><parent>a</parent><child>b</child>{LIMITED}</joint>'
    "</model>",
    "world_of_three": '<world name="w"><model name="a"><link name="l"/></model>'
    '<model name="b"><static>1</static><link name="l"/></model>'
    '<model name="c"><link name="l"/><link name="m"/>'
    f'<joint name="j" type="revolute"><parent>l</parent><child>m</child>{LIMITED}</joint>'
    "</model></world>",
    "two_models_one_name": '<world name="w"><model name="a"><link name="l"/></model>'
    '<model name="a"><link name="k"/></model></world>',
    "nested": '<model name="outer"><link name="base"/>'
    '<model name="inner"><link name="l1"/><link name="l2"/>'
    '<joint name="ij" type="prismatic"><parent>l1</parent><child>l2</child>'
    f"{LIMITED}</joint></model>"
    '<frame name="f" attached_to="base"/>'
    '<joint name="oj" type="revolute"><parent>f</parent><child>inner::l1</child>'
    "<axis><xyz>0 0 1</xyz></axis></joint>"
    '<joint name="w" type="fixed"><parent>world</parent><child>base</child></joint></model>',
    "nested_free": '<model name="outer"><link name="base"/>'
    '<model name="inner"><link name="l1"/></model></model>',
    "frame_as_child": '<model name="m"><link name="a"/><link name="b"/>'
    '<frame name="fb" attached_to="b"/>'
    '<joint name="j" type="revolute"><parent>world</parent><child>a</child>'
    "<axis><xyz>0 0 1</xyz></axis></joint>"
    '<joint name="k" type="ball"><parent>a</parent><child>fb</child></joint></model>',
    "model_frame_as_parent": '<model name="m" canonical_link="b"><link name="a"/>'
    '<link name="b"/><joint name="j" type="prismatic"><parent>__model__</parent>'
    f"<child>a</child>{LIMITED}</joint></model>",
    "link_named_world": '<model name="m"><link name="world"/><link name="a"/></model>',
    "world_joint_scoped": '<world name="w"><model name="m"><link name="base"/>'
    '<link name="arm"/><joint name="j" type="revolute"><parent>base</parent>'
    f"<child>arm</child>{LIMITED}</joint></model>"
    '<joint name="bolt" type="fixed"><parent>world</parent><child>m::base</child></joint>'
    "</world>",
    "world_frame_beside_a_link": '<world name="w"><frame name="base"/>'
    '<model name="m"><link name="base"/></model></world>',
    "moving_world_joint": '<world name="w"><model name="m"><link name="base"/></model>'
    '<joint name="spin" type="revolute"><parent>world</parent><child>m::base</child>'
    f"{LIMITED}</joint></world>",
    "nested_not_static_in_static": '<model name="outer"><static>true</static>'
    '<link name="base"/><model name="inner"><static>false</static><link name="x"/>'
    '<link name="y"/><joint name="j" type="revolute"><parent>x</parent><child>y</child>'
    f"{LIMITED}</joint></model></model>",
    "frame_on_a_joint": '<model name="m"><link name="a"/><link name="b"/><link name="c"/>'
    '<joint name="w" type="fixed"><parent>world</parent><child>a</child></joint>'
    f'<joint name="j" type="revolute"><parent>a</parent><child>b</child>{LIMITED}</joint>'
    '<frame name="fj" attached_to="j"/>'
    f'<joint name="k" type="prismatic"><parent>fj</parent><child>c</child>{LIMITED}</joint>'
    "</model>",
    "inner_model_frame": '<model name="outer"><link name="base"/>'
    '<model name="inner"><link name="l1"/></model>'
    '<joint name="w" type="fixed"><parent>world</parent><child>base</child></joint>'
    f'<joint name="j" type="revolute"><parent>base</parent><child>inner::__model__</child>'
    f"{LIMITED}</joint></model>",
    "joint_named_as_link": '<model name="m"><link name="a"/><link name="b"/>'
    f'<joint name="b" type="revolute"><parent>a</parent><child>b</child>{LIMITED}</joint>'
    "</model>",
}


FRAMES_AND_NESTING = (
    "nested",
    "nested_free",
    "frame_as_child",
    "model_frame_as_parent",
    "world_joint_scoped",
    "world_frame_beside_a_link",
    "moving_world_joint",
    "nested_not_static_in_static",
    "frame_on_a_joint",
    "inner_model_frame",
)
"""Cases of SDFormat 1.8 and later (frames, canonical links, nested models)."""

VERSIONED = [
    (case, version)
    for case in sorted(CASES)
    for version in ("1.4", "1.6", "1.7", "1.9", "1.11")
    if case not in FRAMES_AND_NESTING or version in ("1.9", "1.11")
]


@pytest.mark.parametrize(("case", "version"), VERSIONED)
def test_each_sdformat_rule_as_drake_reads_it(case: str, version: str, tmp_path: Path) -> None:
    body = CASES[case]
    path = tmp_path / "robot.sdf"
    path.write_text(f'<sdf version="{version}">{body}</sdf>')
    (tmp_path / "drake").mkdir()
    _check(path, tmp_path / "drake")


def test_a_free_link_floats_with_a_finding_that_says_how_to_bolt_it_down() -> None:
    report = cspace.inspect(REPO / "tests" / "sdf" / "free_arm.sdf")
    assert report.manifold.notation == "R^4 × RP^3"
    floats = [d for d in report.diagnostics if d.code == "sdf-link-floats"]
    assert len(floats) == 1 and floats[0].severity is cspace.Severity.INFO
    assert "<static>true</static>" in floats[0].message and "from 'world'" in floats[0].message
    assert report.joints[0].name == "base" and report.joints[0].kind is cspace.JointKind.FLOATING


@pytest.mark.bounded
def test_a_long_chain_of_frames_is_followed_once(tmp_path: Path) -> None:
    # 100,000 frames, each attached to the one before, and 4,000 joints whose children
    # are links but whose parents are the last frame: followed each time, 4*10^8 steps
    frames = 100_000
    parts = ['<sdf version="1.9"><model name="m"><link name="base"/>']
    parts.append('<frame name="f0" attached_to="base"/>')
    parts += [f'<frame name="f{k}" attached_to="f{k - 1}"/>' for k in range(1, frames)]
    for k in range(4_000):
        parts.append(
            f'<link name="l{k}"/><joint name="j{k}" type="prismatic"><parent>f{frames - 1}'
            f"</parent><child>l{k}</child>{LIMITED}</joint>"
        )
    parts.append('<joint name="w" type="fixed"><parent>world</parent><child>base</child>')
    parts.append("</joint></model></sdf>")
    path = tmp_path / "frames.sdf"
    path.write_text("\n".join(parts))
    result = measured("inspect", "--format", "json", str(path), cwd=tmp_path)
    assert result.run.code == 0, result.run.stderr
    assert result.cpu_seconds < 10 and result.peak_mib < 600
    assert json.loads(result.run.stdout)["dimension"] == 4_000


def test_frames_attached_in_a_circle_are_refused_in_one_line(tmp_path: Path) -> None:
    path = tmp_path / "circle.sdf"
    path.write_text(
        '<sdf version="1.9"><model name="m"><link name="a"/><link name="b"/>'
        '<frame name="f" attached_to="g"/><frame name="g" attached_to="f"/>'
        f'<joint name="j" type="prismatic"><parent>f</parent><child>b</child>{LIMITED}</joint>'
        "</model></sdf>"
    )
    run = run_cli("inspect", str(path))
    assert run.code == 2 and run.stderr.count("\n") == 1
    assert "attached to itself" in run.stderr and "[cycle]" in run.stderr


@pytest.mark.bounded
def test_a_huge_model_name_is_refused_before_its_scoped_names_are_built(tmp_path: Path) -> None:
    # a 1 MB model name over 3,000 links would make 3 GB of scoped names first
    links = "".join(f'<link name="l{k}"/>' for k in range(3_000))
    path = tmp_path / "huge.sdf"
    path.write_text(
        f'<sdf version="1.9"><world name="w"><model name="{"m" * 1_000_000}">{links}</model>'
        '<model name="other"><link name="x"/></model></world></sdf>'
    )
    result = measured("inspect", str(path), cwd=tmp_path)
    assert result.run.code == 2 and "[name-too-long]" in result.run.stderr
    assert result.cpu_seconds < 10 and result.peak_mib < 600
    assert len(result.run.stderr) < 1_000


def test_drakes_order_and_names_of_a_world_of_nested_models(tmp_path: Path) -> None:
    """Drake makes a model's nested models before its own links, and names joints and
    bodies without their scope: a world of four models, one holding two nested ones,
    free links, a jointed tree and a welded one (tests/sdf/world_of_models.sdf)."""
    path = REPO / "tests" / "sdf" / "world_of_models.sdf"
    drake, ours = _drake(path, tmp_path), _ours(path)
    assert not isinstance(drake, str) and not isinstance(ours, cspace.RobotFileError)
    assert ours[2] is not None and ours[2] == drake[2]
    assert ours[2][0][:2] == ("h_q", "l_qw")  # the welded tree, then floated trees
    assert ours[2][0].index("l1_qw") < ours[2][0].index("base_qw")  # nested model first
