"""The process that compiles one MJCF model with MuJoCo, confined (run as ``python -I -m``).

MuJoCo's parse and compile have no limits of their own: time grows faster than linearly
with the model, memory with what ``<replicate>`` makes, and a compile cannot be
interrupted. So the parent (`mjcf`) runs it here, in a child that, before
it reads the document:

1. imports MuJoCo and compiles a small model (nothing is imported later), before it
   even reads the request, so that the parent's imports overlap it;
2. caps itself with resource limits (`limit_self`): CPU seconds,
   address space, output size, 64 open files, no core;
3. gives up every capability and installs the seccomp filter (`seccomp`):
   no socket, no new process or thread, no program started;
4. confines itself with Landlock (`landlock`) to reading nothing at all:
   every file MuJoCo needs came in the request (the parent's pre-scan read them).

Where the kernel offers neither layer, the child still runs: the pre-scan has already
given MuJoCo every file it names, so the layers are a second wall, not the only one.

It writes ``U`` and the model's facts as JSON (`facts`), or
``E`` and MuJoCo's message.
"""

from __future__ import annotations

import base64
import json
import sys

from cspace._confine.sandbox import confine_to_reading, quiet_stdout, take_request, write_answer

MAX_MESSAGE_CHARS = 4096
"""Longest error message the child sends back."""

_WARM_UP = """<mujoco><asset><mesh name="m" file="m.stl"/></asset><worldbody>
<body><freejoint/><geom type="mesh" mesh="m"/><body><joint name="j"/><geom size=".1"/>
</body></body></worldbody><equality><joint joint1="j"/></equality></mujoco>"""
"""A small model that makes MuJoCo load what it loads on first use."""


def _ignore(message: str) -> None:
    """MuJoCo's warnings, dropped."""


def _message(exc: BaseException, memory_bytes: int) -> str:
    if isinstance(exc, MemoryError):
        return f"MuJoCo needed more than the {memory_bytes // 2**20:,} MiB of memory it may use"
    said = str(exc)
    if len(said) > MAX_MESSAGE_CHARS:
        half = MAX_MESSAGE_CHARS // 2
        said = f"{said[:half]} ... {said[-half:]}"
    return said or type(exc).__name__


def main() -> int:
    """Load MuJoCo, read the request, confine this process, compile, write the facts.

    MuJoCo is imported and warmed up before the request is read (it is trusted code), so
    that the parent's own imports run meanwhile; the limits and the confinement are in
    force before anything of the document is read.
    """
    import mujoco

    from cspace._formats.mjcf_compile import compile_model, facts

    # MuJoCo's own warning handler appends to MUJOCO_LOG.TXT in the working folder: a
    # file must not make cspace write one. Warnings change no fact cspace reads.
    mujoco.set_mju_user_warning(_ignore)
    compile_model(_WARM_UP, {}, ["m.stl"])
    request = take_request()
    limits = request["limits"]
    # The answer goes to the file the parent gave as stdout; anything MuJoCo itself
    # prints to stdout goes nowhere, so that it cannot be taken for the answer.
    out = quiet_stdout()
    confine_to_reading(())  # every file MuJoCo needs came in the request
    includes = {name: base64.b64decode(data) for name, data in request["includes"].items()}
    try:
        model, spec, written = compile_model(request["main"], includes, request["placeholders"])
        answer = b"U" + json.dumps(facts(model, spec, written)).encode("utf-8")
    except BaseException as exc:  # MuJoCo raises ValueError; memory and the rest too
        answer = b"E" + _message(exc, int(limits["memory_bytes"])).encode("utf-8")
    write_answer(answer, int(limits["output_bytes"]), out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
