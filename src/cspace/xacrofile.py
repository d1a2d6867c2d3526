"""Expanding xacro files to URDF, through the ``xacrodoc`` package (no ROS needed).

``$(find PKG)`` is resolved from the folders given with ``package_paths`` (each searched
for ``package.xml`` files) and then from the ``package.xml`` files found walking up from
the xacro file's folder; relative ``xacro:include`` file names are relative to the file
that includes them; ``args`` set ``<xacro:arg>`` values (``name:=value`` on the command
line).

``xacrodoc`` and ``xacro`` are imported only when a xacro file is read. xacro keeps its
package finder and include stack in module state, so expansion is reset before and
after each file.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType

from .errors import XacroError
from .xmlio import SourceFile, source_from_bytes


@dataclass(frozen=True)
class XacroOptions:
    """How to expand xacro files.

    Attributes:
        package_paths: Folders searched for ROS packages (``package.xml``), in order.
        args: xacro argument values by name.
    """

    package_paths: tuple[str, ...] = ()
    args: Mapping[str, str] = field(default_factory=lambda: MappingProxyType({}))

    @classmethod
    def from_cli(cls, package_paths: Sequence[str], args: Sequence[str]) -> XacroOptions:
        """Options from ``--package-path DIR`` and ``--arg NAME:=VALUE`` strings.

        Raises:
            ValueError: An argument is not ``NAME:=VALUE``.
        """
        parsed: dict[str, str] = {}
        for arg in args:
            name, sep, value = arg.partition(":=")
            if not sep or not name.strip():
                raise ValueError(f"xacro argument '{arg}' is not NAME:=VALUE")
            parsed[name.strip()] = value
        return cls(tuple(package_paths), MappingProxyType(parsed))


def expand(source: SourceFile, options: XacroOptions, file: str | None) -> SourceFile:
    """Expand a xacro document to URDF.

    Args:
        source: The xacro file's bytes.
        options: Package folders and argument values.
        file: The file on disk the bytes came from (relative includes and the
            ``package.xml`` search start from its folder), or None for the current folder.

    Returns:
        The URDF document, under the same path.

    Raises:
        XacroError: xacro failed (unknown package, missing include, bad expression, ...).
    """
    import xacro
    from xacrodoc import XacroDoc, packages

    start = os.path.abspath(file) if file is not None else os.path.join(os.getcwd(), "-")
    packages.reset()
    packages.walk_up_from(os.path.dirname(start))
    for folder in options.package_paths:
        if not os.path.isdir(folder):
            raise XacroError(source.path, f"package path '{folder}' is not a folder")
        packages.look_in([os.path.abspath(folder)])
    printed = io.StringIO()
    try:
        xacro.init_stacks(start)
        with contextlib.redirect_stderr(printed), contextlib.redirect_stdout(printed):
            document = XacroDoc.from_string(
                source.text, subargs=dict(options.args), resolve_packages=False
            )
            text = document.to_urdf_string()
    except Exception as exc:  # xacro raises its own, ValueError, KeyError, ...
        said = " ".join(str(exc).split()) or type(exc).__name__
        missing = re.search(r"Package not found: (\S+)", said)
        if missing:
            said = (
                f"$(find {missing.group(1)}): no such package (give a folder that holds it "
                "with --package-path, or put its package.xml above the file)"
            )
        raise XacroError(source.path, f"xacro cannot expand the file: {said}") from None
    finally:
        xacro.init_stacks(None)
        packages.reset()
    return source_from_bytes(source.path, text.encode("utf-8"))
