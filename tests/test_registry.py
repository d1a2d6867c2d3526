"""The registry of conventions is the one list: the command line, the types, the maps,
the report's slots and the labels all come from it or agree with it."""

from __future__ import annotations

import argparse
import json
from typing import get_args

from cspace._cli.main import build_parser
from cspace.conventions import TOOLS, Conventions
from cspace.space._conventions import Convention, Named

from conftest import REPO


def _choices(command: str, dest: str) -> tuple[str, ...]:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    action = next(a for a in sub.choices[command]._actions if a.dest == dest)
    return tuple(action.choices or ())


def test_the_command_line_offers_exactly_the_registry() -> None:
    assert _choices("convert", "source") == (*TOOLS, "named")
    assert _choices("convert", "target") == (*TOOLS, "named")
    assert _choices("unwrap", "convention") == tuple(TOOLS)


def test_the_python_types_are_the_registry() -> None:
    assert get_args(Convention) == tuple(TOOLS)
    assert get_args(Named) == (*TOOLS, "named")


def test_every_tool_has_its_maps_both_ways() -> None:
    for name in TOOLS:
        if name == "canonical":
            continue
        for verb in ("to", "from"):
            assert callable(getattr(Conventions, f"{verb}_{name}"))
            assert callable(getattr(Conventions, f"{verb}_{name}_velocity"))


def test_the_reports_slots_are_the_registrys() -> None:
    schema = json.loads((REPO / "src/cspace/_schema/report-v1.schema.json").read_text())
    slots = set(schema["$defs"]["joint"]["properties"]["slots"]["properties"])
    declared = {key for tool in TOOLS.values() if tool.slots for key in tool.slots}
    assert slots == declared
