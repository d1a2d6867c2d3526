"""The configuration space and its factors.

``configuration_space`` holds :class:`ConfigurationSpace`; ``factors`` and ``rotations``
its factors; ``layout`` and ``mapping`` where their coordinates sit; ``kernels`` the
batch kernels.

``ConfigurationSpace`` and ``load`` are imported on first use: NumPy stays out of
``import cspace``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from cspace.space.configuration_space import ConfigurationSpace, load

__all__ = ["ConfigurationSpace", "load"]


def __getattr__(name: str) -> Any:
    if name in __all__:
        from cspace.space import configuration_space

        return getattr(configuration_space, name)
    raise AttributeError(f"module 'cspace.space' has no attribute {name!r}")
