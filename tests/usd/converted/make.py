"""Remake this folder: each teaching URDF (robots/*.urdf) as urdf-usd-converter writes it.

Not run by the tests (the converter's usd-exchange ships a pxr of its own, which
cannot share an environment with usd-core): run it in an environment with
``urdf-usd-converter`` when the converter or a teaching robot changes::

    python -m venv /tmp/conv && /tmp/conv/bin/pip install urdf-usd-converter
    /tmp/conv/bin/python tests/usd/converted/make.py

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


if __name__ == "__main__":
    for urdf in sorted(ROBOTS.glob("*.urdf")):
        convert(urdf)
        print(urdf.name)
