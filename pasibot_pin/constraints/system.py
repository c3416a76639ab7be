"""THE constraint system of a robot: residual, Jacobian, drift, projections and the KKT solves.

Every closed-loop computation of the package goes through :class:`ConstraintSystem`: the
loop closures at the cut joints, the stance-foot weld, prescribed (possibly time-dependent)
coordinates such as the cranks' theta0 + omega t or a held hip, frame pitches (a level swing
foot) and motor couplings (one motor for both cranks: q_L - q_R - pi = 0). This module is
the only one that calls Pinocchio's Jacobian algorithms; :mod:`.pinocchio_models` the only one
that calls its constraint API.

Rows, in order (``labels``):

* each constraint model: x and z of p1 - p2 (world axes) for a point coincidence, plus the
  pitch difference for a weld; the out-of-plane rows are identically zero and dropped, so J
  has full row rank away from singular poses;
* each scalar row: a linear combination of coordinates (:class:`CoordinateRow`) or a frame's
  pitch (:class:`PitchRow`) minus its target, offset + rate t.

With Phi(q, t) the rows, J = dPhi/dq, the drift J_dot v (the rows' second time derivative at
zero joint acceleration) and Phi_t = dPhi/dt:

* ``project``: Newton on Phi(q, t) = 0 (square: exact solve; otherwise minimum-norm or
  minimum-M-norm corrections);
* ``velocity``: J v = -Phi_t (square);  ``acceleration``: J a = -J_dot v (square);
* ``forward_dynamics``: [M J^T; J 0][a; mu] = [tau - h; -J_dot v], lambda = -mu;
* ``impulse``: [M J^T; J 0][v+; mu] = [M v-; -Phi_t] (inelastic impact, velocity projection).

The model is planar (x-z plane, every rotation about y), so the angular velocity of every
body is along y: the point rows use that. Pitch is counter-clockwise seen from the right
(about -y). Units: SI, angles [rad].
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from pasibot_pin.constraints.evaluation import RowSystem
from pasibot_pin.constraints.rows import (  # noqa: F401 (the rows' names, re-exported where they always were)
    ANGLE_TOL,
    RELATIVE_TOL,
    STEP_LIMIT,
    CoordinateRow,
    PitchRow,
    Projection,
    Rows,
    ScalarRow,
    coordinate,
    coupling,
    frame_rows,
    planar_kinematics,
    planar_pitch,
)
from pasibot_pin.constraints.solves import (  # noqa: F401 (re-exported)
    frame_jacobian,
    kkt_solve,
    split_torques,
    square_solve,
    square_solve_many,
    symmetric_mass_matrix,
)
from pasibot_pin.errors import ClosureError, ParameterError, SingularPoseError


class ConstraintSystem(RowSystem):
    """The rows of :class:`~pasibot_pin.constraints.evaluation.RowSystem` and the solves on them.

    Projections (Newton on Phi = 0, one sample or a batch), velocities and accelerations on the
    manifold, and the dynamics on the same rows (the KKT forward dynamics and the impulse).
    Args as :class:`~pasibot_pin.constraints.evaluation.RowSystem`.
    """

    # ---- projections
    def project(
        self,
        q: np.ndarray,
        t: float = 0.0,
        targets: ArrayLike | None = None,
        metric: str = "euclidean",
        max_iter: int = 50,
    ) -> np.ndarray:
        """Newton onto Phi(q, t) = 0 from ``q``: the closed configuration (:meth:`project_rows`'s ``q``)."""
        return self.project_rows(q, t, targets, metric, max_iter).q

    def project_rows(
        self,
        q: np.ndarray,
        t: float = 0.0,
        targets: ArrayLike | None = None,
        metric: str = "euclidean",
        max_iter: int = 50,
    ) -> Projection:
        """Newton onto Phi(q, t) = 0 from ``q``, with the rows at the answer.

        Nothing is stored on the system (it is cached and shared): everything the projection
        computed is in the returned :class:`Projection`.

        Args:
            q: start configuration.
            t: time [s].
            targets: the scalar rows' targets instead of offset + rate t.
            metric: ``euclidean`` (minimum-norm corrections; exact for a square system) or
                ``mass`` (minimum M-norm corrections, a KKT solve: the simulator's projection).
            max_iter: iteration limit.

        Returns:
            :class:`Projection`: q with every row below :attr:`tolerance`, the rows evaluated
            there, and the largest residual at the start.

        Raises:
            ClosureError: no convergence (naming the worst row).
            SingularPoseError: the Jacobian lost rank on the way.

        """
        q = np.array(q, dtype=float)
        rows: Rows | None = None
        initial = 0.0
        for k in range(max_iter):
            rows = self.evaluate(q, None, t, targets)
            error = np.abs(rows.phi)
            if k == 0:
                initial = float(error.max()) if self.nrows else 0.0
            if (error < self.tolerance).all():
                return Projection(q, rows, initial)
            step = self._newton_step(q, rows, metric)
            largest = np.abs(step).max()
            if largest > STEP_LIMIT:
                step *= STEP_LIMIT / largest
            q = pin.integrate(self.model, q, step)
        if rows is None:
            raise ParameterError(f"parameter 'max_iter' must be >= 1, got {max_iter!r}")
        worst = int(np.argmax(np.abs(rows.phi) / self.tolerance))
        raise ClosureError(
            f"loop closure failed: constraint {self.labels[worst]} keeps a residual of {abs(rows.phi[worst]):.3e} "
            f"after {max_iter} Newton iterations at t = {t:.4f} s; the loop cannot assemble there"
        )

    def project_many(self, q: np.ndarray, targets: np.ndarray, max_iter: int = 50) -> tuple[np.ndarray, Rows]:
        """Newton onto Phi = 0 for a batch of samples at once (square systems, planar kinematics).

        Each sample iterates exactly as :meth:`project` would from its own start, and stops once
        all its rows are below :attr:`tolerance`; the batch shares the kinematic evaluations and
        the factorisations (one ``np.linalg.solve`` on (N, m, m) per iteration).

        Args:
            q: starting configurations (N, nq).
            targets: the scalar rows' targets per sample (N, n_scalars) or shared (n_scalars,).
            max_iter: iteration limit.

        Returns:
            (q, rows): the closed configurations (N, nq) and the rows evaluated there (J (N, m, nv)).

        Raises:
            ValueError: no convergence or a singular pose, naming the first failing sample.

        """
        q = np.array(q, dtype=float)
        if q.ndim != 2 or self._planar_ends is None or self.nrows != self.model.nv:
            raise ParameterError("project_many needs a batch (N, nq) and a square planar constraint system")
        targets = np.broadcast_to(np.asarray(targets, dtype=float), (len(q), len(self.scalars)))
        rows = self.evaluate(q, None, 0.0, targets)
        for _ in range(max_iter):
            open_ = np.any(np.abs(rows.phi) >= self.tolerance, axis=1)
            if not np.any(open_):
                return q, rows
            try:
                step = np.linalg.solve(rows.jac[open_], -rows.phi[open_][:, :, None])[:, :, 0]
            except np.linalg.LinAlgError as err:
                raise SingularPoseError("closure Newton: singular pose, the constraint Jacobian lost rank") from err
            largest = np.max(np.abs(step), axis=1, keepdims=True)
            step *= np.minimum(1.0, STEP_LIMIT / np.maximum(largest, 1e-300))
            q[open_] += step  # nq == nv and every joint is Euclidean: integrate is a sum
            part = self.evaluate(q[open_], None, 0.0, targets[open_])
            rows.phi[open_], rows.jac[open_] = part.phi, part.jac
        k = int(np.argmax(np.any(np.abs(rows.phi) >= self.tolerance, axis=1)))
        worst = int(np.argmax(np.abs(rows.phi[k]) / self.tolerance))
        raise ClosureError(
            f"loop closure failed: constraint {self.labels[worst]} keeps a residual of {abs(rows.phi[k, worst]):.3e} "
            f"after {max_iter} Newton iterations (sample {k}, targets {np.round(targets[k], 6).tolist()}); "
            "the loop cannot assemble there"
        )

    def motion_many(self, q: np.ndarray, rates: np.ndarray, accelerations: np.ndarray, jac: np.ndarray | None = None):
        """(v, a, J) for a batch of configurations on the manifold (square system).

        Args:
            q: configurations (N, nq) on the manifold.
            rates: the scalar rows' rates (N, n_scalars) or (n_scalars,) [rad/s, m/s].
            accelerations: their second derivatives, same shapes [rad/s^2, m/s^2].
            jac: J at ``q`` (N, m, nv) if already known (from :meth:`project_many`).

        """
        jac = self.evaluate(q).jac if jac is None else jac
        n0, shape = self.n_constraint_rows, (len(q), self.nrows)
        rhs = np.zeros(shape)
        rhs[:, n0:] = rates
        v = square_solve_many(jac, rhs, "velocity")
        rows = self.evaluate(q, v)
        rhs = -rows.drift
        rhs[:, n0:] += accelerations
        return v, square_solve_many(rows.jac, rhs, "acceleration"), rows.jac

    def _newton_step(self, q: np.ndarray, rows: Rows, metric: str) -> np.ndarray:
        jac = rows.jac
        # a square system has one Newton step whatever the metric: no mass matrix needed
        if metric == "mass" and jac.shape[0] != jac.shape[1]:
            # M delta = J^T lambda, J delta = -phi: the KKT with M(q), no bias force and tau = 0
            self._mass_only(q)
            try:
                return self._kkt_solve(self._zero_v, jac, rows.phi)[0]
            except SingularPoseError:
                # M is singular (a point mass on its own joint axis: a foot with toe = heel has no
                # inertia about its ankle). The metric only picks which correction closes the rows:
                # the minimum-norm one below closes them as well.
                pass
        if jac.shape[0] == jac.shape[1]:
            try:
                return np.linalg.solve(jac, -rows.phi)
            except np.linalg.LinAlgError as err:
                raise SingularPoseError("closure Newton: singular pose, the constraint Jacobian lost rank") from err
        return np.linalg.lstsq(jac, -rows.phi, rcond=None)[0]

    def velocity(self, q: np.ndarray, t: float = 0.0, rates: ArrayLike | None = None) -> np.ndarray:
        """V on the manifold: J v = -Phi_t (square), i.e. [J_c; J_s] v = [0; s_dot*].

        Args:
            q: configuration (on the manifold).
            t: time [s].
            rates: the scalar rows' rates instead of their ``rate``.

        """
        rows = self.evaluate(q, None, t)
        rhs = -rows.phi_t if rates is None else self._rhs_rates(rates)
        return square_solve(rows.jac, rhs, "velocity")

    def _rhs_rates(self, rates: ArrayLike) -> np.ndarray:
        rhs = np.zeros(self.nrows)
        rhs[self.n_constraint_rows :] = np.asarray(rates, dtype=float)
        return rhs

    def acceleration(
        self, q: np.ndarray, v: np.ndarray, t: float = 0.0, accelerations: ArrayLike | None = None
    ) -> np.ndarray:
        """A on the manifold: J a = [0; s_ddot*] - J_dot v (square)."""
        rows = self.evaluate(q, v, t)
        rhs = -rows.drift
        if accelerations is not None:
            rhs[self.n_constraint_rows :] += np.asarray(accelerations, dtype=float)
        return square_solve(rows.jac, rhs, "acceleration")

    def motion(
        self, q: np.ndarray, rates: Sequence[float], accelerations: Sequence[float], jac: np.ndarray | None = None
    ):
        """(v, a, J) on the manifold for given scalar-row rates and accelerations (square system).

        ``jac``: J at ``q`` if already known (e.g. ``rows.jac`` of :meth:`project_rows`).
        """
        jac = self.evaluate(q).jac if jac is None else jac
        v = square_solve(jac, self._rhs_rates(rates), "velocity")
        rows = self.evaluate(q, v)
        rhs = -rows.drift
        rhs[self.n_constraint_rows :] += np.asarray(accelerations, dtype=float)
        return v, square_solve(rows.jac, rhs, "acceleration"), rows.jac

    # ---- dynamics on the same rows
    def _kkt(self, q: np.ndarray, v: np.ndarray, tau: np.ndarray, jac: np.ndarray, gamma: np.ndarray):
        """Solve M a + h(q, v) = tau + J^T lambda, J a = -gamma in Pinocchio's C++; returns (a, lambda).

        M(q) from ``pin.crba`` and h(q, v) from ``pin.nonLinearEffects`` (cheaper than the
        ``computeAllTerms`` of ``forwardDynamics(q, v, ...)``), then :meth:`_kkt_solve`.

        Raises:
            ValueError: a singular system (the constraint Jacobian lost rank) or a non-finite answer.

        """
        pin.crba(self.model, self.data, q)  # the full symmetric M
        pin.nonLinearEffects(self.model, self.data, q, v)
        return self._kkt_solve(tau, jac, gamma)

    def _mass_only(self, q: np.ndarray) -> np.ndarray:
        """M(q) in ``data`` with a zero bias force h, for the KKT solves without dynamics; returns M."""
        mass = pin.crba(self.model, self.data, q)
        self.data.nle[:] = 0.0
        return mass

    def _kkt_solve(self, tau: np.ndarray, jac: np.ndarray, gamma: np.ndarray):
        """Solve M a + h = tau + J^T lambda, J a = -gamma with M and h already in ``data``: :func:`kkt_solve`."""
        return kkt_solve(self.model, self.data, tau, jac, gamma)

    def forward_dynamics(self, q: np.ndarray, v: np.ndarray, tau: np.ndarray, t: float = 0.0, mass_ready: bool = False):
        """Constrained forward dynamics, one KKT solve: returns (a, lambda, Rows).

        J^T lambda is the constraint force (generalised); M a + h = tau + J^T lambda, J a = -J_dot v.

        ``mass_ready``: ``data`` already holds M(q) of this very ``q`` (the last :meth:`impulse` was at
        ``q`` and nothing ran ``crba`` since): ``pin.crba`` is skipped, the answer is the same bits.
        """
        rows = self.evaluate(q, v, t)
        if mass_ready:
            pin.nonLinearEffects(self.model, self.data, q, v)
            a, lam = self._kkt_solve(tau, rows.jac, rows.drift)
        else:
            a, lam = self._kkt(q, v, tau, rows.jac, rows.drift)
        return a, lam, rows

    def impulse(self, q: np.ndarray, v_minus: np.ndarray, t: float = 0.0, rows: Rows | None = None):
        """Inelastic impact / M-orthogonal velocity projection onto J v + Phi_t = 0.

        M (v+ - v-) = J^T Lambda, J v+ = -Phi_t: the KKT with M(q), no bias force and
        tau = M v-, so that its "acceleration" is v+.

        Returns:
            (v_plus, Lambda): the velocity after and the impulse per row [N.s, N.m.s].

        """
        rows = self.evaluate(q, None, t) if rows is None else rows
        mass = self._mass_only(q)
        return self._kkt_solve(mass.dot(v_minus), rows.jac, rows.phi_t)
