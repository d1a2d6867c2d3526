"""What the space's helpers read of a configuration space: a protocol, not the class.

The helpers (engines, conventions, sampling, validation, ...) take the space they work
on, and `ConfigurationSpace` calls them; typing them with the class itself would make
each import the other. `Space` is the part of the space they read, so that imports go
one way only: `ConfigurationSpace` to its helpers, the helpers to this module.
`ConfigurationSpace` satisfies it (mypy checks that where it passes itself).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

from numpy.typing import ArrayLike

from cspace.space._geometry.rotations import BoolArray, FloatArray

if TYPE_CHECKING:
    from cspace._factor_kinds import Coordinate
    from cspace._findings import Diagnostic
    from cspace._reports.report import JointReport
    from cspace._slots import MujocoLayout
    from cspace.space._geometry.layout import Layout, Slot


class Space(Protocol):
    """The configuration space, as its helpers read it (see `ConfigurationSpace`)."""

    @property
    def robot(self) -> str: ...

    @property
    def layout(self) -> Layout: ...

    @property
    def nq(self) -> int: ...

    @property
    def weights(self) -> tuple[float, ...]: ...

    @property
    def other_joints(self) -> tuple[str, ...]: ...

    @property
    def tolerance(self) -> float: ...

    @property
    def report_joints(self) -> tuple[JointReport, ...]: ...

    @property
    def mujoco(self) -> MujocoLayout | None: ...

    @property
    def source_format(self) -> str: ...

    @property
    def drake_findings(self) -> tuple[Diagnostic, ...]: ...

    @property
    def size(self) -> int: ...

    @property
    def dimension(self) -> int: ...

    @property
    def names(self) -> tuple[str, ...]: ...

    @property
    def coordinates(self) -> tuple[Coordinate, ...]: ...

    @property
    def joints(self) -> tuple[str, ...]: ...

    @property
    def slots(self) -> tuple[Slot, ...]: ...

    @property
    def tangent_names(self) -> tuple[str, ...]: ...

    @property
    def _columns(self) -> Any: ...

    def canonicalize(self, x: ArrayLike, out: FloatArray | None = None) -> FloatArray: ...

    def neutral(self) -> FloatArray: ...

    def contains(self, x: ArrayLike, tolerance: float = 0.0) -> bool | BoolArray: ...

    def to_pinocchio(self, x: ArrayLike) -> FloatArray: ...

    def from_pinocchio(self, q: ArrayLike) -> FloatArray: ...
