"""The loop-closure constraints of a mechanism, on its tree's Pinocchio model.

A mechanism with loops is its kinematic tree (Pinocchio's model of the file with every
loop cut open) and one constraint per cut (`CutSpec`): two frames, on two links, that
coincide up to the motion the cut leaves free. With ``T = M_a^-1 M_b`` the second frame
in the first (``R`` its rotation, ``t`` its translation, both in frame a), the equations
are (LaValle, *Planning Algorithms*, section 4.4):

- ``rotation`` (a ball, MJCF ``connect``): ``t = 0`` (3 rows, m);
- ``none`` (a weld, a fixed joint): ``t = 0`` and ``log3(R) = 0`` (6 rows, m and rad);
- ``revolute`` about the unit axis ``a``: ``t = 0`` and the two components of ``log3(R)``
  normal to ``a`` (5 rows);
- ``prismatic`` along ``a``: the two components of ``t`` normal to ``a`` and
  ``log3(R) = 0`` (5 rows).

Their Jacobian, with ``nu_a``, ``nu_b`` the frames' body velocities (Pinocchio's
``LOCAL`` frame Jacobians): ``nu_T = nu_b - Ad(T^-1) nu_a``, ``dt = R v_T``,
``d log3(R) = Jlog3(R) w_T``. Configurations are Pinocchio's ``q`` (shape ``(nq,)``),
tangents its ``v`` (``(nv,)``); steps go through ``pinocchio.integrate``, so quaternions
stay unit and angles stay (cos, sin) pairs.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from cspace._formats.shared.description import CutSpec
from cspace._formats.shared.pose import Pose

FloatArray = np.ndarray[Any, np.dtype[np.float64]]

CLOSED_TOLERANCE = 1e-9
"""Largest residual (m, rad; the largest absolute row) a projection aims for."""

RANK_FLOOR = 1e-12
"""A singular value at or below this counts for nothing, whatever the largest (m, rad)."""

RANK_TOLERANCE = 1e-5
"""A singular value of the constraint Jacobian counts when above this share of the largest
(and above `RANK_FLOOR`), whatever the mechanism's size: files write six digits or so, and
a planar linkage whose axes they tilt by 1e-6 rad, or a Bennett linkage written in
OpenUSD's 32-bit joint frames (its condition missed by 4e-8), still moves as drawn."""

MAX_ITERATIONS = 60
"""Most Levenberg-Marquardt steps of one projection."""


def se3(pose: Pose) -> Any:
    """A pose as a Pinocchio ``SE3``, its quaternion normalised."""
    w, x, y, z = pose.rotation_wxyz
    rotation = pin.Quaternion(float(w), float(x), float(y), float(z))
    rotation.normalize()
    return pin.SE3(rotation.matrix(), np.array(pose.position, dtype=float))


def _normals(axis: Sequence[float]) -> FloatArray:
    """Two unit vectors normal to ``axis`` and to each other, shape (2, 3)."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    helper = np.eye(3)[int(np.argmin(np.abs(a)))]
    u = np.cross(a, helper)
    u /= np.linalg.norm(u)
    return np.stack([u, np.cross(a, u)])


def link_frame(model: Any, link: str, root_link: str, rooted: bool = False) -> int:
    """The Pinocchio frame of a link: its ``BODY`` frame.

    The root link without one (MJCF's world) is the frame of the root joint cspace added
    above it (``rooted``), or else the universe.

    Raises:
        KeyError: The model has no frame for the link.
    """
    if model.existFrame(link, pin.FrameType.BODY):
        return int(model.getFrameId(link, pin.FrameType.BODY))
    if link == root_link:  # MJCF's world: on the root joint cspace adds, if any
        from cspace._model.adapter import ROOT_JOINT_NAME

        if rooted and model.existFrame(ROOT_JOINT_NAME, pin.FrameType.JOINT):
            return int(model.getFrameId(ROOT_JOINT_NAME, pin.FrameType.JOINT))
        return 0
    raise KeyError(link)


class LoopConstraints:
    """The closure constraints of one mechanism: residual, Jacobian, projection.

    Holds its own copy of the tree's model (with a frame on each side of each cut) and
    its own data: not for use from two threads at once.

    Attributes:
        cuts: The cuts, in order.
        rows: Rows of the residual, sum of the cuts' rows.
        nq: Length of Pinocchio's q.
        nv: Length of Pinocchio's v.
    """

    def __init__(
        self, model: Any, cuts: Sequence[CutSpec], root_link: str, rooted: bool = False
    ) -> None:
        """Frames for the cuts on a copy of ``model``.

        Raises:
            KeyError: A cut names a link the model has no frame for.
        """
        self.model = pin.Model(model)
        self.cuts = tuple(cuts)
        self._frames: list[tuple[int, int, str, FloatArray]] = []
        for index, cut in enumerate(self.cuts):
            ids = []
            for side, link, pose in (
                ("a", cut.link_a, cut.frame_a),
                ("b", cut.link_b, cut.frame_b),
            ):
                parent = self.model.frames[link_frame(self.model, link, root_link, rooted)]
                frame = pin.Frame(
                    f"cspace_cut{index}_{side}",
                    parent.parentJoint,
                    parent.placement * se3(pose),
                    pin.FrameType.OP_FRAME,
                )
                ids.append(int(self.model.addFrame(frame, False)))
            self._frames.append((ids[0], ids[1], cut.free, _normals(cut.axis)))
        self.data = self.model.createData()
        self.rows = sum(cut.rows for cut in self.cuts)
        self.nq = int(self.model.nq)
        self.nv = int(self.model.nv)

    def residual(self, q: FloatArray) -> FloatArray:
        """The closure residual at one configuration, shape (rows,)."""
        pin.framesForwardKinematics(self.model, self.data, q)
        return np.concatenate([self._rows(a, b, free, n)[0] for a, b, free, n in self._frames])

    def residual_and_jacobian(self, q: FloatArray) -> tuple[FloatArray, FloatArray]:
        """The residual (rows,) and its Jacobian (rows, nv) at one configuration."""
        if self.nv == 0:  # Pinocchio's frame Jacobian crashes on a model without velocities
            return self.residual(q), np.zeros((self.rows, 0))
        pin.computeJointJacobians(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)
        values, blocks = [], []
        for a, b, free, normals in self._frames:
            value, transform = self._rows(a, b, free, normals)
            values.append(value)
            blocks.append(self._jacobian(a, b, free, normals, transform))
        if not blocks:
            return np.zeros(0), np.zeros((0, self.nv))
        return np.concatenate(values), np.vstack(blocks)

    def _rows(self, a: int, b: int, free: str, normals: FloatArray) -> tuple[FloatArray, Any]:
        transform = self.data.oMf[a].actInv(self.data.oMf[b])
        t = transform.translation
        if free == "rotation":
            return t.copy(), transform
        w = pin.log3(transform.rotation)
        if free == "none":
            return np.concatenate([t, w]), transform
        if free == "revolute":
            return np.concatenate([t, normals @ w]), transform
        return np.concatenate([normals @ t, w]), transform

    def _jacobian(
        self, a: int, b: int, free: str, normals: FloatArray, transform: Any
    ) -> FloatArray:
        jb = pin.getFrameJacobian(self.model, self.data, b, pin.ReferenceFrame.LOCAL)
        ja = pin.getFrameJacobian(self.model, self.data, a, pin.ReferenceFrame.LOCAL)
        relative = jb - transform.inverse().action @ ja
        dt: FloatArray = transform.rotation @ relative[:3]
        if free == "rotation":
            return dt
        dw = pin.Jlog3(transform.rotation) @ relative[3:]
        if free == "none":
            return np.vstack([dt, dw])
        if free == "revolute":
            return np.vstack([dt, normals @ dw])
        return np.vstack([normals @ dt, dw])

    def project(
        self,
        q: FloatArray,
        bounds: tuple[FloatArray, FloatArray] | None = None,
        *,
        tolerance: float = CLOSED_TOLERANCE,
        max_iterations: int = MAX_ITERATIONS,
    ) -> tuple[FloatArray, float, int]:
        """The configuration moved onto the constraints by Levenberg-Marquardt steps.

        Each step solves the damped normal equations in Pinocchio's tangent space and
        integrates; a step that does not lower the residual is refused and the damping
        raised.

        Args:
            q: A configuration, shape (nq,); not changed.
            bounds: Lower and upper values of q's entries (shape (nq,) each, infinite
                where free); each step's result is clipped into them.
            tolerance: The largest absolute residual row at which to stop.
            max_iterations: Most steps taken.

        Returns:
            The configuration reached, its largest absolute residual row, the steps taken.
        """
        with np.errstate(all="ignore"):  # a file's huge numbers give inf: no step then
            return self._project(np.array(q, dtype=float), bounds, tolerance, max_iterations)

    def _project(
        self,
        q: FloatArray,
        bounds: tuple[FloatArray, FloatArray] | None,
        tolerance: float,
        max_iterations: int,
    ) -> tuple[FloatArray, float, int]:
        r, jacobian = self.residual_and_jacobian(q)
        worst = float(np.max(np.abs(r), initial=0.0))
        damping = 1e-6
        steps = 0
        while worst > tolerance and steps < max_iterations and _finite(r, jacobian):
            steps += 1
            try:
                step = _damped_step(jacobian, r, damping)
                if bounds is not None:  # a joint at its bound, pushed out: hold it there
                    held = self._pushed_out(q, step, bounds)
                    if held.any():
                        step = _damped_step(np.where(held, 0.0, jacobian), r, damping)
                        step[held] = 0.0
            except np.linalg.LinAlgError:
                break
            candidate = pin.integrate(self.model, q, step)
            if bounds is not None:
                candidate = np.clip(candidate, bounds[0], bounds[1])
            r_new, j_new = self.residual_and_jacobian(candidate)
            new = float(np.max(np.abs(r_new), initial=0.0))
            if np.isfinite(new) and float(r_new @ r_new) < float(r @ r):
                q, r, jacobian, worst = candidate, r_new, j_new, new
                damping = max(damping / 4.0, 1e-12)
            else:
                damping *= 8.0
                if damping > 1e8:
                    break
        return q, (worst if np.isfinite(worst) else math.inf), steps

    def _pushed_out(
        self, q: FloatArray, step: FloatArray, bounds: tuple[FloatArray, FloatArray]
    ) -> Any:
        """The tangent entries of one-number joints at a bound that ``step`` pushes past it."""
        held = np.zeros(self.nv, dtype=bool)
        at_q, at_v = self.scalar
        value, move = q[at_q], step[at_v]
        out = ((value <= bounds[0][at_q]) & (move < 0)) | ((value >= bounds[1][at_q]) & (move > 0))
        held[at_v[out]] = True
        return held

    def longest_step(
        self,
        q: FloatArray,
        direction: FloatArray,
        most: float,
        bounds: tuple[FloatArray, FloatArray],
    ) -> float:
        """The longest step along a tangent ``direction`` that stays within ``bounds``.

        At most ``most``; every one-number joint's value stays within its bounds.
        """
        at_q, at_v = self.scalar
        value, move = q[at_q], direction[at_v]
        room = np.full(len(at_q), np.inf)
        up, down = move > 0, move < 0
        room[up] = (bounds[1][at_q][up] - value[up]) / move[up]
        room[down] = (bounds[0][at_q][down] - value[down]) / move[down]
        return float(max(0.0, min(most, float(np.min(room, initial=np.inf)))))

    @property
    def scalar(self) -> tuple[Any, Any]:
        """The q and v indices of the joints of one number in both (revolute, prismatic)."""
        if not hasattr(self, "_scalar_indices"):
            pairs = [
                (int(j.idx_q), int(j.idx_v))
                for j in self.model.joints[1:]
                if int(j.nq) == 1 and int(j.nv) == 1
            ]
            self._scalar_indices = (
                np.array([p[0] for p in pairs], dtype=int),
                np.array([p[1] for p in pairs], dtype=int),
            )
        return self._scalar_indices


def _finite(r: FloatArray, jacobian: FloatArray) -> bool:
    return bool(np.isfinite(r).all() and np.isfinite(jacobian).all())


def _damped_step(jacobian: FloatArray, r: FloatArray, damping: float) -> FloatArray:
    """``-J^T (J J^T + mu I)^-1 r``, solved in the smaller of the two sizes."""
    rows, cols = jacobian.shape
    scale = damping * max(1.0, float(r @ r))
    if rows <= cols:
        system = jacobian @ jacobian.T + scale * np.eye(rows)
        step: FloatArray = np.asarray(-jacobian.T @ np.linalg.solve(system, r), dtype=float)
        return step
    normal = jacobian.T @ jacobian + scale * np.eye(cols)
    out: FloatArray = np.asarray(-np.linalg.solve(normal, jacobian.T @ r), dtype=float)
    return out


def is_chart(jacobian: FloatArray, commanded: Sequence[int]) -> bool:
    """Whether the given velocity columns are coordinates of the mechanism near a point.

    With J the constraint Jacobian there, ``commanded`` the columns given (the joints on
    no loop count as given: their columns are zero) and P the others: the passive joints'
    velocities follow from the given ones, and the given ones are free, when
    rank(J_P) = |P| = rank(J) (the implicit function theorem).
    """
    given = set(commanded)
    on_loops = np.abs(jacobian).max(axis=0, initial=0.0) > RANK_TOLERANCE
    passive = [c for c in range(jacobian.shape[1]) if c not in given and on_loops[c]]
    return rank(jacobian[:, passive]) == len(passive) == rank(jacobian)


def rank(jacobian: FloatArray) -> int:
    """The numerical rank of a constraint Jacobian (`RANK_TOLERANCE`)."""
    if jacobian.size == 0 or not np.isfinite(jacobian).all():
        return 0
    values = np.linalg.svd(jacobian, compute_uv=False)
    largest = float(values[0])
    return int(np.sum(values > max(RANK_TOLERANCE * largest, RANK_FLOOR)))


MAX_DISTANCE = 1e6
"""Farthest a cut's frame may be from its link's origin (m): beyond, differences of its
coordinates lose every digit a residual needs."""


def problem(cut: CutSpec) -> str | None:
    """Why a cut is none of the mechanism's constraints, or None when it is one.

    A cut must hold two links, with finite frames within `MAX_DISTANCE` and a nonzero
    axis (`closure_analysis` leaves the others out, with a ``closure-invalid`` finding).
    """
    if cut.link_a == cut.link_b:
        return f"holds link '{cut.link_a}' to itself"
    numbers = [*cut.frame_a.position, *cut.frame_a.rotation_wxyz, *cut.frame_b.position]
    numbers += [*cut.frame_b.rotation_wxyz, *cut.axis]
    if not all(math.isfinite(n) for n in numbers) or not any(cut.axis):
        return "has a number that is not finite, or a zero axis"
    far = max(abs(n) for n in (*cut.frame_a.position, *cut.frame_b.position))
    if far > MAX_DISTANCE:
        return f"has a frame {far:.3g} m from its link, farther than {MAX_DISTANCE:g} m"
    return None


@dataclass(frozen=True)
class LoopModel:
    """What `LoopConstraints` is built from: the tree's model and the mechanism's cuts.

    Pickles (Pinocchio's models do), so a configuration space that holds one does.

    Attributes:
        model: The tree's ``pinocchio.Model``.
        cuts: The cuts `problem` finds nothing wrong with, in the file's order.
        root_link: The tree's root link.
        rooted: Whether cspace added a root joint above it.
    """

    model: Any
    cuts: tuple[CutSpec, ...]
    root_link: str
    rooted: bool = False

    def constraints(self) -> LoopConstraints:
        """The constraints (a new `LoopConstraints`, with its own data)."""
        return LoopConstraints(self.model, self.cuts, self.root_link, self.rooted)
