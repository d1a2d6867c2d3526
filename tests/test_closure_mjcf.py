"""Closed chains in MJCF: the mechanism's numbers against the known answers and MuJoCo's own.

The fixtures (tests/closed/) are the mechanisms of LaValle's section 4.4 with known
mobility: a planar four-bar (1, Grübler 0), a Bennett linkage (1, Grübler -2), the same
four hinges without Bennett's condition (rigid: 0), a delta robot (3) and an arm tied to
a point it cannot reach (not assembled). The oracle is MuJoCo: its own constraint
residual and Jacobian (``efc_pos`` and ``efc_J`` of the equality rows), driven onto the
constraints by Gauss-Newton steps of its own (``mj_integratePos``), from random
configurations; the mobility is nv less the rank of its Jacobian there.
"""

from __future__ import annotations

import json
from pathlib import Path

import mujoco
import numpy as np
import pytest

import cspace

from conftest import REPO, run_cli

CLOSED = REPO / "tests" / "closed"

KNOWN = {  # file: (loops, tree dimension, equations, Grübler, rank, mobility)
    "fourbar.xml": (1, 3, 3, 0, 2, 1),
    "bennett.xml": (1, 4, 6, -2, 3, 1),
    "fourr_rigid.xml": (1, 4, 6, -2, 4, 0),
    "delta.xml": (6, 21, 18, 3, 18, 3),
}


def mujoco_ranks(path: Path, starts: int = 8, seed: int = 5) -> list[int]:
    """The rank of MuJoCo's equality Jacobian at configurations MuJoCo's own steps close.

    Random starts (qpos0 moved by a uniform tangent in [-1, 1]); Gauss-Newton on the
    equality rows' ``efc_pos`` with their ``efc_J`` (dense), through ``mj_integratePos``.
    """
    model = mujoco.MjModel.from_xml_path(str(path))
    model.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    model.opt.jacobian = int(mujoco.mjtJacobian.mjJAC_DENSE)
    data = mujoco.MjData(model)
    generator = np.random.default_rng(seed)
    ranks = []
    for _ in range(starts):
        data.qpos[:] = model.qpos0
        mujoco.mj_integratePos(model, data.qpos, generator.uniform(-1, 1, model.nv), 1.0)
        for _ in range(200):
            mujoco.mj_forward(model, data)
            rows = data.efc_type[: data.nefc] == int(mujoco.mjtConstraint.mjCNSTR_EQUALITY)
            residual = data.efc_pos[: data.nefc][rows]
            jacobian = data.efc_J[: data.nefc * model.nv].reshape(data.nefc, model.nv)[rows]
            if np.max(np.abs(residual)) < 1e-11:
                values = np.linalg.svd(jacobian, compute_uv=False)
                ranks.append(int(np.sum(values > 1e-8 * max(values[0], 1.0))))
                break
            step = -np.linalg.lstsq(jacobian, residual, rcond=None)[0]
            mujoco.mj_integratePos(model, data.qpos, step, 1.0)
    return ranks


@pytest.mark.parametrize("name", sorted(KNOWN))
def test_mobility_is_the_known_answer_and_mujocos(name: str) -> None:
    loops, dimension, rows, grubler, rank, mobility = KNOWN[name]
    report = cspace.inspect(CLOSED / name)
    closure = report.closure
    assert closure is not None and report.dimension == dimension
    assert (closure.loops, closure.constraint_rows, closure.grubler) == (loops, rows, grubler)
    assert closure.assembled is True and closure.samples > 0.8 * closure.attempts
    assert closure.rank is not None and closure.rank[1] == rank
    assert closure.mobility == mobility
    assert closure.max_residual is not None and closure.max_residual <= 1e-9
    found = mujoco_ranks(CLOSED / name)
    assert len(found) >= 4, "MuJoCo's own steps close the loops"
    assert max(found) == rank  # MuJoCo's Jacobian: the same generic rank
    codes = {d.code for d in report.diagnostics}
    assert ("closure-grubler-differs" in codes) == (rank < rows)
    assert ("closure-rigid" in codes) == (mobility == 0)


def test_an_arm_tied_to_a_point_it_cannot_reach_is_not_assembled() -> None:
    run = run_cli("inspect", "tests/closed/unreachable.xml", "--format", "json")
    assert run.code == 1  # an error-level finding
    document = json.loads(run.stdout)
    closure = document["closure"]
    assert closure["assembled"] is False and closure["samples"] == 0
    assert closure["mobility"] is None and closure["rank"] is None
    assert closure["attempts"] > 1
    (found,) = [d for d in document["diagnostics"] if d["code"] == "closure-not-assembled"]
    assert found["severity"] == "error" and "'reach'" in found["message"]
    assert mujoco_ranks(CLOSED / "unreachable.xml") == []  # MuJoCo's steps never close it


def test_the_report_says_the_mechanism_and_is_the_same_bytes_twice() -> None:
    first = run_cli("inspect", "tests/closed/fourbar.xml", "--format", "json")
    second = run_cli("inspect", "tests/closed/fourbar.xml", "--format", "json", fresh=True)
    assert first.code == 0 and first.stdout == second.stdout
    closure = json.loads(first.stdout)["closure"]
    geometry = {key: closure["cuts"][0].pop(key) for key in ("free", "frame_a", "frame_b")}
    assert geometry["free"] == "rotation"  # a point held: the anchor on each body
    assert geometry["frame_a"]["position"] == [0.25548, 0.0, -1.47808]
    assert np.allclose(geometry["frame_b"]["position"], [2, 0, 0], atol=1e-12)
    assert closure["cuts"][0].pop("axis") == [0.0, 0.0, 1.0]
    assert closure["cuts"] == [
        {
            "kind": "connect",
            "name": "ground_pivot",
            "links": ["rocker", "world"],
            "rows": 3,
            "file": "tests/closed/fourbar.xml",
            "line": _line_of(CLOSED / "fourbar.xml", '<connect name="ground_pivot"'),
        }
    ]
    assert closure["actuated"] == ["crank"] and closure["chart"] is True


def _line_of(path: Path, text: str) -> int:
    (line,) = [n for n, got in enumerate(path.read_text().splitlines(), 1) if text in got]
    return line


def test_a_tree_has_no_closure() -> None:
    report = cspace.inspect(REPO / "robots" / "arm7.urdf")
    assert report.closure is None and "closure" not in report.to_dict()


def _fourbar(tmp_path: Path, equality: str, extra: str = "") -> Path:
    text = (CLOSED / "fourbar.xml").read_text()
    start, end = text.index("  <equality>"), text.index("</equality>") + len("</equality>")
    path = tmp_path / "mechanism.xml"
    path.write_text(text[:start] + equality + extra + text[end:])
    return path


@pytest.mark.parametrize(
    "equality",
    [
        '<equality><connect body1="rocker" anchor="0.25548 0 -1.47808" active="false"/></equality>',
        '<option><flag equality="disable"/></option><equality><connect body1="rocker" '
        'anchor="0.25548 0 -1.47808"/></equality>',
    ],
    ids=["inactive", "switched-off"],
)
def test_a_constraint_mujoco_does_not_apply_closes_no_loop(tmp_path: Path, equality: str) -> None:
    report = cspace.inspect(_fourbar(tmp_path, equality))
    assert report.closure is None
    assert any(d.code == "equality-connect" for d in report.diagnostics)


def test_a_keyframe_off_the_loop_is_named_with_its_line(tmp_path: Path) -> None:
    keys = '<keyframe>\n<key name="closed" qpos="0 0 0"/>\n'
    keys += '<key name="open" qpos="0.5 0 0"/>\n</keyframe>\n'
    path = tmp_path / "keyed.xml"
    path.write_text((CLOSED / "fourbar.xml").read_text().replace("</mujoco>", keys + "</mujoco>"))
    report = cspace.inspect(path)
    found = [d for d in report.diagnostics if d.code == "pose-not-closed"]
    assert len(found) == 1 and "'open'" in found[0].message and "ground_pivot" in found[0].message
    assert found[0].line == _line_of(path, '<key name="open"')


def test_site_connects_and_welds_close_where_mujoco_closes_them(tmp_path: Path) -> None:
    """Sites on both sides, a weld with a relpose: cspace's projected configurations close
    MuJoCo's own equality rows."""
    path = tmp_path / "sites.xml"
    path.write_text(
        """<mujoco>
  <worldbody>
    <site name="ground" pos="0.6 0.1 0.2" euler="10 20 30"/>
    <body name="a" euler="5 10 15"><joint name="a" type="ball"/>
      <geom size="0.05"/>
      <body name="b" pos="0.4 0 0" euler="20 0 10"><joint name="b" type="hinge" axis="0 1 1"/>
        <geom size="0.05"/>
        <body name="c" pos="0.3 0.1 0"><joint name="c" type="slide" axis="1 0 0" range="-1 1"/>
          <geom size="0.05"/><site name="tip" pos="0.1 0.2 0" euler="7 8 9"/>
        </body>
      </body>
    </body>
    <body name="d" pos="1 0 0"><freejoint name="d"/><geom size="0.05"/></body>
  </worldbody>
  <equality>
    <connect name="pin" site1="tip" site2="ground"/>
    <weld name="glue" body1="d" body2="b" relpose="0.1 0.2 0.3 0.9 0.1 0.2 0.3"/>
  </equality>
</mujoco>"""
    )
    report = cspace.inspect(path)
    closure = report.closure
    assert closure is not None and closure.assembled
    assert [c.kind for c in closure.cuts] == ["connect", "weld"]
    # tree 3 + 1 + 1 + 6 = 11; 3 + 6 equations, independent: mobility 2
    assert (report.dimension, closure.constraint_rows, closure.mobility) == (11, 9, 2)
    assert max(mujoco_ranks(path)) == 9


def test_loops_the_limits_keep_open_are_said_to_be_the_limits(tmp_path: Path) -> None:
    """The four-bar closes with the rocker near 0; a range of [-1.2, -1] rad keeps it open."""
    path = tmp_path / "limited.xml"
    text = (CLOSED / "fourbar.xml").read_text()
    text = text.replace(
        '<joint name="rocker" type="hinge" axis="0 1 0"/>',
        '<joint name="rocker" type="hinge" axis="0 1 0" limited="true" range="-1.2 -1"/>',
    )
    path.write_text(text.replace("<worldbody>", '<compiler angle="radian"/>\n  <worldbody>'))
    report = cspace.inspect(path)
    assert report.closure is not None and report.closure.assembled is False, report.closure
    (found,) = [d for d in report.diagnostics if d.code == "closure-not-assembled"]
    assert "limits of 'rocker' left out" in found.message, found.message


def test_pinocchios_own_constraint_model_closes_where_cspace_does() -> None:
    """Pinocchio's MJCF parser reads the four-bar's connect as its own constraint model
    (``CONTACT_3D``): at the configurations cspace samples on the mechanism, Pinocchio's
    model puts the two points together and its constraint Jacobian has cspace's rank."""
    import pinocchio as pin

    path = CLOSED / "fourbar.xml"
    space = cspace.load(path)
    assert space.closure is not None
    found = space.closure.sample(6, np.random.default_rng(3))
    ours = cspace.pinocchio_model(path)
    model, constraints = pin.buildModelAndLegacyConstraintsFromMJCF(str(path))
    (constraint,) = constraints
    assert constraint.type == pin.ContactType.CONTACT_3D
    data, cdata = model.createData(), constraint.createData()
    assert len(found) == 6
    for x in found:
        q_ours, q = space.to_pinocchio(x), pin.neutral(model)
        for joint in range(1, model.njoints):  # by name: the two models' orders may differ
            mine, theirs = ours.joints[ours.getJointId(model.names[joint])], model.joints[joint]
            q[theirs.idx_q : theirs.idx_q + theirs.nq] = q_ours[mine.idx_q : mine.idx_q + mine.nq]
        pin.forwardKinematics(model, data, q)
        pin.computeJointJacobians(model, data, q)
        first = data.oMi[constraint.joint1_id] * constraint.joint1_placement
        second = data.oMi[constraint.joint2_id] * constraint.joint2_placement
        assert np.max(np.abs(first.translation - second.translation)) < 1e-8
        constraint.calc(model, data, cdata)
        jacobian = constraint.jacobian(model, data, cdata)[:3]
        values = np.linalg.svd(jacobian, compute_uv=False)
        assert int(np.sum(values > 1e-8 * values[0])) == 2 == model.nv - 1


@pytest.mark.parametrize("metres", [1.0, 0.001], ids=["metre", "millimetre"])
def test_a_four_bar_whose_links_just_reach_is_locked_not_mobile(
    tmp_path: Path, metres: float
) -> None:
    """Crank 0.5, coupler 2 and rocker 1.5 laid straight on a ground of 4: the one
    configuration is singular (a first-order motion there); no step along it projects
    anywhere else, so the mechanism is locked: mobility 0, said as shaky, at any size."""
    path = tmp_path / "flat.xml"
    a, b, c = (f"{length * metres:g}" for length in (0.5, 2.0, 1.5))
    path.write_text(
        f"""<mujoco model="flat"><worldbody>
  <body name="crank"><joint name="crank" axis="0 1 0"/><geom size="{a}"/>
    <body name="coupler" pos="{a} 0 0"><joint name="coupler" axis="0 1 0"/><geom size="{a}"/>
      <body name="rocker" pos="{b} 0 0"><joint name="rocker" axis="0 1 0"/><geom size="{a}"/>
      </body></body></body></worldbody>
  <equality><connect name="pin" body1="rocker" anchor="{c} 0 0"/></equality></mujoco>"""
    )
    report = cspace.inspect(path)
    assert report.closure is not None and report.closure.mobility == 0
    codes = {d.code for d in report.diagnostics}
    assert {"closure-shaky", "closure-rigid"} <= codes


def _flat(count: int, crank: str = "") -> str:
    """``count`` four-bars locked straight (crank 0.5, coupler 2, rocker 1.5 on a ground of
    4), side by side; ``crank`` is the first crank's extra joint attributes."""
    bodies, pins = [], []
    for k in range(count):
        extra = crank if k == 0 else ""
        bodies.append(
            f'<body name="crank{k}" pos="0 {k} 0"><joint name="crank{k}" axis="0 1 0"{extra}/>'
            f'<geom size="0.05"/><body name="coupler{k}" pos="0.5 0 0"><joint name="coupler{k}" '
            f'axis="0 1 0"/><geom size="0.05"/><body name="rocker{k}" pos="2 0 0">'
            f'<joint name="rocker{k}" axis="0 1 0"/><geom size="0.05"/></body></body></body>'
        )
        pins.append(f'<connect name="pin{k}" body1="rocker{k}" anchor="1.5 0 0"/>')
    return (
        '<mujoco model="flat"><compiler angle="radian"/><worldbody>'
        + "".join(bodies)
        + "</worldbody><equality>"
        + "".join(pins)
        + "</equality></mujoco>"
    )


@pytest.mark.parametrize(
    ("count", "crank"),
    [(3, ""), (1, ' limited="true" range="0 1"')],
    ids=["three-side-by-side", "a-stop-where-it-locks"],
)
def test_locked_four_bars_stay_locked(tmp_path: Path, count: int, crank: str) -> None:
    """Three locked four-bars: each direction is checked, none moves (mobility 0, not the
    first order's 3). A stop at the locked configuration (a toggle clamp's) stops the
    step one way; the other way springs back: still locked."""
    path = tmp_path / "flat.xml"
    path.write_text(_flat(count, crank))
    report = cspace.inspect(path)
    assert report.closure is not None and report.closure.mobility == 0
    assert {"closure-shaky", "closure-rigid"} <= {d.code for d in report.diagnostics}


def test_a_crank_of_a_small_range_still_moves_the_four_bar(tmp_path: Path) -> None:
    """A step along the motion that the crank's limits (+-0.3 mrad) cut short is no
    evidence against it: mobility 1."""
    path = tmp_path / "short.xml"
    path.write_text(
        (CLOSED / "fourbar.xml")
        .read_text()
        .replace(
            '<joint name="crank" type="hinge" axis="0 1 0"/>',
            '<joint name="crank" type="hinge" axis="0 1 0" limited="true" range="-0.0003 0.0003"/>',
        )
        .replace("<worldbody>", '<compiler angle="radian"/>\n  <worldbody>')
    )
    closure = cspace.inspect(path).closure
    assert closure is not None and closure.mobility == 1


def test_a_millimetre_arm_five_micrometres_short_does_not_assemble(tmp_path: Path) -> None:
    """A loop is closed within 1e-6 m, whatever the mechanism's size: 5 um is open."""
    path = tmp_path / "tiny.xml"
    path.write_text(
        """<mujoco model="tiny"><worldbody><site name="far" pos="0.001005 0 0"/>
  <body name="upper"><joint name="shoulder" axis="0 0 1"/><geom size="0.0001" mass="0.01"/>
    <body name="lower" pos="0.0005 0 0"><joint name="elbow" axis="0 0 1"/>
      <geom size="0.0001" mass="0.01"/><site name="tip" pos="0.0005 0 0"/></body></body></worldbody>
  <equality><connect name="reach" site1="tip" site2="far"/></equality></mujoco>"""
    )
    closure = cspace.inspect(path).closure
    assert closure is not None and closure.assembled is False


def test_a_weld_without_torque_holds_a_point_as_mujoco_does(tmp_path: Path) -> None:
    """``torquescale="0"``: MuJoCo's rotation rows are zero, the weld holds the rocker's
    origin only (a point on a planar four-bar: rank 2, mobility 1)."""
    path = tmp_path / "weld.xml"
    text = (CLOSED / "fourbar.xml").read_text()
    start, end = text.index("<connect"), text.index("/>", text.index("<connect")) + 2
    path.write_text(text[:start] + '<weld name="w" body1="rocker" torquescale="0"/>' + text[end:])
    closure = cspace.inspect(path).closure
    assert closure is not None and closure.cuts[0].rows == 3
    assert (closure.mobility, closure.rank) == (1, (2, 2))
    assert max(mujoco_ranks(path)) == 2


def test_a_tendon_tie_beside_the_loop_is_said_to_be_left_out(tmp_path: Path) -> None:
    """MuJoCo holds the tendon too (mobility 0); the closure holds only the connect."""
    path = tmp_path / "tendon.xml"
    tendon = (
        '<tendon><fixed name="tie"><joint joint="crank" coef="1"/><joint joint="rocker" '
        'coef="1"/></fixed></tendon>\n  <equality><tendon tendon1="tie"/>'
    )
    path.write_text((CLOSED / "fourbar.xml").read_text().replace("<equality>", tendon))
    report = cspace.inspect(path)
    assert report.closure is not None and report.closure.mobility == 1
    (found,) = [d for d in report.diagnostics if d.code == "closure-partial"]
    assert "1 joint or tendon equality constrains" in found.message
    assert max(mujoco_ranks(path)) == 3  # MuJoCo: the tie's row too, mobility 0
