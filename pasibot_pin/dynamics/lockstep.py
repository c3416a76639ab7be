"""Several welded runs at once, in lockstep: the runs of the dynamic spring sweep.

Runs that differ only in their ankle spring (K_e, beta0, c) and their initial hip pitch share the
touchdown times, the step and every constraint row but two: the stance weld's x (each run's foot
lands at its own x; the row is p_foot - p_target, so a run's residual is the shared one plus
x_shared - x_run) and the swing ankle's rest angle (a per-run target of its row).
:func:`simulate_many` integrates them together with the same RK4, mass-metric projection and
impulse as :class:`~pasibot_pin.dynamics.simulator.BipedSimulator`, run by run for every
Pinocchio call (M, h and the KKT solves), but with the constraint rows of every run in one batched
evaluation (``ConstraintSystem.evaluate`` on (N, nv)). The answers equal :func:`simulate`'s to
round-off (the batched rows sum in another order); ``tests/test_simulate.py`` checks it.

Units: SI; angles [rad].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pasibot_pin.constraints.system import STEP_LIMIT, ConstraintSystem, kkt_solve
from pasibot_pin.dynamics.simulator import BipedSimulator, Impact, SimulationResult, SimulationSettings
from pasibot_pin.dynamics.spring_energy import foot_pose, sole_height, total_energy
from pasibot_pin.errors import ParameterError, SimulationError
from pasibot_pin.model.coordinates import other

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot

PROJECT_ITERATIONS = 20
"""Newton iterations of the projections (the simulator's)."""


class _Failed(Exception):
    """One run's solve failed (its message is the simulator's)."""


def _check(settings: Sequence[SimulationSettings]) -> SimulationSettings:
    """The shared settings; ValueError unless the runs differ only in spring and initial pitch."""
    if not settings:
        raise ParameterError("simulate_many needs at least one run")
    first = settings[0]
    for s in settings:
        if s.with_(spring=first.spring, initial_pitch=first.initial_pitch) != first:
            raise ParameterError("simulate_many: the runs may differ only in their spring and initial pitch")
    if first.swing_ankle != "rest" or first.integrator != "rk4" or first.feedforward is not None:
        raise ParameterError("simulate_many runs swing_ankle='rest', RK4 runs without feed-forward")
    if first.record_every != 1 or not first.omega > 0:
        raise ParameterError("simulate_many records every step of a run with a positive crank rate")
    return first


class _Runs:
    """The lockstep state: one shared constraint system per stance, per-run targets and weld offsets."""

    def __init__(self, robot: PasibotRobot, settings: Sequence[SimulationSettings]):
        self.model, self.data = robot.model, robot.data
        self.sims = [BipedSimulator(robot, s) for s in settings]
        self.n = len(settings)
        springs = [s.spring for s in settings if s.spring is not None]
        if len(springs) != self.n:
            raise ParameterError("simulate_many needs a spring in every run's settings")
        self.stiffness = np.array([sp.stiffness for sp in springs])
        self.rest = np.array([sp.rest_angle for sp in springs])
        self.damping = np.array([sp.damping for sp in springs])
        self.ankle_index = list(self.sims[0].ankles.values())
        self.zero = np.zeros(self.model.nv)

    def stance(self, stance: str, welds: list) -> None:
        """Take the constraint rows of ``stance`` with each run's weld (``welds[k]``, None: stopped)."""
        first = next(w for w in welds if w is not None)
        self.cset: ConstraintSystem = self.sims[0].constraint_set(stance, first)
        cset = self.cset
        self.labels = self.sims[0]._multiplier_rows(cset)
        self.weld_x = cset.labels.index(f"{first.name}.x")
        shared = first.joint2_placement.translation[0]
        self.offset = np.array([0.0 if w is None else shared - w.joint2_placement.translation[0] for w in welds])
        self.ankle_target = cset.labels.index(f"{other(stance)}_j13_ankle") - cset.n_constraint_rows
        self.swing = other(stance)

    def rows(self, q: np.ndarray, v: np.ndarray | None, t: float, idx: np.ndarray):
        """The rows of runs ``idx`` at (q, v) (N, nv), time t."""
        targets = np.repeat(self.cset.targets(t)[None, :], len(idx), axis=0)
        targets[:, self.ankle_target] = math.pi / 2 - self.rest[idx]
        rows = self.cset.evaluate(q, v, t, targets)
        rows.phi[:, self.weld_x] += self.offset[idx]
        return rows

    def forces(self, q: np.ndarray, v: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """The ankle springs' generalised forces (N, nv), as ``spring_energy.spring_forces``."""
        tau = np.zeros(q.shape)
        k, b0, c = self.stiffness[idx], self.rest[idx], self.damping[idx]
        for i in self.ankle_index:
            tau[:, i] = -(-k * ((math.pi / 2 - q[:, i]) - b0) - c * (-v[:, i]))
        return tau

    def kkt(self, q: np.ndarray, tau: np.ndarray, jac: np.ndarray, gamma: np.ndarray, v=None):
        """One run's KKT solve (M, and h when ``v`` is given, else h = 0): (a, lambda); _Failed if singular."""
        model, data = self.model, self.data
        pin.crba(model, data, q)
        if v is None:
            data.nle[:] = 0.0
        else:
            pin.nonLinearEffects(model, data, q, v)
        try:
            return kkt_solve(model, data, tau, jac, gamma)
        except SimulationError as err:
            raise _Failed(str(err)) from err

    def accelerations(self, t: float, q: np.ndarray, v: np.ndarray, idx: np.ndarray, failed: dict):
        """Constrained accelerations and multipliers of runs ``idx``; a failing run goes into ``failed``."""
        rows = self.rows(q, v, t, idx)
        tau = self.forces(q, v, idx)
        a, lam = np.zeros(q.shape), np.zeros((len(idx), self.cset.nrows))
        for j, k in enumerate(idx):
            if k in failed:
                continue
            try:
                a[j], lam[j] = self.kkt(q[j], tau[j], rows.jac[j], rows.drift[j], v[j])
            except _Failed as err:
                failed[k] = str(err)
        return a, lam

    def project(self, q: np.ndarray, t: float, idx: np.ndarray, failed: dict):
        """Mass-metric Newton of runs ``idx`` onto the rows at t: (q, rows at q, residual before)."""
        q = q.copy()
        cset = self.cset
        rows = self.rows(q, None, t, idx)
        error = np.abs(rows.phi)
        initial = error.max(axis=1)
        open_ = ~np.all(error < cset.tolerance, axis=1)
        for _ in range(PROJECT_ITERATIONS):
            for j in np.nonzero(open_)[0]:
                if idx[j] in failed:
                    open_[j] = False
                    continue
                try:
                    step = self.kkt(q[j], self.zero, rows.jac[j], rows.phi[j])[0]
                except _Failed as err:
                    failed[idx[j]], open_[j] = str(err), False
                    continue
                largest = np.abs(step).max()
                if largest > STEP_LIMIT:
                    step *= STEP_LIMIT / largest
                q[j] = pin.integrate(self.model, q[j], step)
            if not np.any(open_):
                break
            part = self.rows(q[open_], None, t, idx[open_])
            rows.phi[open_], rows.jac[open_] = part.phi, part.jac
            open_[open_] = ~np.all(np.abs(part.phi) < cset.tolerance, axis=1)
        for j in np.nonzero(open_)[0]:
            worst = int(np.argmax(np.abs(rows.phi[j]) / cset.tolerance))
            failed[idx[j]] = (
                f"loop closure failed: constraint {cset.labels[worst]} keeps a residual of "
                f"{abs(rows.phi[j, worst]):.3e} after {PROJECT_ITERATIONS} Newton iterations at t = {t:.4f} s; "
                "the loop cannot assemble there"
            )
        return q, rows, initial

    def impulse(self, q: np.ndarray, v: np.ndarray, rows, idx: np.ndarray, failed: dict) -> np.ndarray:
        """Velocity projection (inelastic impulse) of runs ``idx`` onto J v = -Phi_t."""
        out = v.copy()
        for j, k in enumerate(idx):
            if k in failed:
                continue
            model, data = self.model, self.data
            mass = pin.crba(model, data, q[j])
            try:
                out[j] = self.kkt_mass(mass, v[j], rows.jac[j], rows.phi_t[j])
            except _Failed as err:
                failed[k] = str(err)
        return out

    def kkt_mass(self, mass: np.ndarray, v: np.ndarray, jac: np.ndarray, phi_t: np.ndarray) -> np.ndarray:
        """The impulse's KKT with M already in the data: v+ (_Failed if singular)."""
        self.data.nle[:] = 0.0
        try:
            return kkt_solve(self.model, self.data, mass.dot(v), jac, phi_t)[0]
        except SimulationError as err:
            raise _Failed(str(err)) from err


def simulate_many(robot: PasibotRobot, settings: Sequence[SimulationSettings], steps: int) -> list[SimulationResult]:
    """Run ``steps`` stance phases with each of ``settings`` (see the module docstring).

    Args:
        robot: the ``spring`` biped (``pp.load("spring", 2)`` or a scenario's copy).
        settings: one per run; they may differ only in ``spring`` and ``initial_pitch``
            (``swing_ankle="rest"``, RK4, no feed-forward, every step recorded).
        steps: stance phases to run (a touchdown ends each but the last).

    Returns:
        One :class:`~pasibot_pin.dynamics.simulator.SimulationResult` per run, as
        :func:`~pasibot_pin.dynamics.simulator.simulate` gives it to round-off.

    """
    s = _check(settings)
    if int(steps) != steps or steps < 1:
        raise ParameterError(f"parameter 'steps' must be a positive integer, got {steps!r}")
    run = _Lockstep(robot, settings, s)
    t = 0.0
    ends = run.phase_ends(int(steps))
    for phase, t_end in enumerate(ends):
        t = run.integrate_phase(t, t_end)
        if not len(run.active) or phase == len(ends) - 1:
            break
        run.touchdown(t)
    return run.results(t)


class _Lockstep:
    """The runs of :func:`simulate_many` stepped together: their states, records and the ones still going."""

    def __init__(self, robot: PasibotRobot, settings: Sequence[SimulationSettings], s: SimulationSettings):
        self.robot, self.s = robot, s
        self.runs = runs = _Runs(robot, settings)
        n = runs.n
        starts = [sim.initial_state() for sim in runs.sims]
        self.stance = starts[0][2]
        q = np.array([st[0] for st in starts])
        v = np.array([st[1] for st in starts])
        runs.stance(self.stance, [sim.ground_weld(self.stance, q[k]) for k, sim in enumerate(runs.sims)])
        keys = ("t", "q", "v", "lam", "stance", "drift", "swing")
        self.recs: list[dict[str, list]] = [{key: [] for key in keys} for _ in range(n)]
        self.impacts: list[list[Impact]] = [[] for _ in range(n)]
        self.fell, self.message = [False] * n, [""] * n
        self.soles = runs.sims[0].soles
        failed: dict = {}
        everyone = np.arange(n)
        self.q, rows, _ = runs.project(q, 0.0, everyone, failed)
        self.v = runs.impulse(self.q, v, rows, everyone, failed)
        if failed:  # the single run raises here: so does the batch
            raise SimulationError(next(iter(failed.values())))
        self.last_drift = np.zeros(n)
        self.active = np.arange(n)

    def phase_ends(self, steps: int) -> list[float]:
        """The end time of each stance phase: the next touchdown angle pi/2 + k pi of the right crank [s]."""
        s = self.s
        k0 = math.floor((s.theta0 - math.pi / 2) / math.pi + 1e-9) + 1
        return [(math.pi / 2 + (k0 + i) * math.pi - s.theta0) / s.omega for i in range(steps)]

    def record(self, k: int, t: float, qk: np.ndarray, vk: np.ndarray, lam: np.ndarray) -> None:
        """One sample of run ``k``."""
        rec, runs = self.recs[k], self.runs
        rec["t"].append(t)
        rec["q"].append(qk.copy())
        rec["v"].append(vk.copy())
        rec["lam"].append(np.array([0.0 if i is None else lam[i] for i in runs.labels]))
        rec["stance"].append(self.stance)
        rec["drift"].append(self.last_drift[k])
        rec["swing"].append(sole_height(self.robot, qk, runs.swing, self.soles[runs.swing]))

    def finish(self, k: int, t: float, qk: np.ndarray, vk: np.ndarray) -> None:
        """A stopped run's last sample (its multipliers at (t, q, v), zeros if they fail)."""
        done: dict = {}
        lam = self.runs.accelerations(t, qk[None], vk[None], np.array([k]), done)[1][0]
        self.record(k, t, qk, vk, np.zeros(self.runs.cset.nrows) if done else lam)

    def integrate_phase(self, t: float, t_end: float) -> float:
        """RK4 steps of equal length from ``t`` to ``t_end`` (at most ``dt``) for every run still going; the new t."""
        steps_n = max(1, math.ceil((t_end - t) / self.s.dt - 1e-9))
        h = (t_end - t) / steps_n
        for _ in range(steps_n):
            if not len(self.active):
                break
            self.rk4_step(t, h)
            t += h
        return t

    def rk4_step(self, t: float, h: float) -> None:
        """One RK4 step of every active run, projected onto its rows, then each run's record and fall check."""
        runs, active, half = self.runs, self.active, h / 2
        qa, va = self.q[active], self.v[active]
        failed: dict = {}
        a1, lam = runs.accelerations(t, qa, va, active, failed)
        v2 = va + half * a1
        a2 = runs.accelerations(t + half, qa + half * va, v2, active, failed)[0]
        v3 = va + half * a2
        a3 = runs.accelerations(t + half, qa + half * v2, v3, active, failed)[0]
        v4 = va + h * a3
        a4 = runs.accelerations(t + h, qa + h * v3, v4, active, failed)[0]
        q_new = qa + h / 6 * ((va + v4) + 2 * (v2 + v3))
        v_new = va + h / 6 * ((a1 + a4) + 2 * (a2 + a3))
        q_new, rows, drift = runs.project(q_new, t + h, active, failed)
        v_new = runs.impulse(q_new, v_new, rows, active, failed)
        keep = []
        for j, k in enumerate(active.tolist()):
            if k in failed:
                self.fell[k], self.message[k] = True, f"stopped at t = {t:.3f} s: {failed[k]}"
                if not self.recs[k]["t"] or self.recs[k]["t"][-1] < t:  # as the single run: no sample twice
                    self.finish(k, t, qa[j], va[j])
                continue
            self.record(k, t, qa[j], va[j], lam[j])
            self.q[k], self.v[k], self.last_drift[k] = q_new[j], v_new[j], drift[j]
            if abs(self.q[k, 2]) > self.s.fall_limit:
                self.fell[k] = True
                limit = math.degrees(self.s.fall_limit)
                self.message[k] = f"fell: |hip pitch| passed {limit:.0f} deg at t = {t + h:.3f} s"
                self.finish(k, t + h, self.q[k], self.v[k])
                continue
            keep.append(k)
        self.active = np.array(keep, dtype=int)

    def touchdown(self, t: float) -> None:
        """The swing foot lands: weld it, project every run onto the new rows, the inelastic impact."""
        runs, robot, q, v = self.runs, self.robot, self.q, self.v
        lam = runs.accelerations(t, q[self.active], v[self.active], self.active, {})[1]
        side = other(self.stance)
        welds: list = [None] * runs.n
        poses = {}
        for j, k in enumerate(self.active.tolist()):
            self.record(k, t, q[k], v[k], lam[j])
            poses[k] = foot_pose(robot, q[k], side)
            welds[k] = runs.sims[k].ground_weld(side, q[k])
        self.stance = side
        runs.stance(side, welds)
        failed: dict = {}
        q_land, rows, _ = runs.project(q[self.active], t, self.active, failed)
        keep = []
        for j, k in enumerate(self.active.tolist()):
            if k in failed:
                self.fell[k], self.message[k] = True, f"landing failed at t = {t:.3f} s: {failed[k]}"
                continue
            keep.append(j)
        if len(keep) < len(self.active):
            q_land, self.active = q_land[keep], self.active[keep]
            rows.phi, rows.jac, rows.phi_t = rows.phi[keep], rows.jac[keep], rows.phi_t[keep]
        active = self.active
        q[active] = q_land
        before = [total_energy(robot, q[k], v[k])["kinetic"] for k in active]
        v_land = runs.impulse(q[active], v[active], rows, active, failed)
        for j, k in enumerate(active.tolist()):
            v[k] = v_land[j]
            _, z, pitch = poses[k]
            self.impacts[k].append(Impact(t, side, z, pitch, before[j], total_energy(robot, q[k], v[k])["kinetic"]))

    def results(self, t: float) -> list[SimulationResult]:
        """Every run's :class:`SimulationResult`, the ones still going ended at ``t``."""
        for k in self.active.tolist():
            self.finish(k, t, self.q[k], self.v[k])
        return [
            sim.result(self.recs[k], self.impacts[k], self.fell[k], self.message[k])
            for k, sim in enumerate(self.runs.sims)
        ]
