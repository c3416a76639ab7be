"""Foot-ground contact: heel and toe forces, centre of pressure, friction needed (QP, proxsuite).

The inverse dynamics (:mod:`pasibot_pin.dynamics.inverse`) holds the stance foot with a planar weld
and returns the ground's wrench on the foot at the ankle, world axes: Fx, Fz [N] and the
counter-clockwise moment My [N.m] (the weld's in-plane rows x, z, pitch; the pitch is about
-y). With 4 actuators for 4 degrees of freedom that wrench is unique, so any set of contact
forces that reproduces the prescribed motion must add up to it. This module replaces the
weld by two point contacts, heel and toe, and asks whether the ground can supply the wrench:

* each contact is unilateral (normal force >= 0) with a Coulomb cone, linearised (in the
  plane the cone is exactly two half-planes, so the linearisation is exact),
* the distribution is a dense QP (proxsuite): minimise 1/2 |f|^2 + reg/2 |f|^2 subject to the
  3 wrench rows (equalities) and the cone rows (inequalities). The normal forces are fixed by
  Fz and My; the QP chooses the split of the tangential force,
* when the QP is infeasible (a fall or a slip), a second QP finds the nearest wrench the
  contacts can supply (forces first, then the moment: a tipping foot stands on its edge), and
  the sample is flagged with the reason: ``lift-off`` (the foot is
  pulled up), ``tip-toe`` / ``tip-heel`` (the CoP leaves the sole past the toe / heel: the
  foot rotates about that edge), ``slip`` (|F_t| > mu F_n).

The centre of pressure (CoP) comes from the wrench alone: with the sole through the ankle,
tangent t and normal n, the moment of the contact forces about the ankle is sum s_i (n.f_i),
so s_cop = My / F_n along the sole from the ankle [m]. Units: SI.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import pinocchio as pin
import proxsuite

from pasibot_pin.dynamics.floor.ground import check_mu
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import design_robot
from pasibot_pin.model.params import SOLE_FLOOR_MU
from pasibot_pin.model.scenarios import get_preset, get_scenario
from pasibot_pin.reprs import short_repr

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot

QP_EPS: float = 1e-12
"""Absolute accuracy asked of proxsuite [N, N.m]."""

FEASIBILITY_TOL: float = 1e-9
"""Relative tolerance on the wrench rows and the cone rows when a QP solution is checked."""

CONE_TOL: float = 1e-12
"""A force of :func:`cone_qp` may lie outside its cone by this much, relative to the largest force [-] (round-off)."""

REGULARISATION: float = 1e-9
"""Relative weight added to the Hessian (the 'regularised force norm') [-]."""

FAILURES: tuple[str, ...] = ("lift-off", "tip-heel", "tip-toe", "slip")
"""Reasons a sample can fail, in reporting order."""


MIN_SOLE_REACH = 1e-4
"""A what-if sole's heel and toe are each at least this far from the ankle [m] (a shorter sole has no
lever for its centre of pressure, and its contact problem no interior)."""


def check_sole(sole, name: str = "parameter 'sole'") -> tuple[float, float] | None:
    """``sole`` (s_heel, s_toe) [m] if ``None`` or on either side of the ankle by :data:`MIN_SOLE_REACH`.

    Raises:
        ParameterError: naming ``name``, before any work.

    """
    if sole is None:
        return None
    if not (len(sole) == 2 and sole[0] <= -MIN_SOLE_REACH and sole[1] >= MIN_SOLE_REACH):
        raise ParameterError(
            f"{name} must be (heel <= -{MIN_SOLE_REACH:g} m, toe >= {MIN_SOLE_REACH:g} m): heel and toe "
            f"on either side of the ankle, got {tuple(sole)!r}"
        )
    return float(sole[0]), float(sole[1])


@dataclass(frozen=True)
class ContactPoint2D:
    """One sample's contact distribution.

    Attributes:
        forces: (2, 2) ground force on the foot at heel (row 0) and toe (row 1), world (x, z) [N].
        feasible: True when the contacts reproduce the wrench inside their cones.
        status: proxsuite's status of the distribution QP.
        reasons: failure reasons (subset of :data:`FAILURES`), empty when feasible.
        s_cop: CoP along the sole from the ankle (forward positive) demanded by the wrench [m]
            (``inf``/``-inf`` when F_n <= 0).
        margin: signed distance of the CoP to the nearer sole edge [m] (negative: outside).
        mu_needed: |F_t| / F_n, the friction coefficient the wrench needs [-] (``inf`` if F_n <= 0).
        residual: wrench the contacts cannot supply (demanded minus supplied) Fx, Fz [N], My [N.m].

    """

    forces: np.ndarray
    feasible: bool
    status: str
    reasons: tuple[str, ...]
    s_cop: float
    margin: float
    mu_needed: float
    residual: np.ndarray


def _qp(h: np.ndarray, g: np.ndarray, a_eq, b_eq, c_in: np.ndarray, u_in: np.ndarray):
    n = h.shape[0]
    neq = 0 if a_eq is None else a_eq.shape[0]
    qp = proxsuite.proxqp.dense.QP(n, neq, c_in.shape[0])
    qp.settings.eps_abs = QP_EPS
    qp.settings.eps_rel = 0.0
    qp.settings.verbose = False
    qp.settings.max_iter = 1000
    lower = np.full(c_in.shape[0], -1e20)
    qp.init(h, g, a_eq, b_eq, c_in, lower, u_in)
    qp.solve()
    return np.array(qp.results.x), qp.results.info.status


def _cone_face_bases(t: np.ndarray, n: np.ndarray, mu: float) -> tuple[np.ndarray, np.ndarray]:
    """Bases of the 16 pairs of faces of the heel's and the toe's friction cones, padded to (16, 4, 4).

    A point's cone {f: |t.f| <= mu n.f} has four faces: its inside (basis: the plane), its two edges (n +- mu t)
    and its apex (none). Returns the bases (columns beyond a face's own are zero) and, per pair, 1 on the
    diagonal where a column is padding (0 elsewhere): each pair's reduced system is square and regular.
    """
    zero = np.zeros(2)
    faces = np.array(
        [
            [[1.0, 0.0], [0.0, 1.0]],
            np.column_stack((n + mu * t, zero)),
            np.column_stack((n - mu * t, zero)),
            np.zeros((2, 2)),
        ]
    )
    used = np.array([[1.0, 1.0], [1.0, 0.0], [1.0, 0.0], [0.0, 0.0]])  # the face's own columns
    bases = np.zeros((4, 4, 4, 4))
    bases[:, :, :2, :2] = faces[:, None]
    bases[:, :, 2:, 2:] = faces[None, :]
    pad = 1.0 - np.concatenate((np.repeat(used[:, None], 4, 1), np.repeat(used[None, :], 4, 0)), axis=2)
    return bases.reshape(16, 4, 4), pad.reshape(16, 4)


def cone_qp(hess: np.ndarray, g: np.ndarray, t: np.ndarray, n: np.ndarray, mu: float) -> np.ndarray:
    """The least 1/2 f^T H f + g^T f over heel and toe forces f = [f_heel, f_toe] (4,), each in its friction cone.

    Exact, by the cones' faces: the minimum lies inside one face of each point's cone (its inside, an edge or
    the apex: 16 pairs), where it is the minimum over that face's span. Every pair's minimum is solved at once
    (sixteen 4 x 4 solves, one call); of those in both cones (to :data:`CONE_TOL`) the least is the answer
    (H is positive definite: one minimum, and it is one of them).

    Args:
        hess: H (4, 4), symmetric positive definite.
        g: (4,).
        t: the ground's tangent (2,) (unit).
        n: its normal (2,) (unit).
        mu: friction coefficient [-].

    Returns:
        f (4,) [N].

    """
    bases, pad = _cone_face_bases(t, n, mu)
    reduced = np.einsum("kia,ij,kjb->kab", bases, hess, bases) + pad[:, :, None] * np.eye(4)
    p = np.linalg.solve(reduced, -np.einsum("kia,i->ka", bases, g)[:, :, None])[:, :, 0]
    f = np.einsum("kia,ka->ki", bases, p)  # (16, 4): each pair's minimum
    rows = np.array([t - mu * n, -t - mu * n, -n])  # each <= 0 inside the cone (as distribute's rows)
    outside = np.max(np.einsum("rj,kpj->kpr", rows, f.reshape(16, 2, 2)), axis=(1, 2))
    inside = outside <= CONE_TOL * (1.0 + np.abs(f).max(axis=1))
    cost = 0.5 * np.einsum("ki,ij,kj->k", f, hess, f) + f @ g
    return f[np.flatnonzero(inside)[np.argmin(cost[inside])]]  # the apexes' pair (f = 0) is always inside


def cop_metrics(wrench, s_heel: float, s_toe: float, pitch=0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Centre of pressure, its margin inside the sole and the friction needed, for many wrenches.

    Args:
        wrench: (N, 3) ground wrenches on the foot at the ankle, world axes: Fx, Fz [N], CCW moment [N.m].
        s_heel: heel position along the sole from the ankle [m] (negative: behind).
        s_toe: toe position along the sole from the ankle [m].
        pitch: sole pitch in the world (CCW) [rad], a float or (N,).

    Returns:
        (s_cop [m] along the sole from the ankle, margin [m]: signed distance of the CoP to the
        nearer sole edge, negative outside; mu_needed = |F_t| / F_n [-]), each (N,). A wrench
        that pulls the foot off the ground (F_n <= 0) has margin -inf and mu_needed inf.

    """
    w = np.atleast_2d(np.asarray(wrench, dtype=float))
    pitch = np.asarray(pitch, dtype=float)
    f_n = -np.sin(pitch) * w[:, 0] + np.cos(pitch) * w[:, 1]
    f_t = np.cos(pitch) * w[:, 0] + np.sin(pitch) * w[:, 1]
    pushing = f_n > 0
    safe = np.where(pushing, f_n, 1.0)
    off = np.where(w[:, 2] != 0, np.copysign(np.inf, w[:, 2]), -np.inf)
    s_cop = np.where(pushing, w[:, 2] / safe, off)
    margin = np.where(pushing, np.minimum(s_cop - s_heel, s_toe - s_cop), -np.inf)
    mu_needed = np.where(pushing, np.abs(f_t) / safe, np.inf)
    return s_cop, margin, mu_needed


def _check_distribute(wrench, s_heel: float, s_toe: float, mu: float, regularisation: float) -> np.ndarray:
    """The wrench as a (3,) array once :func:`distribute`'s arguments are checked (ValueError naming one)."""
    w = np.asarray(wrench, dtype=float).reshape(-1)
    if w.shape != (3,) or not np.all(np.isfinite(w)):
        raise ParameterError(f"parameter 'wrench' must be 3 finite numbers (Fx, Fz, My), got {wrench!r}")
    check_mu(mu)
    if not (math.isfinite(s_heel) and math.isfinite(s_toe) and s_heel < s_toe):
        raise ParameterError(f"parameters 's_heel' < 's_toe' must be finite [m], got {s_heel!r}, {s_toe!r}")
    if not (math.isfinite(regularisation) and regularisation >= 0):
        raise ParameterError(f"parameter 'regularisation' must be >= 0, got {regularisation!r}")
    return w


def _heel_toe_rows(s_heel: float, s_toe: float, mu: float, t: np.ndarray, n: np.ndarray):
    """The QP's rows on f = [fx_h, fz_h, fx_t, fz_t]: equalities (sum fx, sum fz, moment), cone inequalities."""
    a_eq = np.array(
        [
            [1.0, 0.0, 1.0, 0.0],
            [0.0, 1.0, 0.0, 1.0],
            [s_heel * n[0], s_heel * n[1], s_toe * n[0], s_toe * n[1]],
        ]
    )
    c_rows = []
    for k in range(2):
        for sign in (1.0, -1.0):  # sign * t.f - mu n.f <= 0
            row = np.zeros(4)
            row[2 * k : 2 * k + 2] = sign * t - mu * n
            c_rows.append(row)
        row = np.zeros(4)
        row[2 * k : 2 * k + 2] = -n  # n.f >= 0
        c_rows.append(row)
    return a_eq, np.array(c_rows)


def _failure_reasons(
    f_n: float, s_cop: float, margin: float, mu_needed: float, s_heel: float, s_toe: float, mu: float, scale: float
) -> list[str]:
    """Why no heel/toe split holds the wrench: lift-off, tipping over the heel or toe, slipping."""
    reasons: list[str] = []
    if f_n <= FEASIBILITY_TOL * scale:
        reasons.append("lift-off")
    else:
        if s_cop < s_heel:
            reasons.append("tip-heel")
        if s_cop > s_toe:
            reasons.append("tip-toe")
        if mu_needed > mu:
            reasons.append("slip")
    if not reasons:  # at the boundary within tolerance: name the binding condition
        reasons.append("slip" if mu_needed >= mu * (1 - 1e-6) else ("tip-toe" if margin >= 0 else "tip-heel"))
    return reasons


def distribute(
    wrench: Sequence[float],
    s_heel: float,
    s_toe: float,
    mu: float,
    pitch: float = 0.0,
    regularisation: float = REGULARISATION,
) -> ContactPoint2D:
    """Distribute a planar ground wrench on the foot onto heel and toe contacts (proxsuite QP).

    Args:
        wrench: ground wrench on the foot at the ankle, world axes: Fx, Fz [N], CCW moment [N.m].
        s_heel: heel position along the sole from the ankle [m] (negative: behind).
        s_toe: toe position along the sole from the ankle [m] (positive: ahead).
        mu: Coulomb friction coefficient [-].
        pitch: sole pitch in the world (CCW) [rad]; the ground normal is the sole's normal.
        regularisation: relative weight of the extra force-norm term [-].

    Returns:
        A :class:`ContactPoint2D`.

    Raises:
        ValueError: a non-finite wrench, a sole whose heel is not behind its toe, a bad mu.

    """
    w = _check_distribute(wrench, s_heel, s_toe, mu, regularisation)
    mu = float(mu)
    t = np.array([math.cos(pitch), math.sin(pitch)])
    n = np.array([-math.sin(pitch), math.cos(pitch)])
    a_eq, c_in = _heel_toe_rows(s_heel, s_toe, mu, t, n)
    u_in = np.zeros(c_in.shape[0])
    x, status = _qp((1.0 + regularisation) * np.eye(4), np.zeros(4), a_eq, w, c_in, u_in)
    scale = max(float(np.linalg.norm(w[:2])), abs(w[2]) / (s_toe - s_heel), 1.0)
    eq_ok = bool(np.all(np.isfinite(x))) and np.max(np.abs(a_eq @ x - w)) <= FEASIBILITY_TOL * scale * 10
    in_ok = bool(np.all(np.isfinite(x))) and np.max(c_in @ x) <= FEASIBILITY_TOL * scale * 10
    feasible = status == proxsuite.proxqp.QPSolverOutput.PROXQP_SOLVED and eq_ok and in_ok
    if not feasible:
        # best effort: the forces first, then the moment (min |W (A f - w)|^2 + reg |f|^2 s.t. cones).
        # A tipping foot then stands on its edge with the full normal force and the residual is the
        # unbalanced tipping moment; a slipping one gives mu F_n and the residual is the missing friction.
        weights = np.diag([1.0, 10.0, 1e-3 / (s_toe - s_heel)])  # Fz, then Fx, then My
        aw = weights @ a_eq
        hess = aw.T @ aw + max(regularisation, 1e-12) * np.eye(4)
        x = cone_qp(hess, -aw.T @ (weights @ w), t, n, mu)
    forces = x.reshape(2, 2)
    s_cop, margin, mu_needed = (float(x[0]) for x in cop_metrics(w[None, :], s_heel, s_toe, pitch))
    reasons = [] if feasible else _failure_reasons(float(n @ w[:2]), s_cop, margin, mu_needed, s_heel, s_toe, mu, scale)
    return ContactPoint2D(
        forces=forces,
        feasible=bool(feasible),
        status=str(status).rsplit(".", 1)[-1],
        reasons=tuple(reasons),
        s_cop=float(s_cop),
        margin=float(margin),
        mu_needed=float(mu_needed),
        residual=w - a_eq @ x,
    )


@dataclass
class ContactResult:
    """Heel/toe contact along a motion, one row per sample.

    Attributes:
        t: time [s].
        theta: stance crank angle [rad].
        stance: stance side per sample.
        mu: friction coefficient used [-].
        wrench: ground wrench on the stance foot at its ankle: Fx, Fz [N], CCW moment [N.m].
        heel_force, toe_force: (N x 2) ground force at heel / toe, world (x, z) [N].
        feasible: (N,) bool.
        reasons: failure reasons per sample (empty tuple when feasible).
        status: proxsuite status per sample.
        s_cop: CoP along the sole from the stance ankle [m].
        cop_x: world x of the CoP [m] (the ankle's x + s_cop cos(pitch)).
        ankle_x: world x of the stance ankle [m].
        s_heel, s_toe: heel and toe along the sole from the ankle [m].
        margin: signed distance of the CoP to the nearer edge [m].
        mu_needed: |F_t| / F_n [-].
        residual: (N x 3) wrench the contacts cannot supply.

    """

    __repr__ = short_repr

    t: np.ndarray
    theta: np.ndarray
    stance: list[str]
    mu: float
    wrench: np.ndarray
    heel_force: np.ndarray
    toe_force: np.ndarray
    feasible: np.ndarray
    reasons: list[tuple[str, ...]]
    status: list[str]
    s_cop: np.ndarray
    cop_x: np.ndarray
    ankle_x: np.ndarray
    s_heel: np.ndarray
    s_toe: np.ndarray
    margin: np.ndarray
    mu_needed: np.ndarray
    residual: np.ndarray
    extra: dict[str, Any] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.t)

    @property
    def all_feasible(self) -> bool:
        """True when every sample is feasible."""
        return bool(np.all(self.feasible))

    def first_failure(self) -> tuple[float, float, tuple[str, ...]] | None:
        """(time [s], stance crank angle [rad], reasons) of the first infeasible sample, or None."""
        bad = np.flatnonzero(~self.feasible)
        if bad.size == 0:
            return None
        k = int(bad[0])
        return float(self.t[k]), float(self.theta[k]), self.reasons[k]

    def tip_events(self) -> list[dict[str, float | str]]:
        """Where the CoP crosses a sole edge: one dict per crossing (linear interpolation).

        Keys: ``edge`` (heel/toe), ``direction`` (``leaves`` / ``enters`` the sole), ``t`` [s],
        ``theta`` [rad], ``x`` (world x of the edge, the pivot the foot would rotate about) [m].
        Only crossings within one stance phase count (a stance swap is not a crossing).
        """
        events: list[dict[str, float | str]] = []
        for edge, dist in (("heel", self.s_cop - self.s_heel), ("toe", self.s_toe - self.s_cop)):
            for k in range(len(self.t) - 1):
                if self.stance[k] != self.stance[k + 1]:
                    continue
                d0, d1 = dist[k], dist[k + 1]
                if not (np.isfinite(d0) and np.isfinite(d1)) or (d0 >= 0) == (d1 >= 0):
                    continue
                r = d0 / (d0 - d1)
                s_edge = self.s_heel[k] if edge == "heel" else self.s_toe[k]
                events.append(
                    {
                        "edge": edge,
                        "direction": "leaves" if d1 < 0 else "enters",
                        "t": float(self.t[k] + r * (self.t[k + 1] - self.t[k])),
                        "theta": float(self.theta[k] + r * (self.theta[k + 1] - self.theta[k])),
                        "x": float(self.ankle_x[k] + s_edge),
                    }
                )
        return sorted(events, key=lambda e: e["t"])

    def sole_needed(self) -> tuple[float, float]:
        """(heel, toe) extents the CoP demands: min and max of s_cop over samples with F_n > 0 [m]."""
        ok = np.isfinite(self.s_cop)
        if not ok.any():
            return (math.nan, math.nan)
        return float(np.min(self.s_cop[ok])), float(np.max(self.s_cop[ok]))

    def summary(self) -> str:
        """A few lines: feasibility, first failure, CoP range vs the sole, friction needed."""
        n_ok = int(np.sum(self.feasible))
        lines = [f"contact (mu = {self.mu:g}): {n_ok}/{len(self)} samples feasible"]
        first = self.first_failure()
        if first is not None:
            t, th, why = first
            lines.append(
                f"  first failure at t = {t:.4f} s (stance crank {math.degrees(th):.1f} deg): {', '.join(why)}"
            )
        heel, toe = self.sole_needed()
        lines.append(
            f"  CoP demanded from {heel * 1e3:+.1f} to {toe * 1e3:+.1f} mm along the sole "
            f"(sole {self.s_heel[0] * 1e3:+.1f} .. {self.s_toe[0] * 1e3:+.1f} mm); "
            f"minimum margin {np.min(self.margin) * 1e3:+.1f} mm"
        )
        finite = self.mu_needed[np.isfinite(self.mu_needed)]
        if finite.size:
            lines.append(f"  friction needed: max |Ft|/Fn = {np.max(finite):.4f}")
        for ev in self.tip_events():
            lines.append(
                f"  CoP {ev['direction']} the sole at the {ev['edge']} at t = {ev['t']:.4f} s "
                f"(stance crank {math.degrees(float(ev['theta'])):.1f} deg, x = {ev['x']:.4f} m)"
            )
        return "\n".join(lines)

    def columns(self) -> dict[str, np.ndarray]:
        """CSV columns (SI units)."""
        return {
            "t": self.t,
            "theta": self.theta,
            "stance_right": np.array([1.0 if s == "right" else 0.0 for s in self.stance]),
            "Fx": self.wrench[:, 0],
            "Fz": self.wrench[:, 1],
            "My": self.wrench[:, 2],
            "heel_Fx": self.heel_force[:, 0],
            "heel_Fz": self.heel_force[:, 1],
            "toe_Fx": self.toe_force[:, 0],
            "toe_Fz": self.toe_force[:, 1],
            "feasible": self.feasible.astype(float),
            "s_cop": self.s_cop,
            "cop_x": self.cop_x,
            "margin": self.margin,
            "mu_needed": self.mu_needed,
        }


def sole_geometry(robot: PasibotRobot, q: np.ndarray, side: str) -> tuple[float, float, float, float, float]:
    """(ankle x, ankle z, pitch, s_heel, s_toe) of ``side``'s sole at q [m, rad].

    Heel and toe come from the frames ``<side>_heel`` / ``<side>_toe``, projected on the
    foot frame's x axis (the sole passes through the ankle frame ``<side>_foot``).
    """
    model, data = robot.model, robot.data
    pin.framesForwardKinematics(model, data, q)
    foot = data.oMf[robot.frame_id(f"{side}_foot")]
    rot = foot.rotation
    pitch = math.atan2(rot[2, 0], rot[0, 0])
    tangent = rot[:, 0]
    s = {}
    for end in ("heel", "toe"):
        s[end] = float(tangent @ (data.oMf[robot.frame_id(f"{side}_{end}")].translation - foot.translation))
    return float(foot.translation[0]), float(foot.translation[2]), pitch, s["heel"], s["toe"]


def contact_along(robot: PasibotRobot, result, mu: float, sole: tuple[float, float] | None = None) -> ContactResult:
    """Heel/toe contact along an inverse-dynamics result.

    Args:
        robot: a two-legged robot with the same kinematics as the result's (frames
            ``<side>_foot``, ``<side>_heel``, ``<side>_toe``).
        result: anything with ``t``, ``theta``, ``q`` (N x nq), ``stance`` (N sides) and
            ``ground`` (N x 3: Fx, Fz [N], CCW moment at the stance ankle [N.m]), e.g. a
            :class:`~pasibot_pin.dynamics.inverse.TorqueResult`.
        mu: Coulomb friction coefficient [-].
        sole: override (s_heel, s_toe) along the sole from the ankle [m] (what-if: a longer foot).

    Returns:
        A :class:`ContactResult`; never raises for an infeasible contact (it is flagged).

    """
    mu = check_mu(mu)
    if not robot.floating:
        raise ParameterError("contact_along needs the two-legged robot (its stance foot carries the ground wrench)")
    ground = np.asarray(result.ground, dtype=float)
    n = len(result.t)
    if ground.shape != (n, 3) or len(result.q) != n or len(result.stance) != n:
        raise ParameterError("parameter 'result': t, q, stance and ground (N x 3) must have one row per sample")
    check_sole(sole)
    arrays: dict[str, Any] = {
        k: np.zeros(n) for k in ("s_cop", "cop_x", "ankle_x", "s_heel", "s_toe", "margin", "mu_needed")
    }
    heel_f, toe_f, resid = np.zeros((n, 2)), np.zeros((n, 2)), np.zeros((n, 3))
    feasible = np.zeros(n, dtype=bool)
    reasons, status = [], []
    for k in range(n):
        ax, _az, pitch, s_h, s_t = sole_geometry(robot, np.asarray(result.q[k]), result.stance[k])
        if sole is not None:
            s_h, s_t = float(sole[0]), float(sole[1])
        sol = distribute(ground[k], s_h, s_t, mu, pitch)
        heel_f[k], toe_f[k] = sol.forces
        feasible[k] = sol.feasible
        reasons.append(sol.reasons)
        status.append(sol.status)
        resid[k] = sol.residual
        arrays["s_cop"][k], arrays["margin"][k], arrays["mu_needed"][k] = sol.s_cop, sol.margin, sol.mu_needed
        arrays["ankle_x"][k], arrays["s_heel"][k], arrays["s_toe"][k] = ax, s_h, s_t
        arrays["cop_x"][k] = ax + sol.s_cop * math.cos(pitch) if math.isfinite(sol.s_cop) else sol.s_cop
    return ContactResult(
        t=np.asarray(result.t, dtype=float),
        theta=np.asarray(result.theta, dtype=float),
        stance=list(result.stance),
        mu=mu,
        wrench=ground,
        heel_force=heel_f,
        toe_force=toe_f,
        feasible=feasible,
        reasons=reasons,
        status=status,
        residual=resid,
        **arrays,
    )


CONTACT_MU: float = SOLE_FLOOR_MU
"""The default sole-ground Coulomb friction of the contact study [-] (the one of the floor and the MJCF)."""

CONTACT_SAMPLES: int = 60
"""The default crank samples of one right stance, theta in [pi/2, 3 pi/2) (one definition for the
report, the command line and the library)."""


def scenario_contact(
    name: str,
    preset: str = "default",
    mu: float = CONTACT_MU,
    samples: int = CONTACT_SAMPLES,
    sole: tuple[float, float] | None = None,
    variant: str = "spring",
):
    """Inverse dynamics and heel/toe contact of one seed scenario over one right stance.

    Args:
        name: scenario name (:data:`pasibot_pin.model.scenarios.SCENARIOS`): crank speed, body mass and COM.
        preset: modelling preset of the ``spring`` variant (masses, swing foot); accelerations are exact.
        mu: Coulomb friction coefficient [-].
        samples: crank samples over theta in [pi/2, 3 pi/2) (at 3 pi/2 the other foot takes over).
        sole: what-if (s_heel, s_toe) along the sole from the ankle [m].
        variant: ``spring`` or ``parallel`` (any variant: the same inverse dynamics; the
            preset's masses with the scenario's body mass and COM).

    Returns:
        (the inverse-dynamics result, :class:`ContactResult`).

    """
    from pasibot_pin.dynamics.inverse import inverse_dynamics  # deferred: keeps the CLI's start fast
    from pasibot_pin.model.scenario_robots import scenario_robot  # deferred: keeps the CLI's start fast

    if samples < 2:
        raise ParameterError(f"parameter 'samples' must be >= 2, got {samples!r}")
    scenario = get_scenario(name)
    thetas = np.linspace(math.pi / 2, 3 * math.pi / 2, int(samples), endpoint=False)
    choices = get_preset(preset).with_(accelerations="exact", fit_thetas=None)
    robot = scenario_robot(scenario, choices, variant)
    torques = inverse_dynamics(robot, thetas, scenario.omega, swing_foot=choices.swing_foot, stance="right")
    return torques, contact_along(robot, torques, mu, sole=sole)


def design_contact(design, mu: float = CONTACT_MU, samples: int = CONTACT_SAMPLES, sole=None):
    """:func:`scenario_contact` for a :class:`~pasibot_pin.model.design.Design`: its robot, speed and motors.

    Returns:
        (the inverse-dynamics result, :class:`ContactResult`).

    """
    from pasibot_pin.dynamics.inverse import inverse_dynamics  # deferred: keeps the CLI's start fast

    if samples < 2:
        raise ParameterError(f"parameter 'samples' must be >= 2, got {samples!r}")
    robot = design_robot(design, 2)
    thetas = np.linspace(math.pi / 2, 3 * math.pi / 2, int(samples), endpoint=False)
    torques = inverse_dynamics(robot, thetas, design.omega, stance="right", motors=design.motors)
    return torques, contact_along(robot, torques, mu, sole=sole)
