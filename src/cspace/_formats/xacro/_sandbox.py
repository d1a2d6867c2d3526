"""Running xacro in a confined child process with hard limits (the parent's side).

See `xacro._worker` for what the child does to itself. Here, the child is
started with an empty environment (so ``$(env ...)`` and ``$(optenv ...)`` see nothing
of the user's), its output goes to an anonymous file whose size the child's own
``RLIMIT_FSIZE`` caps, and it is killed when it outlives the wall-clock limit. Whatever
the child says is only ever a URDF text or a message for a one-line error.
"""

from collections.abc import Mapping, Sequence

from cspace._confine.sandbox import ChildLimits, ChildRefused, run_child
from cspace._formats.shared.xmlio import MAX_FILE_BYTES, MAX_FILES
from cspace._record import NamedTuple


class XacroLimits(NamedTuple):
    """The bounds of one xacro expansion.

    Attributes:
        cpu_seconds: CPU time the child may use (``RLIMIT_CPU``).
        wall_seconds: Wall-clock time before the child is killed.
        memory_bytes: Address space the child may map (``RLIMIT_AS``); the Python
            interpreter and xacro take about 60 MB of it before any document.
        output_bytes: Largest URDF text the child may write.
        max_files: Most files xacro may open (includes, YAML), each time counted.
        max_bytes: Most bytes in all the files xacro opens.
    """

    cpu_seconds: int = 4
    wall_seconds: float = 5.0
    memory_bytes: int = 512 * 1024 * 1024
    output_bytes: int = MAX_FILE_BYTES
    max_files: int = MAX_FILES
    max_bytes: int = MAX_FILE_BYTES


class XacroRefused(Exception):
    """The child could not expand the document; the message says why (one line)."""


def run_xacro(
    text: str,
    *,
    file: str,
    folders: Sequence[str],
    packages: Mapping[str, str],
    args: Mapping[str, str],
    limits: XacroLimits,
    require_confinement: bool,
) -> str:
    """Expand ``text`` in a confined child process.

    Args:
        text: The xacro document.
        file: The absolute path xacro resolves relative includes from.
        folders: The only folders the child may read (real paths).
        packages: Every package ``$(find NAME)`` may name -> its folder.
        args: ``<xacro:arg>`` values.
        limits: CPU, wall-clock, memory and output bounds.
        require_confinement: Refuse to expand when the kernel cannot confine the child
            (Landlock and seccomp).

    Returns:
        The URDF text.

    Raises:
        XacroRefused: Expansion failed, hit a limit, or tried what the sandbox refuses.
    """
    request = {
        "text": text,
        "file": file,
        "folders": list(folders),
        "packages": dict(packages),
        "args": dict(args),
        "require_confinement": require_confinement,
        "limits": {"max_files": limits.max_files, "max_bytes": limits.max_bytes},
    }
    child = ChildLimits(
        limits.cpu_seconds, limits.wall_seconds, limits.memory_bytes, limits.output_bytes
    )
    try:
        answer = run_child(
            "cspace._formats.xacro._worker", request, child, "xacro", folders[0] if folders else "/"
        )
    except ChildRefused as exc:
        raise XacroRefused(str(exc)) from None
    return answer.decode("utf-8", errors="replace")
