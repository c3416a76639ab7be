"""The quasi-static spring study on the floor: the weld's omega -> 0 answer, checked against a real sole.

The welded quasi-static answer (:func:`~pasibot_pin.studies.methods.statics.static_equilibrium`) holds
the cranks at each crank angle along the stance, keeps the swing foot in the air at its spring's
rest angle, welds the stance foot flat, and finds the hip pitch where the robot stands still.
On a floor nothing welds the stance foot: its heel and toe are unilateral contacts with Coulomb
friction mu (the floor simulator's, :mod:`pasibot_pin.dynamics.floor`). Exact statics, no
simulation: at the weld's equilibrium q, the floor's forces on the stance heel and toe solve

    g(q) - tau_spring(q) = J_b^T lambda + J_n,heel^T N_heel + J_n,toe^T N_toe + J_t^T T

(least squares on the loop, crank and swing-ankle rows and the floor's heel/toe rows: 18 rows,
full rank, so one set of forces; the residual says q is an equilibrium of the floor model too).
Per crank angle the floor's answer is then:

- ``flat``: N_heel >= 0, N_toe >= 0 and |T| <= mu (N_heel + N_toe): the sole holds the weld's
  equilibrium as it is (same hip pitch, same stability);
- ``heel`` / ``toe``: one normal force would have to pull (the centre of pressure, which in
  single-support statics is the robot's centre of mass projected on the floor, lies behind the
  heel or ahead of the toe): the foot rolls onto its heel or toe. Standing on one point is never
  a stable equilibrium (the whole robot rotated rigidly about the point loses m g h delta^2 / 2:
  an inverted pendulum; the ankle spring is internal and does not resist it), so it falls;
- ``none``: the weld itself has no stable equilibrium there (none within the search range, or
  d^2V/dpitch^2 <= 0), and neither has the floor;
- ``swing``: the stance foot would hold, but the swing foot at its rest angle is below the floor
  (by more than :data:`SWING_TOL`): on a floor it touches down and the robot is in double
  support, which this single-support answer does not resolve (it says where it happens).

In single support the floor pushes straight up (gravity is the only other external force), so
the friction use |T| / N is zero up to round-off; friction matters only in double support.

A cell's verdict: the largest |hip pitch| along the stance when every crank angle is ``flat``,
else the first crank angle that is not, with its cause ("rolls onto heel at theta = ...").

Units: SI, angles [rad].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from pasibot_pin.constraints import ConstraintSystem, coordinate
from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.ground import check_mu
from pasibot_pin.dynamics.floor.run import LOAD_TOL
from pasibot_pin.dynamics.floor.settings import FloorSettings
from pasibot_pin.dynamics.spring_energy import AnkleSpring, ankle_indices, foot_pose, sole_height, spring_forces
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.coordinates import other
from pasibot_pin.studies.methods.static_batch import static_equilibria
from pasibot_pin.studies.methods.statics import StaticEquilibrium, StaticProblem, static_equilibrium
from pasibot_pin.studies.spring_study import SPRING_CASES, scenario_inputs, sweep_springs

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot

STATUSES: tuple[str, ...] = ("flat", "heel", "toe", "none", "swing")
"""The floor's answer at one crank angle (see the module docstring)."""
SWING_TOL = 1e-3
"""The swing foot is on the floor when its lowest sole point is below -SWING_TOL [m]."""
CAUSES = {
    "heel": "rolls onto heel",
    "toe": "rolls onto toe",
    "none": "no stable equilibrium",
    "swing": "swing foot on the floor",
}
"""A failing status, in words."""
WALKING_SCENARIOS: tuple[str, ...] = ("run1", "run2", "run3", "run4")


def stance_of(theta: float) -> str:
    """The stance side at right crank angle ``theta`` [rad] (right from pi/2 to 3 pi/2), as the weld's."""
    return "right" if (theta - math.pi / 2) % (2 * math.pi) < math.pi - 1e-9 else "left"


@dataclass
class FloorStatic:
    """One spring's quasi-static path along the stance, weld and floor.

    Attributes:
        theta: right crank angles (n,) [rad].
        weld: the weld's equilibria (hip pitch, stiffness d^2V/dpitch^2, found).
        status: the floor's answer per crank angle (:data:`STATUSES`).
        heel_force, toe_force: the stance heel's and toe's normal forces (n,) [N] (NaN where
            the weld has no equilibrium; negative: the floor would have to pull).
        tangential: the stance sole's friction force (n,) [N].
        friction_use: |T| / (N_heel + N_toe) (n,) [-].
        cop: centre of pressure ahead of the stance ankle (n,) [m] (the sole spans
            [-heel, +toe]).
        swing_clearance: lowest point of the swing sole above the floor (n,) [m].
        residual: |J^T f - (g - tau)| of the floor's statics (n,) [N, N.m].
        mu: the friction coefficient [-].
        spring: the ankle springs.
        configurations: the weld's equilibrium configuration at each crank angle (n, nq) (NaN
            where it has no stable one).

    """

    theta: np.ndarray
    weld: StaticEquilibrium
    status: list[str]
    heel_force: np.ndarray
    toe_force: np.ndarray
    tangential: np.ndarray
    friction_use: np.ndarray
    cop: np.ndarray
    swing_clearance: np.ndarray
    residual: np.ndarray
    mu: float
    spring: AnkleSpring | None = None
    configurations: np.ndarray | None = None

    @property
    def weld_excursion(self) -> float:
        """The weld's quasi-static answer: largest |equilibrium hip pitch| [rad] (inf: none stable)."""
        return self.weld.max_excursion

    @property
    def holds(self) -> bool:
        """True when the floor holds the stance foot flat at every crank angle."""
        return all(s == "flat" for s in self.status)

    @property
    def excursion(self) -> float:
        """The floor's answer: largest |hip pitch| [rad] when it holds, else inf."""
        return self.weld_excursion if self.holds else math.inf

    @property
    def failure(self) -> tuple[float, str] | None:
        """(crank angle [rad], status) of the first crank angle that is not ``flat``, or None."""
        for theta, status in zip(self.theta, self.status):
            if status != "flat":
                return float(theta), status
        return None

    def verdict(self) -> str:
        """The floor's answer in words: ``12.3 deg`` or ``rolls onto heel at theta = 118 deg``."""
        fail = self.failure
        if fail is None:
            return f"{math.degrees(self.excursion):.1f} deg"
        return f"{CAUSES[fail[1]]} at theta = {math.degrees(fail[0]):.0f} deg"


class _FloorStatics:
    """The floor's heel/toe forces at a welded equilibrium of one robot (shared by every spring)."""

    def __init__(self, robot: PasibotRobot):
        self.robot = robot
        self.data = robot.model.createData()
        self.floor = FloorSimulator(robot, FloorSettings(omega=0.0))
        self.ankles = ankle_indices(robot)
        self.systems: dict[str, ConstraintSystem] = {}

    def bilateral(self, stance: str) -> ConstraintSystem:
        """Loops, both cranks held and the swing ankle held (its rest angle): the weld's rows but the weld."""
        if stance not in self.systems:
            robot, swing = self.robot, other(stance)
            rows = [coordinate(f"{s}_j0_crank", robot.idx_v(f"{s}_j0_crank")) for s in ("right", "left")]
            rows.append(coordinate(f"{swing}_j13_ankle", self.ankles[swing]))
            self.systems[stance] = ConstraintSystem(
                robot.model, robot.data, robot.loop_constraints, rows, robot.geometry.L
            )
        return self.systems[stance]

    def forces(self, spring: AnkleSpring | None, q: np.ndarray, stance: str):
        """(N_heel, N_toe, T, cop, residual) of the stance sole holding ``q`` still [N, N, N, m, N]."""
        robot = self.robot
        jb = self.bilateral(stance).evaluate(q).jac
        _, along, jn, jt = self.floor.contact_rows(q)
        k = 0 if stance == "right" else 2  # heel, toe of the stance foot
        stack = np.vstack((jb, jn[k : k + 2], jt[k : k + 1]))  # one tangential row: a flat sole slides as one
        load = pin.computeGeneralizedGravity(robot.model, self.data, q) - spring_forces(
            robot, spring, q, np.zeros(robot.model.nv), self.ankles
        )
        lam = np.linalg.lstsq(stack.T, load, rcond=None)[0]
        residual = float(np.linalg.norm(stack.T @ lam - load))
        m = jb.shape[0]
        heel, toe, tangential = (float(x) for x in lam[m : m + 3])
        ankle = foot_pose(robot, q, stance)[0]
        cop = (heel * along[k] + toe * along[k + 1]) / (heel + toe) - ankle
        return heel, toe, tangential, cop, residual


def floor_static_path(
    robot: PasibotRobot,
    spring: AnkleSpring | None,
    thetas: ArrayLike,
    mu: float = 0.8,
    cache: dict | None = None,
    weld: StaticEquilibrium | None = None,
) -> FloorStatic:
    """The quasi-static answer of one spring along ``thetas``, weld and floor (see the module docstring).

    Args:
        robot: the scenario's two-legged ``spring`` robot.
        spring: the ankle springs.
        thetas: right crank angles [rad] (the weld's: :func:`static_equilibrium`).
        mu: sole-floor Coulomb friction [-].
        cache: shared between calls on the same robot (the weld's assemblies and the floor's rows).
        weld: the weld's equilibria of ``spring`` along ``thetas`` if already solved (a sweep
            solves all its springs at once: :func:`~pasibot_pin.studies.methods.static_batch.static_equilibria`).

    """
    mu = check_mu(mu)
    thetas = np.asarray(thetas, dtype=float)
    if thetas.ndim != 1 or not len(thetas) or not np.all(np.isfinite(thetas)):
        raise ParameterError("parameter 'thetas' must be a non-empty list of finite crank angles [rad]")
    cache = {} if cache is None else cache
    if "floor_statics" not in cache:  # one floor model per robot, built once
        cache["floor_statics"] = _FloorStatics(robot)
    statics = cache["floor_statics"]
    weld = static_equilibrium(robot, spring, thetas, cache=cache) if weld is None else weld
    n = len(thetas)
    heel, toe, tangential, use, cop, clearance, residual = (np.full(n, np.nan) for _ in range(7))
    status = []
    configurations = np.full((n, robot.model.nq), np.nan)
    for k, theta in enumerate(thetas):
        if not (weld.found[k] and weld.stiffness[k] > 0):
            status.append("none")
            continue
        stance = stance_of(float(theta))
        _, q = StaticProblem(robot, spring, float(theta), cache).torque(float(weld.hip_pitch[k]))
        configurations[k] = q
        heel[k], toe[k], tangential[k], cop[k], residual[k] = statics.forces(spring, q, stance)
        use[k] = abs(tangential[k]) / (heel[k] + toe[k])
        clearance[k] = sole_height(robot, q, other(stance))
        if heel[k] < -LOAD_TOL:
            status.append("toe")  # the heel would have to pull: the centre of pressure is ahead of the toe
        elif toe[k] < -LOAD_TOL:
            status.append("heel")
        elif use[k] > mu:
            status.append("none")  # a flat sole that slides (never in single support: T = 0)
        elif clearance[k] < -SWING_TOL:
            status.append("swing")
        else:
            status.append("flat")
    return FloorStatic(
        thetas, weld, status, heel, toe, tangential, use, cop, clearance, residual, mu, spring, configurations
    )


def stance_thetas(samples: int) -> np.ndarray:
    """``samples`` right crank angles over one stance, pi/2 to 3 pi/2 (end excluded) [rad], as the weld's."""
    if int(samples) != samples or samples < 1:
        raise ParameterError(f"parameter 'static_samples' must be a positive integer, got {samples!r}")
    return np.linspace(math.pi / 2, 1.5 * math.pi, int(samples), endpoint=False)


@dataclass
class FloorStaticSweep:
    """One scenario's quasi-static answers on the floor: its spring cases and the (K_e, beta0) grid.

    Attributes:
        scenario: ``run1`` .. ``run4``.
        fitted: the inverse-dynamics spring.
        cases: spring case label -> :class:`FloorStatic`.
        stiffness: K_e grid [N.m/rad] (columns).
        rest: beta0 grid [rad] (rows).
        cells: (len(rest), len(stiffness)) :class:`FloorStatic` of every cell.

    """

    scenario: str
    fitted: AnkleSpring
    cases: dict[str, FloorStatic] = field(default_factory=dict)
    stiffness: np.ndarray | None = None
    rest: np.ndarray | None = None
    cells: list[list[FloorStatic]] = field(default_factory=list)

    def grid(self, what: str) -> np.ndarray:
        """``weld`` or ``floor``: the (rest, stiffness) grid of largest |hip pitch| [rad] (inf: no answer)."""
        attr = {"weld": "weld_excursion", "floor": "excursion"}[what]
        return np.array([[getattr(c, attr) for c in row] for row in self.cells])


def floor_static_sweep(
    scenario: str,
    mu: float = 0.8,
    sweep_stiffness: Sequence[float] | None = None,
    sweep_rest: Sequence[float] | None = None,
    static_samples: int = 19,
    cases: Sequence[tuple[str, float]] = SPRING_CASES,
    sweep: bool = True,
) -> FloorStaticSweep:
    """The quasi-static answer on the floor for a scenario's spring cases and (K_e, beta0) grid.

    Args:
        scenario: ``run1`` .. ``run4`` (or ``1`` .. ``4``; ``quasi-static`` too: the cranks are held anyway).
        mu: sole-floor Coulomb friction [-].
        sweep_stiffness: K_e grid [N.m/rad] (default the weld's: :func:`sweep_springs`).
        sweep_rest: beta0 grid [rad] (default the weld's).
        static_samples: crank angles over one stance.
        cases: spring cases (label, factor on the fitted K_e).
        sweep: False: the cases only.

    """
    mu = check_mu(mu)
    thetas = stance_thetas(static_samples)
    for name, values in (("sweep_stiffness", sweep_stiffness), ("sweep_rest", sweep_rest)):
        if values is not None and (np.ndim(values) != 1 or not len(values) or not np.all(np.isfinite(values))):
            raise ParameterError(f"parameter {name!r} must be a non-empty list of finite numbers, got {values!r}")
    inputs = scenario_inputs(scenario)
    robot, fit = inputs.robot, inputs.fit
    cache: dict = {}
    out = FloorStaticSweep(inputs.name, fit)
    springs = {label: fit.scaled(factor) for label, factor in cases}
    grid: list[list[AnkleSpring]] = []
    if sweep:
        ks, bs = sweep_springs(fit, sweep_stiffness, sweep_rest)
        stiffness, rest = np.asarray(ks, dtype=float), np.asarray(bs, dtype=float)
        out.stiffness, out.rest = stiffness, rest
        grid = [[AnkleSpring(float(k), float(beta0), fit.damping) for k in stiffness] for beta0 in rest]
    # the weld's equilibria of every distinct spring in one batched secant search
    distinct = list(dict.fromkeys([*springs.values(), *(spring for row in grid for spring in row)]))
    welds = dict(zip(distinct, static_equilibria(robot, distinct, thetas, cache=cache)))
    answers: dict[AnkleSpring, FloorStatic] = {}
    for spring in distinct:
        answers[spring] = floor_static_path(robot, spring, thetas, mu, cache, weld=welds[spring])
    out.cases = {label: answers[spring] for label, spring in springs.items()}
    out.cells = [[answers[spring] for spring in row] for row in grid]
    return out


def floor_static_study(
    scenarios: Sequence[str] = WALKING_SCENARIOS, mu: float = 0.8, static_samples: int = 19, sweep: bool = True
) -> list[FloorStaticSweep]:
    """:func:`floor_static_sweep` for each scenario (default runs 1-4)."""
    if not len(scenarios):
        raise ParameterError("parameter 'scenarios' must name at least one scenario")
    check_mu(mu)
    stance_thetas(static_samples)
    return [floor_static_sweep(s, mu, static_samples=static_samples, sweep=sweep) for s in scenarios]
