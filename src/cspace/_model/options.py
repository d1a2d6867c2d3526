"""How a robot file is loaded: one record of the options every way in takes.

`cspace.inspect`, `cspace.inspect_source`, `cspace.pinocchio_model`, `cspace.load`
(`cspace.space.load`), `cspace.inspect_many` and the command line's loader each take the
same keyword arguments; each builds one `LoadOptions` of them and hands it down, and the
loader reads nothing else. The fields' defaults are the keyword arguments' defaults
(``tests/test_public_api.py`` holds every signature to them), and `cspace.inspect`'s
docstring says what each option means; the other entry points refer to it.
"""

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING

from cspace._record import NamedTuple

if TYPE_CHECKING:
    from cspace._formats.xacro.expand import XacroOptions


class LoadOptions(NamedTuple):
    """The options of one load, as `cspace.inspect`'s keyword arguments of the same names.

    A record pickles (`inspect_many` sends it to its workers) when its ``xacro`` does.
    ``pinocchio_model`` has no ``group`` or ``hold``: its record keeps their defaults.
    """

    root_joint: str | None = None
    xacro: "XacroOptions | None" = None
    force_xacro: bool = False
    allow_dirs: Sequence[str | os.PathLike[str]] = ()
    srdf: str | os.PathLike[str] | bool | None = None
    group: str | None = None
    hold: str | None = None
    limits: str | os.PathLike[str] | bool | None = None
