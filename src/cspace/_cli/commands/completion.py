"""``cspace completion SHELL``: a completion script for bash, zsh or fish.

The script comes from argcomplete (a maintained library, not a script written here):
on TAB, the shell runs ``cspace`` with argcomplete's environment variables, and
`main` answers from the argument parser itself (commands, options, their
choices, file names), so completion never goes stale. Install it once::

    mkdir -p ~/.local/share/bash-completion/completions
    cspace completion bash > ~/.local/share/bash-completion/completions/cspace
    mkdir -p ~/.zfunc  # and in ~/.zshrc, before compinit: fpath=(~/.zfunc $fpath)
    cspace completion zsh > ~/.zfunc/_cspace
    mkdir -p ~/.config/fish/completions
    cspace completion fish > ~/.config/fish/completions/cspace.fish
"""

from __future__ import annotations

import argparse
from typing import Any

from .. import exit_codes, output
from . import add

SHELLS = ("bash", "zsh", "fish")


def register(sub: Any) -> None:
    """Add the ``completion`` command."""
    parser = add(
        sub,
        "completion",
        description="Print the completion script of a shell; where to put it: Getting "
        "started in the documentation (docs/getting-started.md, 'Set-up'). Completion asks "
        "cspace's own argument parser, so it knows every command, option and choice.",
    )
    parser.add_argument("shell", choices=SHELLS, help="the shell")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Write the script."""
    from argcomplete.shell_integration import shellcode

    output.write(shellcode(["cspace"], shell=args.shell))
    return exit_codes.OK
