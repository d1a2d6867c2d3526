"""The `cspace` command, run in a process forked from one that has already imported cspace.

Most of the suite runs the command as a user does: its arguments, working folder,
environment and standard input in, its exit status, standard output and error out. A new
interpreter spends most of such a run importing Python, NumPy, Pinocchio and cspace
(about 0.17 s of CPU of a 0.19 s run, measured on the suite's 1,700 runs), so each pytest
worker starts one server process that imports them once and forks a process per command.
The forked process is a new process, as the console script's would be: it is given the
test's three streams (passed over a Unix socket), folder, environment and ``sys.argv``,
calls the very ``main`` the ``cspace`` script calls, and leaves by ``SystemExit`` through
the interpreter's own shutdown (exit handlers, flushing standard output, a broken pipe's
exit status), whose status the test reads as ``subprocess`` would report it.

What a fork cannot give is what an interpreter fixes as it starts: its start-up
environment (``PYTHON*``, the locale, the thread counts NumPy's BLAS reads), its hash
seed, and the cost of start-up itself. So ``conftest.run_cli`` starts a real process when
a test changes such a variable, when it asks for one (``fresh=True``: determinism across
runs, whose hash seeds differ), and the tests that measure CPU time or memory, run the
wheel, the action or the start-up imports always start the real script.

Run as a script, this module is the server: ``python forked_cli.py SOCKET``.
"""

from __future__ import annotations

import importlib
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

STARTUP_PREFIXES = ("PYTHON", "LC_", "LANG", "OPENBLAS_", "OMP_", "MKL_", "NUMBA_", "LD_")
"""Environment variables read as the interpreter and its libraries start: a command
whose environment changes one of them runs in a new interpreter."""

PRELOADED = (
    "cspace._cli.main",  # first: it sets the BLAS thread count NumPy reads as it loads
    "cspace._cli.commands.inspect",
    "cspace._model.loader",
    "cspace.space",
    "pinocchio",
)
"""What the server imports: what nearly every command needs, and no format's library
(MuJoCo, OpenUSD, xacro's) nor a renderer's, which commands still import as they go."""

_HEADER = 8  # bytes of the request's length


def _startup(env: dict[str, str]) -> dict[str, str]:
    return {k: v for k, v in env.items() if k.startswith(STARTUP_PREFIXES)}


# --- the server --------------------------------------------------------------------


def _receive(conn: socket.socket) -> tuple[dict[str, object], list[int]]:
    data, fds, _, _ = socket.recv_fds(conn, 1 << 16, 3)
    size = int.from_bytes(data[:_HEADER], "big")
    while len(data) < _HEADER + size:
        more = conn.recv(1 << 16)
        if not more:
            raise EOFError("the request was cut short")
        data += more
    request: dict[str, object] = json.loads(data[_HEADER : _HEADER + size])
    return request, fds


def _command(request: dict[str, object], fds: list[int], script: str) -> None:
    """In the forked process: become `cspace ARGS...` and leave as its script would."""
    for target, fd in enumerate(fds):
        os.dup2(fd, target)
        os.close(fd)
    os.chdir(str(request["cwd"]))
    os.environ.clear()
    os.environ.update(request["env"])  # type: ignore[arg-type]
    sys.argv = [script, *request["args"]]  # type: ignore[misc]
    from cspace._cli.main import main

    sys.exit(main())  # up through the server's frames: nothing there catches it


def _handle(conn: socket.socket, script: str) -> None:
    """In a process forked per connection: fork the command, wait, say how it ended."""
    try:
        request, fds = _receive(conn)
        pid = os.fork()
    except BaseException:  # never back into the server's loop
        os._exit(1)
    if pid == 0:
        conn.close()
        _command(request, fds, script)
    try:
        for fd in fds:
            os.close(fd)
        conn.sendall(f"{pid}\n".encode())
        _, status = os.waitpid(pid, 0)
        conn.sendall(f"{os.waitstatus_to_exitcode(status)}\n".encode())
    finally:
        os._exit(0)


def serve(path: str) -> None:
    """Import what every command needs, then fork a process per connection on ``path``."""
    script = str(Path(sys.executable).with_name("cspace"))
    sys.path[0] = str(Path(script).parent)  # as the console script's own sys.path
    for name in PRELOADED:
        importlib.import_module(name)
    parent = os.getppid()
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    listener.bind(path + ".part")
    listener.listen(64)
    os.rename(path + ".part", path)  # connectable once it has its name
    listener.settimeout(1.0)
    signal.signal(signal.SIGCHLD, signal.SIG_IGN)  # handlers are reaped by the kernel
    while os.getppid() == parent:  # the pytest worker is gone: so is the server
        try:
            conn, _ = listener.accept()
        except TimeoutError:
            continue
        conn.settimeout(None)
        if os.fork() == 0:
            listener.close()
            signal.signal(signal.SIGCHLD, signal.SIG_DFL)
            _handle(conn, script)
        conn.close()


# --- the client --------------------------------------------------------------------


class _Server:
    def __init__(self) -> None:
        self.folder = tempfile.mkdtemp(prefix="cspace-forked-")
        self.path = os.path.join(self.folder, "socket")
        self.log = open(os.path.join(self.folder, "log"), "w+b")  # noqa: SIM115
        self.env = dict(os.environ)
        self.process = subprocess.Popen(
            [sys.executable, __file__, self.path],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=self.log,
            close_fds=True,
        )
        deadline = time.monotonic() + 120
        while not os.path.exists(self.path):
            if self.process.poll() is not None or time.monotonic() > deadline:
                self.log.seek(0)
                raise RuntimeError(f"the forked cspace server did not start:\n{self.log.read()}")
            time.sleep(0.01)

    def stop(self) -> None:
        self.process.kill()
        self.process.wait()
        self.log.close()
        for name in os.listdir(self.folder):
            os.unlink(os.path.join(self.folder, name))
        os.rmdir(self.folder)


_SERVER: dict[int, _Server] = {}


def _server() -> _Server:
    server = _SERVER.get(os.getpid())
    if server is None:
        import atexit

        server = _SERVER[os.getpid()] = _Server()
        atexit.register(server.stop)
    return server


def forkable(env: dict[str, str]) -> bool:
    """Whether a command with this environment may run forked (its start-up is the same)."""
    return _startup(env) == _startup(_server().env)


def _drain(fd: int, into: list[bytes]) -> None:
    with open(fd, "rb", closefd=True) as stream:
        into.append(stream.read())


def _feed(fd: int, data: bytes) -> None:
    view = memoryview(data)
    try:
        while view:
            view = view[os.write(fd, view) :]
    except BrokenPipeError:  # the command stopped reading: as subprocess ignores it
        pass
    finally:
        os.close(fd)


def run(
    args: list[str], cwd: str, stdin: bytes | None, timeout: float, env: dict[str, str]
) -> tuple[int, bytes, bytes]:
    """Run `cspace ARGS...` forked; its exit status (negative: the signal), stdout, stderr.

    Raises ``subprocess.TimeoutExpired`` after killing it, as ``subprocess.run`` does."""
    server = _server()
    out_r, out_w = os.pipe()
    err_r, err_w = os.pipe()
    threads: list[threading.Thread] = []
    if stdin is None:
        in_fd, in_w = 0, -1  # this process's own, as subprocess passes it
    else:
        in_fd, in_w = os.pipe()
    payload = json.dumps({"args": list(args), "cwd": cwd, "env": env}).encode()
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as conn:
        conn.connect(server.path)
        header = len(payload).to_bytes(_HEADER, "big")
        socket.send_fds(conn, [header + payload], [in_fd, out_w, err_w])
        for fd in (out_w, err_w) + ((in_fd,) if in_w >= 0 else ()):
            os.close(fd)
        out: list[bytes] = []
        err: list[bytes] = []
        threads = [
            threading.Thread(target=_drain, args=(out_r, out), daemon=True),
            threading.Thread(target=_drain, args=(err_r, err), daemon=True),
        ]
        if in_w >= 0:
            threads.append(threading.Thread(target=_feed, args=(in_w, stdin), daemon=True))
        for thread in threads:
            thread.start()
        reply = conn.makefile("rb")
        pid = int(reply.readline())  # at once: the handler sends it as it forks
        conn.settimeout(timeout)
        try:
            line = reply.readline()
        except TimeoutError:
            os.kill(pid, signal.SIGKILL)
            raise subprocess.TimeoutExpired(["cspace", *args], timeout) from None
        if not line:
            raise RuntimeError(f"the forked cspace server lost the command {args}")
        code = int(line)
    for thread in threads:
        thread.join()
    return code, b"".join(out), b"".join(err)


if __name__ == "__main__":
    serve(sys.argv[1])
