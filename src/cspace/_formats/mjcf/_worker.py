"""The process that compiles MJCF models with MuJoCo, confined (run as ``python -I -m``).

MuJoCo's parse and compile have no limits of their own: time grows faster than linearly
with the model, memory with what ``<replicate>`` makes, and a compile cannot be
interrupted. So the parent (`mjcf`) runs it here, in a child that serves its process's
compiles one at a time (`serving`; the parent keeps one, `kept.KeptChild`), and that,
before it reads any document:

1. imports MuJoCo and compiles a small model (nothing is imported later), before it
   even reads its setup, so that the parent's imports overlap it;
2. caps itself with resource limits (`serving.take_setup`): address space, output
   size, 64 open files, no core, and before each request the CPU it may use for it;
3. gives up every capability and installs the seccomp filter (`seccomp`):
   no socket, no new process or thread, no program started;
4. confines itself with Landlock (`landlock`) to reading nothing at all:
   every file MuJoCo needs comes in the request (the parent's pre-scan read them).

Where the kernel offers neither layer, the child still runs: the pre-scan has already
given MuJoCo every file it names, so the layers are a second wall, not the only one.

It answers each request with ``U`` and the model's facts as JSON (`facts`), ``E`` and
MuJoCo's message, or ``M`` when MuJoCo ran out of the memory it may use; no model is kept
from one request to the next.
"""

from __future__ import annotations

import base64
import json
import sys
from typing import Any

from cspace._confine.sandbox import confine_to_reading, quiet_stdout
from cspace._confine.serving import next_request, send, should_retire, take_setup

_NO_MEMORY = "Could not allocate memory"
"""What MuJoCo says when an allocation of its own fails (its address space is bounded)."""

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


def _answer(request: dict[str, Any], memory_bytes: int) -> bytes:
    """One compile's answer: ``U`` and the facts, ``E`` (``M``: memory) and a message."""
    from cspace._formats.mjcf._compile import compile_model, facts

    includes = {name: base64.b64decode(data) for name, data in request["includes"].items()}
    try:
        model, spec, written = compile_model(request["main"], includes, request["placeholders"])
        answer = b"U" + json.dumps(facts(model, spec, written)).encode("utf-8")
    except BaseException as exc:  # MuJoCo raises ValueError; memory and the rest too
        memory = isinstance(exc, MemoryError) or _NO_MEMORY in str(exc)
        answer = (b"M" if memory else b"E") + _message(exc, memory_bytes).encode("utf-8")
    return answer


def main() -> int:
    """Load MuJoCo, confine this process, then compile one model a request.

    MuJoCo is imported and warmed up before the setup is read (it is trusted code), so
    that the parent's own imports run meanwhile; the limits and the confinement are in
    force before anything of a document is read.
    """
    import mujoco

    from cspace._formats.mjcf._compile import compile_model

    # MuJoCo's own warning handler appends to MUJOCO_LOG.TXT in the working folder: a
    # file must not make cspace write one. Warnings change no fact cspace reads.
    mujoco.set_mju_user_warning(_ignore)
    compile_model(_WARM_UP, {}, ["m.stl"])
    setup = take_setup()
    limits = setup["limits"]
    # Answers go to the pipe this keeps; anything MuJoCo itself prints to stdout goes
    # nowhere, so that it cannot be taken for an answer.
    out = quiet_stdout()
    confine_to_reading(())  # every file MuJoCo needs comes in the requests
    send(out, b"ready", int(limits["output_bytes"]))
    served = 0
    while (request := next_request(limits)) is not None:
        served += 1
        answer = _answer(request, int(limits["memory_bytes"]))
        retire = should_retire(limits, served)
        send(out, answer, int(limits["output_bytes"]), retire)
        if retire:
            break
    return 0


if __name__ == "__main__":
    sys.exit(main())
