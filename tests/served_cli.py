"""The `cspace` command as a program that a shell, xargs or git starts, served forked.

Some tests run a shell script as CI runs it (the workflow of docs/ci.md, ``git ls-files
-z | xargs -0 cspace ...``): the shell, not the test, starts ``cspace``, so
``conftest.run_cli`` cannot fork it. `script` writes a ``cspace`` for them that starts
in about 0.02 s of CPU (``python -I -S``, the standard library only): it hands its
arguments, folder, environment, umask and its own three streams (whatever the script
redirected them to) to this pytest worker's server (``forked_cli``), which forks the
command from a process that has imported cspace, and it leaves with that command's
exit status (killed by the same signal, if one ended it). The script's own logic, its
pipes, redirections and exit statuses all run for real; only each command's
interpreter start-up (about 0.25 s of CPU) is skipped. A command whose environment
changes what an interpreter reads as it starts runs the installed script instead, as
``run_cli`` does. The installed script itself is what the tests of the wheel, the
Action and the pre-commit hook run.
"""

from __future__ import annotations

import atexit
import os
import shutil
import sys
import tempfile
from pathlib import Path

import forked_cli
from conftest import cspace_command

_CLIENT = """\
import array, json, os, socket, sys

SOCKET, HEADER, PREFIXES, IMPORTED, STARTUP, SCRIPT = {settings!r}
env = dict(os.environ)
if {{**IMPORTED, **{{k: v for k, v in env.items() if k.startswith(PREFIXES)}}}} != STARTUP:
    os.execv(SCRIPT, [SCRIPT, *sys.argv[1:]])  # an interpreter would start otherwise
umask = os.umask(0o022)
os.umask(umask)
request = {{"args": sys.argv[1:], "cwd": os.getcwd(), "env": env, "umask": umask}}
payload = json.dumps({{**request, "measure": False}}).encode()
data = len(payload).to_bytes(HEADER, "big") + payload
with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as conn:
    conn.connect(SOCKET)
    streams = array.array("i", [0, 1, 2])  # this process's own, as the script set them
    sent = conn.sendmsg([data], [(socket.SOL_SOCKET, socket.SCM_RIGHTS, streams)])
    conn.sendall(data[sent:])
    reply = conn.makefile("rb")
    reply.readline()  # the command's process id
    ended = reply.readline().split()
if not ended:
    sys.exit("cspace (served): the forked cspace server lost the command")
code = int(ended[0])
if code < 0:  # ended by a signal: so is this process, as its caller would see the script
    import signal

    signal.signal(-code, signal.SIG_DFL)
    os.kill(os.getpid(), -code)
sys.exit(code)
"""
"""The served ``cspace``: the client half of ``forked_cli``'s protocol (a request of
``forked_cli._HEADER`` bytes of length then JSON, with three descriptors; a line of the
command's process id, then one of its exit status), given its settings as a literal."""

_SCRIPTS: dict[int, Path] = {}


def script() -> Path:
    """This process's served ``cspace``, alone in its folder (for the front of ``PATH``).

    Written once a process (each pytest worker has its own server), removed at its exit.
    """
    made = _SCRIPTS.get(os.getpid())
    if made is not None:
        return made
    server = forked_cli._server()
    settings = (
        server.path,
        forked_cli._HEADER,
        forked_cli.STARTUP_PREFIXES,
        server.imported,
        {**server.imported, **server.before},
        cspace_command()[0],
    )
    folder = tempfile.mkdtemp(prefix="cspace-served-")
    made = Path(folder, "cspace")
    made.write_text(f"#!{sys.executable} -IS\n" + _CLIENT.format(settings=settings))
    made.chmod(0o755)
    owner = os.getpid()
    atexit.register(lambda: os.getpid() == owner and shutil.rmtree(folder, ignore_errors=True))
    _SCRIPTS[owner] = made
    return made
