"""Static equilibria of many (spring, crank angle) pairs at once: the static spring sweep's cells.

:func:`static_equilibria` runs, for every spring and every crank angle together, the secant of
:func:`~pasibot_pin.studies.methods.statics.static_equilibrium` (same start, same steps, same stops,
the same central difference for the stability): the hip-holding torque of each pair comes from one
batched Newton closure (``ConstraintSystem.evaluate`` on (N, nv), one ``np.linalg.solve`` on
(N, nv, nv) per iteration) and J^T lambda = g - tau_spring. The pairs share one constraint system:
a crank angle's own rows differ only in the cranks' and the swing ankle's targets and in the weld's
x (each stance foot stands at its own x; the row is p_foot - p_target, so a pair's residual is the
shared one plus x_shared - x_pair). The answers equal the one-angle path's to round-off
(``tests/test_spring_fit.py``).

Units: SI; angles [rad].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from pasibot_pin.constraints.system import STEP_LIMIT
from pasibot_pin.dynamics.spring_energy import AnkleSpring
from pasibot_pin.errors import ParameterError
from pasibot_pin.studies.methods.statics import StaticEquilibrium, StaticProblem

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot

MAX_NEWTON = 20
"""Newton iterations of a closure (the one-angle path's)."""
SECANT_STEPS = 30
"""Secant iterations (the one-angle path's)."""
CHUNK = 32
"""Pairs per batched row evaluation: larger products start BLAS threads, which on a busy machine cost
several times the CPU of the product (measured: 80 pairs 3.9 ms with threads, 0.3 ms without)."""


class _Pairs:
    """Every (spring, crank angle) pair's rows, as targets and weld offsets of one shared system."""

    def __init__(self, robot: PasibotRobot, springs: Sequence[AnkleSpring], thetas: np.ndarray, cache: dict):
        self.robot = robot
        problems = [[StaticProblem(robot, sp, float(th), cache) for th in thetas] for sp in springs]
        flat = [p for row in problems for p in row]
        self.cset = flat[0].cset
        if any(p.cset.labels != self.cset.labels for p in flat):
            raise ParameterError("static_equilibria: the crank angles must share one stance foot")
        keys = [round(float(th), 12) for th in thetas]
        anchors = np.array([cache[key][2].joint2_placement.translation[0] for key in keys])
        weld = next(label for label in self.cset.labels if label.endswith("_weld.x"))
        self.weld_x = self.cset.labels.index(weld)
        self.offset = np.tile(anchors[0] - anchors, len(springs))
        self.targets = np.array([p.targets for p in flat])
        self.q_level = np.array([p.q_level for p in flat])
        self.row = self.cset.nrows - 1
        ankles = list(flat[0].sim.ankles.values())
        self.ankles = ankles
        self.stiffness = np.repeat([sp.stiffness for sp in springs], len(thetas))
        self.rest = np.repeat([sp.rest_angle for sp in springs], len(thetas))

    def torque(self, pitch: np.ndarray, q: np.ndarray, idx: np.ndarray):
        """Hip-holding torques [N.m] of pairs ``idx`` at ``pitch`` from ``q``: (torque, q, ok)."""
        cset = self.cset
        targets = self.targets[idx].copy()
        targets[:, -1] = pitch
        q = q.copy()
        ok = np.ones(len(idx), dtype=bool)
        rows = self._rows(q, targets, idx)
        open_ = ~np.all(np.abs(rows.phi) < cset.tolerance, axis=1)
        for _ in range(MAX_NEWTON):
            if not np.any(open_):
                break
            step = _solve(rows.jac[open_], -rows.phi[open_])
            bad = ~np.all(np.isfinite(step), axis=1)
            largest = np.max(np.abs(np.where(bad[:, None], 0.0, step)), axis=1)
            step *= np.where(largest > STEP_LIMIT, STEP_LIMIT / np.maximum(largest, 1e-300), 1.0)[:, None]
            sel = np.nonzero(open_)[0]
            ok[sel[bad]] = False
            open_[sel[bad]] = False
            good = sel[~bad]
            q[good] += step[~bad]  # nq == nv, every joint Euclidean: integrate is a sum
            if not len(good):
                break
            part = self._rows(q[good], targets[good], idx[good])
            rows.phi[good], rows.jac[good] = part.phi, part.jac
            open_[good] = ~np.all(np.abs(part.phi) < cset.tolerance, axis=1)
        ok &= ~open_
        unit = np.zeros((len(idx), cset.nrows))
        unit[:, self.row] = 1.0
        x = _solve(rows.jac, unit)
        model, data = self.robot.model, self.robot.data
        hold = np.array([x[j].dot(pin.computeGeneralizedGravity(model, data, q[j])) for j in range(len(idx))])
        for i in self.ankles:
            hold -= x[:, i] * self.stiffness[idx] * ((math.pi / 2 - q[:, i]) - self.rest[idx])
        ok &= np.isfinite(hold)
        return hold, q, ok

    def _rows(self, q: np.ndarray, targets: np.ndarray, idx: np.ndarray):
        """The rows of pairs ``idx``, evaluated in chunks of :data:`CHUNK` pairs."""
        if len(idx) > CHUNK:
            parts = [
                self._rows(q[k : k + CHUNK], targets[k : k + CHUNK], idx[k : k + CHUNK])
                for k in range(0, len(idx), CHUNK)
            ]
            rows = parts[0]
            rows.phi = np.concatenate([p.phi for p in parts])
            rows.jac = np.concatenate([p.jac for p in parts])
            return rows
        rows = self.cset.evaluate(q, None, 0.0, targets)
        rows.phi[:, self.weld_x] += self.offset[idx]
        return rows


def _solve(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Batched square solves; a singular system gives a row of NaN instead of an error."""
    try:
        return np.linalg.solve(matrix, rhs[..., None])[..., 0]
    except np.linalg.LinAlgError:
        out = np.full(rhs.shape, np.nan)
        for k in range(len(rhs)):
            try:
                out[k] = np.linalg.solve(matrix[k], rhs[k])
            except np.linalg.LinAlgError:
                pass
        return out


def static_equilibria(
    robot: PasibotRobot,
    springs: Sequence[AnkleSpring],
    thetas: ArrayLike,
    search: float = math.radians(30.0),
    cache: dict | None = None,
) -> list:
    """:func:`~pasibot_pin.studies.methods.statics.static_equilibrium` of each spring, all pairs at once.

    Args:
        robot: the scenario's two-legged ``spring`` robot.
        springs: the ankle springs (``None`` is not accepted here: no spring is K_e = 0).
        thetas: right crank angles over one stance [rad] (one stance side).
        search: the secant's bound on |hip pitch| [rad].
        cache: the static solves' cache (shared with the one-angle path).

    Returns:
        One :class:`~pasibot_pin.studies.methods.statics.StaticEquilibrium` per spring.

    """
    thetas = np.asarray(thetas, dtype=float)
    cache = {} if cache is None else cache
    pairs = _Pairs(robot, springs, thetas, cache)
    n = len(pairs.targets)
    everyone = np.arange(n)
    p0, p1 = np.zeros(n), np.full(n, 1e-3)
    f0, q, alive = pairs.torque(p0, pairs.q_level, everyone)
    f1, q1, ok = pairs.torque(p1, q, everyone)
    alive &= ok
    q = q1
    running = alive.copy()
    for _ in range(SECANT_STEPS):
        running &= f1 != f0
        p2 = np.where(running, p1 - f1 * (p1 - p0) / np.where(running, f1 - f0, 1.0), p1)
        running &= np.abs(p2) <= search
        idx = np.nonzero(running)[0]
        if not len(idx):
            break
        p0[idx], f0[idx] = p1[idx], f1[idx]
        p1[idx] = p2[idx]
        f_new, q_new, ok = pairs.torque(p1[idx], q[idx], idx)
        f1[idx], q[idx] = f_new, q_new
        alive[idx[~ok]] = False
        running[idx[~ok]] = False
        running[idx] &= ~(np.abs(p1[idx] - p0[idx]) < 1e-12)
    done = alive & (np.abs(f1) < 1e-8) & (np.abs(p1) <= search)
    pitch, stiff = np.full(n, np.nan), np.full(n, np.nan)
    idx = np.nonzero(done)[0]
    if len(idx):
        eps = 1e-5
        both = np.concatenate((idx, idx))
        f_pm, _, ok = pairs.torque(np.concatenate((p1[idx] + eps, p1[idx] - eps)), np.vstack((q[idx], q[idx])), both)
        good = ok[: len(idx)] & ok[len(idx) :]
        idx = idx[good]
        fp, fm = f_pm[: len(good)][good], f_pm[len(good) :][good]
        pitch[idx], stiff[idx] = p1[idx], (fp - fm) / (2 * eps)
    found = ~np.isnan(pitch)
    m = len(thetas)
    return [
        StaticEquilibrium(thetas, pitch[k * m : (k + 1) * m], stiff[k * m : (k + 1) * m], found[k * m : (k + 1) * m])
        for k in range(len(springs))
    ]
