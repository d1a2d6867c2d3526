"""Remake this folder: each teaching URDF (robots/*.urdf) as urdf-usd-converter writes it.

Not run by the tests (the converter's usd-exchange ships a pxr of its own, which
cannot share an environment with usd-core): run it in an environment with
``urdf-usd-converter`` when the converter or a teaching robot changes::

    python -m venv /tmp/conv && /tmp/conv/bin/pip install urdf-usd-converter
    /tmp/conv/bin/python tests/usd/converted/make.py
    /tmp/conv/bin/python tests/usd/converted/make.py --sweep ERD_ROBOTS .venv/bin/cspace

``--sweep`` converts every URDF under a folder (example-robot-data's ``robots``) and
says how many ``cspace diff URDF USD`` finds unchanged, listing the others.

Each stage is the converter's output composed into one layer, without its geometry
(meshes, shapes, materials: the C-space does not depend on them), so that the files
stay small; every joint, body and schema the converter writes is kept.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

from pxr import Usd

HERE = Path(__file__).resolve().parent
ROBOTS = HERE.parents[2] / "robots"
GEOMETRY = {
    "Mesh",
    "Cube",
    "Sphere",
    "Cylinder",
    "Capsule",
    "Cone",
    "Plane",
    "Material",
    "Shader",
    "GeomSubset",
    "NodeGraph",
}


def convert(urdf: Path) -> None:
    with tempfile.TemporaryDirectory() as out:
        tool = Path(sys.executable).parent / "urdf_usd_converter"
        subprocess.run([str(tool), str(urdf), out], check=True, capture_output=True)
        (root,) = [p for p in Path(out).glob("*.usd*") if p.is_file()]
        layer = Usd.Stage.Open(str(root)).Flatten()
        stage = Usd.Stage.Open(layer)
        doomed = [p.GetPath() for p in stage.Traverse() if p.GetTypeName() in GEOMETRY]
        for path in sorted(doomed, key=lambda p: -p.pathElementCount):
            stage.RemovePrim(path)
        layer.documentation = (
            f"urdf-usd-converter's output for robots/{urdf.name}, without geometry"
        )
        layer.Export(str(HERE / f"{urdf.stem}.usda"))


def sweep(folder: Path, cspace: str) -> None:
    """Convert every URDF under ``folder`` and the teaching ones; diff each with cspace."""
    urdfs = sorted(folder.rglob("*.urdf")) + sorted(ROBOTS.glob("*.urdf"))
    same, other = 0, []
    with tempfile.TemporaryDirectory() as out:
        for k, urdf in enumerate(urdfs):
            target = Path(out) / str(k)
            tool = Path(sys.executable).parent / "urdf_usd_converter"
            done = subprocess.run(
                [str(tool), str(urdf), str(target)],
                capture_output=True,
                text=True,
                env={"ROS_PACKAGE_PATH": str(folder), "PATH": ""},
            )
            stages = sorted(target.glob("*.usd*")) if done.returncode == 0 else []
            if not stages:
                other.append(f"{urdf}: not converted")
                continue
            diff = subprocess.run(
                [cspace, "diff", str(urdf), str(stages[0])], capture_output=True, text=True
            )
            if diff.returncode == 0:
                same += 1
            else:
                other.append(f"{urdf}: {(diff.stdout or diff.stderr).splitlines()[0]}")
    print(f"{same} of {len(urdfs)} converted URDFs have their URDF's C-space")
    print("\n".join(other))


if __name__ == "__main__":
    if sys.argv[1:2] == ["--sweep"]:
        sweep(Path(sys.argv[2]), sys.argv[3])
    else:
        for urdf in sorted(ROBOTS.glob("*.urdf")):
            convert(urdf)
            print(urdf.name)
