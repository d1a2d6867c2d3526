"""One module per `cspace` command, and the table of them.

`COMMANDS` names each command (its module is ``cspace._cli.commands.NAME``) with the
line ``cspace --help`` shows for it, in that order. The command line imports only the
module of the command it runs (as pip does): the others are listed from this table.
Adding a command is a module with ``register(sub)`` (which calls `add`) and a row here.
"""

from __future__ import annotations

from typing import Any

COMMANDS: dict[str, str] = {
    "inspect": "report the configuration space of robot files",
    "diff": "show what changed in the C-space between two robot files or reports",
    "check": "exit 1 unless a robot has the expected C-space and dimension",
    "schema": "print the JSON Schema of the JSON report",
    "sample": "print uniformly sampled configurations",
    "distance": "print the distance between two configurations",
    "interpolate": "print configurations along the shortest path from A to B",
    "collisions": "find which link pairs collide; check the SRDF's, MuJoCo's or PhysX's filters",
    "convert": "convert configurations (or velocities) between conventions",
    "unwrap": "lift a trajectory: continuous angles unwrapped, quaternion signs kept",
    "completion": "print a shell completion script (bash, zsh, fish)",
}


def add(sub: Any, name: str, **kwargs: Any) -> Any:
    """Add command ``name``'s parser to ``sub``, with its line of `COMMANDS`."""
    return sub.add_parser(name, help=COMMANDS[name], **kwargs)
