"""A trajectory's ctrl through a continuous hinge, held to MuJoCo's ``mj_step``.

MuJoCo does not wrap a hinge's qpos, and a position actuator pulls its joint to where
``gear * qpos`` equals ctrl: a target of -3.03 rad for a joint at 3.0 swings it 6 rad
back, not 0.25 forward. So the ctrl of a lifted trajectory (``conv.wrap(lift,
"mujoco-ctrl")``, ``cspace unwrap --inverse --convention mujoco-ctrl``) follows the lift's
angles, and MuJoCo's servo follows the trajectory the way it goes.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np

import cspace

from conftest import run_cli

SPINNER = """<mujoco>
  <compiler angle="radian"/>
  <option gravity="0 0 0" timestep="0.002"/>
  <worldbody>
    <body name="platter">
      <joint name="spin" type="hinge" axis="0 0 1"/>
      <geom type="box" size="0.2 0.05 0.02"/>
      <body name="carriage">
        <joint name="lift" type="slide" axis="0 0 1" range="-0.2 0.2"/>
        <geom type="box" size="0.02 0.02 0.02"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <position name="lift_servo" joint="lift" kp="400" kv="40"/>
    <position name="spin_servo" joint="spin" kp="40" kv="4" gear="2"/>
  </actuator>
</mujoco>
"""

LIFT = np.stack([np.linspace(2.8, 3.6, 9), np.full(9, 0.1)], axis=1)
"""The turntable crossing pi (canonical coordinates spin, lift), forward all the way."""


def test_the_ctrl_of_a_lift_turns_the_way_the_trajectory_goes(tmp_path: Path) -> None:
    path = tmp_path / "spinner.xml"
    path.write_text(SPINNER)
    conventions = cspace.load(path).conventions()
    ctrl = conventions.wrap(LIFT, "mujoco-ctrl")
    np.testing.assert_allclose(ctrl[:, 1], 2 * LIFT[:, 0], atol=1e-12)  # gear * the lift
    np.testing.assert_allclose(ctrl[:, 0], LIFT[:, 1], atol=1e-12)
    np.testing.assert_allclose(conventions.unwrap(ctrl, "mujoco-ctrl"), LIFT, atol=1e-12)
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    spin = model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, "spin")]
    data.qpos[spin] = LIFT[0, 0]
    low = high = LIFT[0, 0]
    for row in ctrl:
        data.ctrl[:] = row
        for _ in range(300):
            mujoco.mj_step(model, data)
            low, high = min(low, data.qpos[spin]), max(high, data.qpos[spin])
    assert abs(data.qpos[spin] - LIFT[-1, 0]) < 1e-3, data.qpos[spin]
    assert low > LIFT[0, 0] - 0.05 and high < LIFT[-1, 0] + 0.05, (low, high)

    rows = "".join(f"{s!r},{h!r}\n" for s, h in LIFT.tolist())
    (tmp_path / "lift.csv").write_text("spin,lift\n" + rows)
    run = run_cli(
        "unwrap", "spinner.xml", "lift.csv", "--convention", "mujoco-ctrl", "--inverse",
        cwd=tmp_path,
    )  # fmt: skip
    assert run.code == 0, run.stderr
    header, *written = run.stdout.splitlines()
    assert header == "lift_servo,spin_servo"
    spins = [float(line.split(",")[1]) for line in written]
    np.testing.assert_allclose(spins, 2 * LIFT[:, 0], atol=1e-9)
