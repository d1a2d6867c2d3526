"""The `cspace` command, run in a process forked from one that has already imported cspace.

Most of the suite runs the command as a user does: its arguments, working folder,
environment and standard input in, its exit status, standard output and error out. A new
interpreter spends most of such a run importing Python, NumPy, Pinocchio and cspace
(about 0.17 s of CPU of a 0.19 s run, measured on the suite's 1,700 runs), so each pytest
worker starts one server process that imports them once and forks a process per command.
The forked process is a new process, as the console script's would be: it is given the
test's three streams (passed over a Unix socket), folder, environment and ``sys.argv``,
calls the very ``main`` the ``cspace`` script calls, and leaves by ``SystemExit`` through
the interpreter's own shutdown (its threads joined, every exit handler run, standard
output and error flushed, a broken pipe's exit status), whose status the test reads as
``subprocess`` would report it. Only the last step, tearing the interpreter's modules
down, is skipped (`_leave`): it is the same for every command, and cost each 0.02 s.

What a fork cannot give is what an interpreter fixes as it starts: its start-up
environment (``PYTHON*``, the locale, the thread counts NumPy's BLAS reads), its hash
seed, and the cost of start-up itself. So ``conftest.run_cli`` starts a real process when
a test changes such a variable or asks for one (``fresh=True``: determinism across runs,
whose hash seeds differ); the tests that measure a command's CPU time or memory
(``conftest.measured``, ``conftest.cpu_of``: a user's run starts an interpreter) start
it too, unless the bound is on what a file makes cspace do (``measured(forked=True)``:
`measure` gives the forked command's CPU time and peak memory, start-up left out); and
the tests of the wheel, the Action, the pre-commit hook and the start-up imports always
start the real script.

Run as a script, this module is the server: ``python forked_cli.py SOCKET``.
"""

from __future__ import annotations

import array
import contextlib
import gc
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
from collections.abc import Callable
from pathlib import Path
from typing import Any, NamedTuple

STARTUP_PREFIXES = (
    *("PYTHON", "LC_", "LANG", "TZ", "LD_", "MALLOC_", "GLIBC_"),
    *("OPENBLAS_", "GOTO_", "OMP_", "MKL_", "NUMBA_"),
)
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

_STATUS: list[int] = []
"""In a forked command: the exit status its interpreter is leaving with."""


def _leave() -> None:
    """The last exit handler of a forked command: leave with its status, untorn.

    Registered before anything else in the server, so that it runs after every other
    handler (the command's, and its libraries'). Standard output and error are flushed as
    the interpreter would; if that fails, the interpreter goes on and reports it as it
    does (exit status 120). In the server itself it does nothing.
    """
    if not _STATUS:
        return
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except BaseException:
        return
    os._exit(_STATUS[0])


def _status(code: object) -> int:
    """The exit status ``SystemExit(code)`` gives (its message printed by Python)."""
    if code is None:
        return 0
    return code & 0xFF if isinstance(code, int) else 1


def _startup(env: dict[str, str]) -> dict[str, str]:
    return {k: v for k, v in env.items() if k.startswith(STARTUP_PREFIXES)}


# --- a process tree's memory ---------------------------------------------------------

PAGE_KIB = os.sysconf("SC_PAGE_SIZE") // 1024


def tree_rss(root: int) -> int:
    """The resident memory of ``root`` and every process below it, in KiB: the tree walked
    down each thread's list of children (Linux's /proc/PID/task/TID/children)."""
    total, frontier = 0, [root]
    while frontier:
        pid = frontier.pop()
        try:
            with open(f"/proc/{pid}/statm") as f:
                total += int(f.read().split()[1]) * PAGE_KIB
            for task in os.listdir(f"/proc/{pid}/task"):
                with open(f"/proc/{pid}/task/{task}/children") as f:
                    frontier.extend(map(int, f.read().split()))
        except (OSError, IndexError, ValueError):  # ended meanwhile
            pass
    return total


def tree_rss_scanned(root: int) -> int:
    """`tree_rss`, from every process's parent (where the kernel lists no children)."""
    parents, rss = {}, {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
            parents[int(entry)] = int(fields[1])
            rss[int(entry)] = int(fields[21]) * PAGE_KIB
        except (OSError, IndexError, ValueError):
            pass
    below, total, frontier = {root}, 0, [root]
    while frontier:
        pid = frontier.pop()
        total += rss.get(pid, 0)
        children = [c for c, p in parents.items() if p == pid and c not in below]
        below.update(children)
        frontier.extend(children)
    return total


def tree_sampler() -> Callable[[int], int]:
    """`tree_rss` where the kernel lists children, else `tree_rss_scanned`."""
    listed = os.path.exists(f"/proc/{os.getpid()}/task/{os.getpid()}/children")
    return tree_rss if listed else tree_rss_scanned


def tree_peak(pid: int) -> Callable[[], int]:
    """Sample the resident memory of ``pid``'s tree every 20 ms, on a thread (so that its
    end is seen at once); the function returned stops it and gives the peak, in KiB."""
    sample, peak, done = tree_sampler(), [0], threading.Event()

    def sampling() -> None:
        while not done.is_set():
            peak[0] = max(peak[0], sample(pid))
            done.wait(0.02)

    watcher = threading.Thread(target=sampling, daemon=True)
    watcher.start()

    def stop() -> int:
        done.set()
        watcher.join()
        return peak[0]

    return stop


def _watch(pid: int) -> tuple[int, Any, int]:
    """Wait for child ``pid``, its tree's memory sampled (`tree_peak`): its wait status,
    resource usage (its own and every child's it waited for) and peak KiB, the largest of
    the tree's sampled total and of the kernel's peak of any one process."""
    stop = tree_peak(pid)
    _, status, usage = os.wait4(pid, 0)
    return status, usage, max(stop(), usage.ru_maxrss)


# --- the server --------------------------------------------------------------------


def _receive(conn: socket.socket) -> tuple[dict[str, Any], list[int]]:
    data, fds, _, _ = socket.recv_fds(conn, 1 << 16, 3)
    if len(fds) != 3:
        raise EOFError(f"{len(fds)} streams came, not 3")
    size = int.from_bytes(data[:_HEADER], "big")
    while len(data) < _HEADER + size:
        more = conn.recv(1 << 16)
        if not more:
            raise EOFError("the request was cut short")
        data += more
    request: dict[str, Any] = json.loads(data[_HEADER : _HEADER + size])
    return request, fds


def _command(
    request: dict[str, Any], fds: list[int], script: str, imported: dict[str, str]
) -> None:
    """In the forked process: become `cspace ARGS...` and leave as its script would."""
    for target, fd in enumerate(fds):
        os.dup2(fd, target)
        os.close(fd)
    os.chdir(request["cwd"])
    os.umask(request["umask"])
    os.environ.clear()
    os.environ.update(request["env"])
    for name, value in imported.items():  # what importing cspace sets (setdefault)
        os.environ.setdefault(name, value)
    sys.argv = [script, *request["args"]]
    from cspace._cli.main import main

    try:
        code = main()
    except SystemExit as leaving:
        _STATUS.append(_status(leaving.code))
        raise  # up through the server's frames: nothing there catches it
    except BaseException:  # Python prints it, and leaves with status 1
        _STATUS.append(1)
        raise
    _STATUS.append(_status(code))
    sys.exit(code)


def _handle(conn: socket.socket, script: str, imported: dict[str, str]) -> None:
    """In a process forked per connection: fork the command, wait, say how it ended."""
    try:
        request, fds = _receive(conn)
        pid = os.fork()
    except BaseException:  # never back into the server's loop
        os._exit(1)
    if pid == 0:
        conn.close()
        _command(request, fds, script, imported)
    try:
        for fd in fds:
            os.close(fd)
        conn.sendall(f"{pid}\n".encode())
        if request["measure"]:
            status, usage, peak = _watch(pid)
        else:
            _, status, usage = os.wait4(pid, 0)
            peak = usage.ru_maxrss
        cpu = usage.ru_utime + usage.ru_stime  # its own and its waited children's
        conn.sendall(f"{os.waitstatus_to_exitcode(status)} {cpu!r} {peak}\n".encode())
    finally:
        os._exit(0)


def serve(path: str, worker: int) -> None:
    """Import what every command needs, then fork a process per connection on ``path``,
    until process ``worker`` (the pytest worker) is gone."""
    import atexit

    atexit.register(_leave)  # first: it runs last, after every other exit handler
    script = str(Path(sys.executable).with_name("cspace"))
    sys.path[0] = str(Path(script).parent)  # as the console script's own sys.path
    before = dict(os.environ)
    for name in PRELOADED:
        importlib.import_module(name)
    # What the imports made lives as long as each command: out of the collector's sight, a
    # command's collections and its interpreter's shutdown do not write to (and so copy)
    # every page it shares with the server (0.04 s of CPU a command)
    gc.freeze()
    imported = {k: v for k, v in os.environ.items() if k not in before}
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    listener.bind(path)
    listener.listen(64)
    # ready: the start-up the forked commands share, on a line of standard output
    print(json.dumps({"before": _startup(before), "imported": imported}), flush=True)
    listener.settimeout(1.0)
    signal.signal(signal.SIGCHLD, signal.SIG_IGN)  # handlers are reaped by the kernel
    while os.getppid() == worker:
        try:
            conn, _ = listener.accept()
        except TimeoutError:
            continue
        conn.settimeout(None)
        try:
            pid = os.fork()
        except OSError:  # no process to spare now: this request fails, not the server
            conn.close()
            continue
        if pid == 0:
            listener.close()
            signal.signal(signal.SIGCHLD, signal.SIG_DFL)
            _handle(conn, script, imported)
        conn.close()


# --- the client --------------------------------------------------------------------


class _Server:
    def __init__(self) -> None:
        self.owner = os.getpid()
        self.folder = tempfile.mkdtemp(prefix="cspace-forked-")
        self.path = os.path.join(self.folder, "socket")
        # pipes for its own streams, as a command's would be (not seekable, not a terminal)
        self.process = subprocess.Popen(
            [sys.executable, __file__, self.path, str(os.getpid())],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            close_fds=True,
        )
        assert self.process.stdout is not None
        ready = self.process.stdout.readline()  # once it listens; nothing: it ended
        if not ready:
            self.process.wait()
            raise RuntimeError(f"the forked cspace server did not start: {self.said()}")
        startup = json.loads(ready)
        self.before: dict[str, str] = startup["before"]
        self.imported: dict[str, str] = startup["imported"]

    def said(self) -> str:
        """What the server wrote on standard error, once it has ended."""
        if self.process.poll() is None:
            return "(it runs)"
        assert self.process.stderr is not None
        return self.process.stderr.read().decode("utf-8", "replace")

    def stop(self) -> None:
        if os.getpid() != self.owner:  # a process forked from the worker: not its server
            return
        self.process.kill()
        self.process.wait()
        for name in os.listdir(self.folder):
            os.unlink(os.path.join(self.folder, name))
        os.rmdir(self.folder)


_SERVER: dict[int, _Server] = {}
_STARTING = threading.Lock()


def _server() -> _Server:
    with _STARTING:
        server = _SERVER.get(os.getpid())
        if server is None:
            import atexit

            server = _SERVER[os.getpid()] = _Server()
            atexit.register(server.stop)
    return server


def forkable(env: dict[str, str]) -> bool:
    """Whether a command with this environment may run forked: a new interpreter given
    it would start as the server did (the same start-up variables, once cspace's own
    imports have set theirs)."""
    server = _server()
    return {**server.imported, **_startup(env)} == {**server.imported, **server.before}


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


class Killed(subprocess.TimeoutExpired):
    """A forked command that outlived its timeout, killed: ``pid`` was its process."""

    def __init__(self, args: list[str], timeout: float, pid: int) -> None:
        super().__init__(["cspace", *args], timeout)
        self.pid = pid


class Ended(NamedTuple):
    """How a forked command ended."""

    code: int
    """Its exit status (negative: the signal that ended it)."""
    stdout: bytes
    stderr: bytes
    cpu_seconds: float
    """CPU time (user and system) of the command and of every child it waited for, from
    the fork on: the interpreter's start-up and the server's imports are not in it."""
    peak_mib: float
    """Its peak resident memory, of its process tree added up (sampled every 20 ms), or
    of its largest process (the kernel's peak): pages it shares with the server's image
    count once touched or copied. Measured only by `measure`: `run`'s is the kernel's
    peak alone."""


def run(
    args: list[str],
    cwd: str,
    stdin: bytes | None,
    timeout: float,
    env: dict[str, str],
    stdout: int | None = None,
) -> tuple[int, bytes, bytes]:
    """Run `cspace ARGS...` forked: its exit status (negative: the signal), standard
    output and standard error (its standard output goes to descriptor ``stdout`` when
    one is given, and b"" is returned for it).

    ``timeout`` is ``subprocess.run``'s: a wall-clock guard against a hang (from the start
    to the end of both outputs), never a bound on how long a command may take; callers
    give many times what the command takes on a busy machine (``conftest.run_cli``: 60 s).
    Past it the command is killed and `Killed` (a ``subprocess.TimeoutExpired``) raised.
    """
    ended = _request(args, cwd, stdin, timeout, env, measure=False, stdout=stdout)
    return ended.code, ended.stdout, ended.stderr


def measure(
    args: list[str], cwd: str, stdin: bytes | None, timeout: float, env: dict[str, str]
) -> Ended:
    """`run`, and the CPU time and peak memory of the forked command (`Ended`), measured
    as ``conftest.measured`` measures the installed script's, from the fork on."""
    return _request(args, cwd, stdin, timeout, env, measure=True)


def _request(
    args: list[str],
    cwd: str,
    stdin: bytes | None,
    timeout: float,
    env: dict[str, str],
    measure: bool,
    stdout: int | None = None,
) -> Ended:
    server = _server()
    deadline = time.monotonic() + timeout
    umask = os.umask(0o022)
    os.umask(umask)
    request = {
        "args": list(args),
        "cwd": os.path.abspath(cwd),
        "env": env,
        "umask": umask,
        "measure": measure,
    }
    payload = json.dumps(request).encode()
    out_r, out_w = os.pipe() if stdout is None else (-1, stdout)
    err_r, err_w = os.pipe()
    in_fd, in_w = (0, -1) if stdin is None else os.pipe()  # None: this process's own
    out: list[bytes] = []
    err: list[bytes] = []
    threads = [threading.Thread(target=_drain, args=(err_r, err), daemon=True)]
    if out_r >= 0:
        threads.append(threading.Thread(target=_drain, args=(out_r, out), daemon=True))
    if in_w >= 0:
        threads.append(threading.Thread(target=_feed, args=(in_w, stdin), daemon=True))
    pid = 0
    try:
        with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as conn:
            conn.connect(server.path)
            data = len(payload).to_bytes(_HEADER, "big") + payload
            streams = array.array("i", [in_fd, out_w, err_w])
            sent = conn.sendmsg([data], [(socket.SOL_SOCKET, socket.SCM_RIGHTS, streams)])
            conn.sendall(data[sent:])
            for fd in (err_w,) + ((out_w,) if out_r >= 0 else ()) + ((in_fd,) if in_w >= 0 else ()):
                os.close(fd)
            for thread in threads:
                thread.start()
            reply = conn.makefile("rb")
            conn.settimeout(max(deadline - time.monotonic(), 0.001))
            pid = int(reply.readline())
            conn.settimeout(max(deadline - time.monotonic(), 0.001))
            line = reply.readline()
            if not line:
                raise RuntimeError(f"the forked cspace server lost {args}: {server.said()}")
            code, cpu, peak_kib = line.split()
        for thread in threads:
            thread.join(max(deadline - time.monotonic(), 0.001))
            if thread.is_alive():  # a child of the command holds an output open
                raise TimeoutError
    except (TimeoutError, ValueError) as exc:
        if pid:
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)
            raise Killed(args, timeout, pid) from None
        raise RuntimeError(f"the forked cspace server failed {args}: {server.said()}") from exc
    return Ended(int(code), b"".join(out), b"".join(err), float(cpu), int(peak_kib) / 1024)


if __name__ == "__main__":
    serve(sys.argv[1], int(sys.argv[2]))
