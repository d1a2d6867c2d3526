"""Every robot file against Drake: what the suite checks on a part, here on the whole.

Two sweeps, each file read by cspace and parsed by pydrake once:

- ``mjcf``: every MJCF file of the test corpora (the repository's, and every ``<mujoco>``
  file dm_control, Gymnasium (and its robotics), pybullet, robosuite and metaworld
  install). Where MuJoCo compiles it and Drake parses it, cspace's ``drake-mjcf-differs``
  finding must be given exactly when Drake's model differs from MuJoCo's: a body MuJoCo
  names that Drake places elsewhere (1e-9, at 3 random configurations written as qpos
  and as Drake's q through cspace's maps) or lacks, or a Drake q of another length.
- ``files``: every URDF and SDF file under the given folders (default: pydrake's
  ``share/drake``; a Drake source tree or a ``drake_models`` checkout may be named, the
  packages in them added to Drake's package map). Where
  Drake parses it, cspace must read it with Drake's position and velocity names (each
  root cspace does not float welded, as its convention says); where Drake refuses it,
  cspace must refuse it.

Drake aborts the process on some files (a failed internal check, as on robosuite's
sawyer): each file is parsed in a worker process, restarted after a crash, the file
counted as ``drake-aborts``. Prints one line a file that is not as it should be, then
the counts and the CPU time.

Run: `.venv/bin/python bench/sweep_drake.py mjcf` or
`.venv/bin/python bench/sweep_drake.py files [FOLDER...]`.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib.util
import json
import re
import resource
import subprocess
import sys
from collections import Counter
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO / "tests"))  # the suite's corpora and oracles, not copies

from test_mjcf_sweep import PACKAGES  # noqa: E402

MJCF_ROOT = re.compile(rb"(\s|<\?xml[^>]*\?>|<!--.*?-->)*<mujoco[\s>]", re.S)


def mjcf_files() -> list[Path]:
    """The MJCF files of the corpora (as tests/test_mjcf_sweep.py and the repo's own)."""
    files = [
        p
        for folder in (REPO / "robots", REPO / "tests")
        for p in sorted(folder.rglob("*.xml"))
        if MJCF_ROOT.match(p.read_bytes())
    ]
    for package in PACKAGES:
        spec = importlib.util.find_spec(package)  # found, not imported
        if spec is None or not spec.submodule_search_locations:
            continue
        folder = Path(next(iter(spec.submodule_search_locations)))
        files += sorted(p for p in folder.rglob("*.xml") if MJCF_ROOT.match(p.read_bytes()))
    return files


def robot_files(folders: list[Path]) -> list[Path]:
    return sorted(p for f in folders for p in [*f.rglob("*.urdf"), *f.rglob("*.sdf")])


def _plant(path: Path, folders: list[str], weld: tuple[str, ...] = ()) -> Any:
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant

    plant = MultibodyPlant(0.0)
    parser = Parser(plant)
    for folder in folders:  # its packages (drake_models), unless Drake knows them already
        with contextlib.suppress(RuntimeError):
            parser.package_map().PopulateFromFolder(folder)
    models = parser.AddModels(str(path))
    for name in weld:
        for model in models:
            if plant.HasBodyNamed(name.rpartition("::")[2], model):
                body = plant.GetBodyByName(name.rpartition("::")[2], model)
                plant.WeldFrames(plant.world_frame(), body.body_frame())
    plant.Finalize()
    return plant


def check_mjcf(path: Path) -> str:
    """``said``/``quiet`` and whether right; or who refuses it."""
    import mujoco

    import cspace

    try:
        model = mujoco.MjModel.from_xml_path(str(path))
    except ValueError:
        return "mujoco-refuses"
    try:
        report = cspace.inspect(path)
        space = cspace.ConfigurationSpace.from_report(report)
        space.conventions().names("drake")  # refused where Drake's order cannot be said
    except cspace.CspaceError:
        return "cspace-refuses"
    said = any(d.code == "drake-mjcf-differs" for d in report.diagnostics)
    try:
        plant = _plant(path, [])
    except RuntimeError:
        return "drake-refuses"
    from test_drake_mjcf import drake_differs  # the suite's oracle, on every file

    differs = drake_differs(model, plant, space)
    verdict = "differs" if differs else "agrees"
    return f"{verdict}, said" if said else f"{verdict}, quiet"


def check_file(path: Path, folders: list[str]) -> str:
    """``agree``, ``both-refuse``, or what is wrong."""
    import cspace

    try:
        report = cspace.inspect(path)
        space = cspace.ConfigurationSpace.from_report(report)
        conventions = space.conventions()
        names = (conventions.names("drake"), conventions.names("drake", velocity=True))
        welded = conventions.drake.welded
    except cspace.CspaceError as refused:
        try:
            _plant(path, folders)
        except RuntimeError:
            return "both-refuse"
        return f"cspace refuses what Drake parses: {str(refused)[:160]}"
    try:
        plant = _plant(path, folders, welded)
    except RuntimeError as refused:
        return f"cspace reads what Drake refuses: {str(refused).splitlines()[0][:160]}"
    theirs = (tuple(plant.GetPositionNames(False)), tuple(plant.GetVelocityNames(False)))
    if names == theirs:
        return "agree"
    if not report.joints and len(theirs[0]) == 7:  # cspace has no joint to name it by
        return "agree, but Drake floats the one link"
    return f"names differ: {names[0][:6]} vs {theirs[0][:6]}"


def worker(kind: str, folders: list[str]) -> None:
    import logging

    logging.getLogger("drake").setLevel(logging.CRITICAL)
    for line in sys.stdin:
        path = Path(line.strip())
        outcome = check_mjcf(path) if kind == "mjcf" else check_file(path, folders)
        print(json.dumps([str(path), outcome]), flush=True)


def sweep(kind: str, paths: list[Path], folders: list[str]) -> dict[str, str]:
    """Each path's outcome, from workers restarted after each crash."""
    outcomes: dict[str, str] = {}
    todo = [str(p) for p in paths]
    while todo:
        child = subprocess.Popen(
            [sys.executable, __file__, "--worker", kind, *folders],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            text=True,
        )
        assert child.stdin is not None and child.stdout is not None
        child.stdin.write("".join(f"{p}\n" for p in todo))
        child.stdin.close()
        for line in child.stdout:
            path, outcome = json.loads(line)
            outcomes[path] = outcome
        child.wait()
        todo = [p for p in todo if p not in outcomes]
        if todo:
            outcomes[todo.pop(0)] = "drake-aborts"
    return outcomes


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("kind", choices=("mjcf", "files"))
    parser.add_argument("folders", nargs="*", type=Path)
    args = parser.parse_args()
    if args.kind == "mjcf":
        paths = mjcf_files()
        fine = ("differs, said", "agrees, quiet")
    else:
        from pydrake.common import FindResourceOrThrow

        share = Path(FindResourceOrThrow("drake/examples/acrobot/Acrobot.urdf")).parents[2]
        folders = args.folders or [share]
        paths = robot_files(folders)
        fine = ("agree", "both-refuse", "agree, but Drake floats the one link")
    outcomes = sweep(args.kind, paths, [str(f) for f in args.folders])
    for path, outcome in outcomes.items():
        if outcome not in fine and not outcome.endswith("-refuses"):
            print(f"{outcome}: {path}")
    used = resource.getrusage(resource.RUSAGE_CHILDREN)
    kinds = Counter(outcome.split(":")[0] for outcome in outcomes.values())
    print(", ".join(f"{kind} {n}" for kind, n in kinds.most_common()), f"({len(outcomes)} files)")
    print(f"{used.ru_utime + used.ru_stime:.1f} s of CPU in the workers")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--worker"]:
        worker(sys.argv[2], sys.argv[3:])
    else:
        main()
