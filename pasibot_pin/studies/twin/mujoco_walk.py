"""The MuJoCo twin of a walk: the same design, start, crank schedule and verdict, in MuJoCo.

:func:`walk_in_mujoco` is :func:`~pasibot_pin.studies.walking.walk_design` with MuJoCo in place
of our floor simulator. Everything but the engine is shared:

* the robot: the design's two-legged robot exported by :func:`~pasibot_pin.model.mjcf.to_mjcf`
  (its variant, masses, sole; its ankle spring from
  :func:`~pasibot_pin.studies.methods.spring_fit.design_spring`, as ours);
* the start: ours (:meth:`~pasibot_pin.dynamics.floor.FloorSimulator.start_state`: the flat
  double support, or the settled one of a preloaded spring; the flat one where the robot cannot
  stand at theta0, as :func:`walk_design`), the soles' capsules :data:`SINK` into the floor;
* the cranks: theta0 + omega advance(t) (:func:`~pasibot_pin.dynamics.floor.crank_advance`,
  the walk's ramp), imposed by :data:`MJ_WALK`'s ``constraint`` drives (an ``equality joint``
  per crank, set every step). They follow the target better than the position servo: measured on the
  4.5 L parallel walker at 1 rad/s, the servo (kp 5000, kv 20, its ramp lag kv omega / kp
  added) is 5-10 mrad off under the stance torque, the drive 1.9 mrad before and < 0.1 mrad
  after its own lag (2 tau zeta^2 omega with the equality's solref (tau, zeta)) is added
  (:data:`DRIVE_LEAD`). With ``motors = "one"`` both cranks are driven on the same schedule
  pi apart, which is the coupling row of ours; the one motor's power is the sum of the two;
* the verdict: a :class:`~pasibot_pin.dynamics.verdict.GaitJudge` with the walk's
  :class:`~pasibot_pin.dynamics.verdict.GaitCriteria`, fed every :data:`SAMPLE_DT` (ours feeds it
  every step of its own ~1 ms) and the run stopped as soon as it is decided.

Per foot, each sample: ``loaded`` when the sole's contacts push with more than
:data:`~pasibot_pin.dynamics.floor.LOAD_TOL` on average over the last :data:`LOAD_WINDOW`
(every MuJoCo step counted; ours reports each step's impulse over its length, an average over
its ~1 ms); ``on_point`` when only the heel half or only the toe half of the sole carries load
(where the contact points lie along heel -> toe, compared in x); ``x`` the middle of the heel and toe sites,
``pitch`` from their heights; ``normal`` the sole's average normal force; ``slip`` the largest
|x velocity| of the heel or toe site whose half is loaded (the foot is rigid: its contact points
move between them; the capsule's 2 mm radius changes that speed by |pitch rate| x 2 mm). The
motor power is the drive's equality force (averaged over the sample) times the crank rate.

Why 10 ms and not MuJoCo's step: a landing foot of PASIBOT grazes the floor and slides on it
under a light load while the other foot still stands (ours: ``sliding`` for ~0.3 s at 1 rad/s).
MuJoCo's compliant contact, with the stiff loops, makes that foot chatter instead: on for 1-3
ms, off for 1-3 ms (at a 0.1 ms step, with pyramidal or elliptic cones, with or without
no-slip, at floor time constants from 1 to 5 ms), about 50-150 N on average, now and then off
for 10-20 ms. Sampled per step or per ms, the judge (its 10 ms dwell) sees such a gap as a
lift-off and the next contact as a landing where the foot stood (``hopped``, before the
verdict's bounce rule); averaged over 10 ms (the judge's dwell, several chatter periods) it is
the load ours computes. On the 4.5 L walker (3 steps) the twin's steps land within 3 ms of ours
with the 10 ms average, 16 ms after them with 1 ms averages (both walk, the bounce rule
absorbing the gaps). Larger MuJoCo steps chatter longer: 0.2 and 0.25 ms ``hopped`` after one
and two steps even with the 10 ms average (before the bounce rule).

The contacts (:data:`MJ_WALK`) are a stiff floor (1 ms, impedance 0.9999) with Coulomb friction
mu, at MuJoCo's 0.1 ms step; the floor plane is given the soles' solref/solimp too (MuJoCo
averages the two geoms' parameters: with the plane's defaults the stance foot sank ~1 mm,
enough to land the swing foot of the 4.5 L walker 0.4 s early and hard, as its touchdown
grazes the floor).

A MuJoCo instability (a non-finite state, a MuJoCo warning that it reset a bad acceleration or
state, a speed above :data:`~pasibot_pin.dynamics.floor.SPEED_LIMIT`) is the ``diverged``
outcome, never an exception.

Units: SI, angles [rad].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
import pinocchio as pin

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.run import LOAD_TOL
from pasibot_pin.dynamics.floor.settings import crank_advance
from pasibot_pin.dynamics.floor.tracked_step import SPEED_LIMIT
from pasibot_pin.dynamics.verdict import FootSample, GaitJudge, GaitSample, Verdict
from pasibot_pin.errors import MissingExtraError, ParameterError, SimulationError
from pasibot_pin.model.coordinates import HIP_PITCH, HIP_X, HIP_Z, SIDES
from pasibot_pin.model.design import design_robot
from pasibot_pin.model.mjcf import MjcfOptions, check_twin, spatial_qpos, to_mjcf
from pasibot_pin.model.spatial import planar_to_spatial, planar_velocity_to_spatial, roll_pitch_yaw
from pasibot_pin.studies.walking import WalkSettings, floor_settings, walk_duration

MJ_WALK = MjcfOptions(
    actuator="constraint",
    contact_solref=(1e-3, 1.0),
    contact_solimp=(0.9999, 0.9999, 0.001),
    timestep=1e-4,
)
"""The MuJoCo model of a walk: crank drives as stiff equality constraints, a stiff floor and
friction (impedance 0.9999: MuJoCo's friction creeps by its 1 - 0.9999 regularisation only), a
0.1 ms step (the spring, mu and boundinertia are filled in per design). No no-slip post-solve:
measured on the 4.5 L walker (3 steps), 30 no-slip iterations (with ``planar_noslip``) give the
same verdict, steps 3 ms later instead of within 3 ms of ours, 43.6 J instead of 41.6 J of motor
work per stride (ours 41.1 J), and cost 60 % more per MuJoCo step."""
SAMPLE_DT = 1e-3
"""The judge takes a sample this often [s] (an average over the MuJoCo steps in between)."""
LOAD_WINDOW = 0.01
"""A foot's load is its sole's normal force averaged over this long [s] (see the module docstring)."""
SINK = 1e-6
"""The soles start this far into MuJoCo's floor [m], so its contacts carry the weight from the first step."""
_WARNINGS = ("mjWARN_BADQACC", "mjWARN_BADQPOS", "mjWARN_BADQVEL")
"""MuJoCo's warnings that it reset a bad acceleration or state: the walk diverged."""
MISSING = "needs the mujoco extra: pip install 'pasibot-pin[mujoco]'"


def _mujoco():
    """The ``mujoco`` module, or :class:`MissingExtraError`."""
    try:
        import mujoco  # deferred: optional extra (mujoco)
    except ImportError as err:
        raise MissingExtraError(f"walk_in_mujoco {MISSING}") from err
    return mujoco


@dataclass
class MujocoWalk:
    """A design walked in MuJoCo: its verdict and a few traces (one row per judged sample).

    Attributes:
        verdict: the :class:`~pasibot_pin.dynamics.verdict.Verdict`.
        omega: crank speed [rad/s].
        dt: MuJoCo's time step [s].
        sample_dt: the judge's sample interval [s].
        start_kind: ``flat`` or ``settled`` (our start it began from).
        t: sample times from the start [s].
        hip_x: hip forward position [m].
        hip_pitch: [rad].
        loaded: (n, 2) right and left foot loaded.
        normal: (n, 2) right and left normal force [N].
        max_crank_error: largest |crank - schedule| over the samples [rad].
        options: the :class:`~pasibot_pin.model.mjcf.MjcfOptions` exported.
        max_hip_roll_deg: the 3-D walk's largest |hip roll| [deg] (NaN for the planar one).

    """

    verdict: Verdict
    omega: float
    dt: float
    sample_dt: float
    start_kind: str
    t: np.ndarray
    hip_x: np.ndarray
    hip_pitch: np.ndarray
    loaded: np.ndarray
    normal: np.ndarray
    max_crank_error: float
    options: MjcfOptions = field(repr=False)
    max_hip_roll_deg: float = math.nan

    def __repr__(self) -> str:
        return f"MujocoWalk(omega={self.omega:g} rad/s, dt={self.dt:g} s: {self.verdict.summary()})"


def mujoco_options(design, settings: WalkSettings, robot, base: MjcfOptions = MJ_WALK) -> MjcfOptions:
    """The export options of ``design``'s walk: ``base`` with the design's spring and the walk's mu and slope."""
    floor = floor_settings(design, settings, robot)
    if floor.step_height:
        raise ParameterError("parameter 'step_height': the MuJoCo twin walks a flat floor or a slope, not a step")
    options = replace(base, mu=floor.mu, slope=floor.slope)
    if floor.spring is not None:
        spring = floor.spring
        options = replace(
            options,
            spring_stiffness=spring.stiffness,
            spring_rest_angle=spring.rest_angle,
            spring_damping=spring.damping,
        )
    return options


class _Twin:
    """MuJoCo's model and data of one walk, the crank schedule and the judge's samples."""

    def __init__(self, mujoco, robot, design, settings: WalkSettings, options: MjcfOptions):
        self.mj, self.robot = mujoco, robot
        self.floor = floor_settings(design, settings, robot)
        sim = FloorSimulator(robot, self.floor)
        try:
            start = sim.start_state()
            q0, v0, self.start_kind = start.q, start.v, start.kind
        except SimulationError:  # cannot stand at theta0: the flat double support, as walk_design
            (q0, v0), self.start_kind = sim.initial_state(), "flat"
        self.weight, self.options = sim.weight, options
        self.spatial = options.footprint is not None
        self.turn = sim.turn  # the ground's frame, e^(-i slope): the judge reads along and across it, as ours
        model = mujoco.MjModel.from_xml_string(to_mjcf(robot, options, q_weld=q0))
        floor_geom = model.geom("floor").id  # MuJoCo mixes both geoms' solref/solimp: make them equal
        model.geom_solref[floor_geom] = options.contact_solref
        model.geom_solimp[floor_geom, :3] = options.contact_solimp
        self.model, self.data = model, mujoco.MjData(model)
        if self.spatial:  # the free joint: world-axes linear velocity, local angular velocity
            self.data.qpos[:] = spatial_qpos(q0)
            u0 = planar_velocity_to_spatial(v0)
            rotation = pin.Quaternion(planar_to_spatial(q0)[3:7]).toRotationMatrix()
            self.data.qvel[:] = np.concatenate((u0[:3], rotation.T @ u0[3:6], u0[6:]))
            self.data.qpos[2] += options.sole_radius - SINK  # box bottoms where our points are
        else:
            self.data.qpos[:], self.data.qvel[:] = q0, v0
            lift = options.sole_radius - SINK  # capsule bottoms where our points are: along the ground's normal
            if self.turn != 1.0:
                self.data.qpos[HIP_X] += lift * self.turn.imag  # -sin(slope)
                lift *= self.turn.real
            self.data.qpos[HIP_Z] += lift
        motors = list(robot.actuated_joints)
        self.theta0 = np.array([q0[robot.idx_q(m)] for m in motors])
        self.qadr = [model.joint(m).qposadr[0] for m in motors]
        self.dofs = [model.joint(m).dofadr[0] for m in motors]
        self.drives = np.array([model.equality(f"{m}_drive").id for m in motors])
        tau, zeta = options.solref
        self.lead = 2.0 * tau * zeta * zeta  # the drive's lag on a ramp, per unit of crank rate [s]
        bands = 0 if options.footprint is None else len(options.footprint.bands)
        names = [[f"{side}_sole{k}" for k in range(bands)] if self.spatial else [f"{side}_sole"] for side in SIDES]
        self.sites = [[model.site(f"{side}_{p}").id for p in ("heel", "toe")] for side in SIDES]
        self.one_motor = self.floor.motors == "one"
        self.model.eq_data[self.drives, 0] = self.theta0
        self._drive_rows: list[int] | None = None
        foot_of_geom = np.full(model.ngeom, -1)
        for foot, geoms in enumerate(names):
            foot_of_geom[[model.geom(name).id for name in geoms]] = foot
        self._foot_of_geom: list[int] = foot_of_geom.tolist()  # read once per contact and step: a list
        self._ends: list[int] = np.array(self.sites).ravel().tolist()
        self._site_xpos = self.data.site_xpos  # MjData's buffer stays where it is (not so its contacts')
        self._eq_angle = self.model.eq_data[:, 0]  # a view too (the drives' targets)
        self._drive_ids: list[int] = self.drives.tolist()
        self._theta0: list[float] = self.theta0.tolist()
        self._warnings = [(int(getattr(mujoco.mjtWarning, name)), name[7:]) for name in _WARNINGS]
        self._velocity = np.zeros(6)  # mj_objectVelocity's output: angular, then linear
        # the last samples' forces [N], as lists: the same divisions and sums as numpy's rows, cheaper
        self._recent: list[list[float]] = [[0.0] * 4 for _ in range(max(1, round(LOAD_WINDOW / SAMPLE_DT)))]
        self._slot = 0
        self._reset_window()

    def _reset_window(self) -> None:
        # Python floats, added one by one: the very IEEE sums numpy's arrays gave, at a step's fraction of the cost
        self._force = [0.0, 0.0, 0.0, 0.0]  # right heel half, right toe half, left heel half, left toe half [N]
        self._torque = [0.0] * len(self.drives)
        self._n = 0

    def _angles(self, t: float) -> tuple[list[float], float]:
        """The cranks' angles [rad] and rate [rad/s] at ``t`` [s] after the start (Python floats: each step's)."""
        advance, rate = crank_advance(t, self.floor.crank_ramp)
        shift = self.floor.omega * advance
        return [theta0 + shift for theta0 in self._theta0], self.floor.omega * rate

    def schedule(self, t: float) -> tuple[np.ndarray, float]:
        """The cranks' angles [rad] and rate [rad/s] at ``t`` [s] after the start, as arrays (for benchmarks)."""
        angles, rate = self._angles(t)
        return np.array(angles), rate

    def step(self, t: float) -> None:
        """One MuJoCo step from ``t`` [s], the drives on the schedule (lag added), forces summed."""
        advance, rate = crank_advance(t, self.floor.crank_ramp)  # :meth:`_angles`, inlined: every step's
        omega, eq_angle = self.floor.omega, self._eq_angle
        shift, lag = omega * advance, self.lead * (omega * rate)
        for drive, theta0 in zip(self._drive_ids, self._theta0):
            eq_angle[drive] = theta0 + shift + lag  # (theta0 + shift) + lag, as the angle plus the lag
        self.mj.mj_step(self.model, self.data)
        self._accumulate()

    def _accumulate(self) -> None:
        """Add this step's drive torques and each sole half's normal force to the window's sums."""
        data = self.data
        self._n += 1
        efc = data.efc_force.tolist()
        if self._drive_rows is None:  # equality rows come first in MuJoCo's order: fixed indices
            eq_type, efc_id = int(self.mj.mjtConstraint.mjCNSTR_EQUALITY), data.efc_id
            kind = np.asarray(data.efc_type, dtype=int)
            self._drive_rows = [int(np.flatnonzero((kind == eq_type) & (efc_id == eq))[0]) for eq in self.drives]
        torque = self._torque
        for i, row in enumerate(self._drive_rows):  # a joint equality's row has J = 1 on its crank
            torque[i] += efc[row]
        if not data.ncon:
            return
        # a few dozen contacts at most: scalar arithmetic on lists is cheaper than numpy's per-call cost
        # here, and a list's float sums are the very IEEE sums of numpy's float64 scalars, in the same order
        contact = data.contact  # ncon long: its fields need no slicing
        xpos, (s0, s1, s2, s3) = self._site_xpos, self._ends
        heel_r, toe_r, heel_l, toe_l = xpos.item(s0, 0), xpos.item(s1, 0), xpos.item(s2, 0), xpos.item(s3, 0)
        middle = (0.5 * (heel_r + toe_r), 0.5 * (heel_l + toe_l))
        length = (toe_r - heel_r, toe_l - heel_l)
        foot_of_geom = self._foot_of_geom
        force = [0.0, 0.0, 0.0, 0.0]  # this step's sums, then added to the window's
        for a, geoms, pos in zip(contact.efc_address.tolist(), contact.geom.tolist(), contact.pos.tolist()):
            foot = foot_of_geom[max(geoms)]
            if a < 0 or foot < 0:
                raise SimulationError("a contact that is not a sole's pyramidal condim-3 contact with the floor")
            normal = efc[a] + efc[a + 1] + efc[a + 2] + efc[a + 3]  # the pyramid's edges
            force[2 * foot + ((pos[0] - middle[foot]) * length[foot] >= 0.0)] += normal  # the toe half in x
        window = self._force
        for k in range(4):
            window[k] += force[k]

    def sample(self, t: float) -> GaitSample:
        """The judge's sample at ``t`` [s]: this instant's pose, the forces averaged (:data:`LOAD_WINDOW`).

        On Python floats: the very divisions, sums (numpy's mean over the rows adds them in row order,
        then divides) and products numpy gave, without its per-call cost on 4 numbers.
        """
        n = max(self._n, 1)
        recent = self._recent
        recent[self._slot % len(recent)] = [f / n for f in self._force]
        self._slot += 1
        rows = recent[: self._slot]
        total = list(rows[0])
        for row in rows[1:]:
            for k in range(4):
                total[k] += row[k]
        force = [f / len(rows) for f in total]  # right heel half, right toe half, left heel half, left toe half [N]
        feet = (self._foot(0, force[0], force[1]), self._foot(1, force[2], force[3]))
        qvel = self.data.qvel
        power = [tau / n * qvel.item(dof) for tau, dof in zip(self._torque, self.dofs)]
        if self.one_motor:
            power = [sum(power)]
        self._reset_window()
        hip_x, pitch = self.hip()
        return GaitSample(t, hip_x, pitch, feet, tuple(power))

    def _foot(self, i: int, heel_force: float, toe_force: float) -> FootSample:
        """Foot ``i``'s sample from its heel and toe halves' average normal forces [N]."""
        heel_site, toe_site = self.sites[i]
        heel_x, heel_z = self._along(*self._xz(heel_site))
        toe_x, toe_z = self._along(*self._xz(toe_site))
        normal = heel_force + toe_force
        slip = 0.0
        for site, half in ((heel_site, heel_force), (toe_site, toe_force)):
            if half > LOAD_TOL:  # the site's linear velocity, along the ground
                self.mj.mj_objectVelocity(self.model, self.data, self.mj.mjtObj.mjOBJ_SITE, site, self._velocity, 0)
                velocity = self._velocity
                slip = max(slip, abs(self._along(velocity.item(3), velocity.item(5))[0]))
        return FootSample(
            loaded=normal > LOAD_TOL,
            x=0.5 * (heel_x + toe_x),
            pitch=math.atan2(toe_z - heel_z, toe_x - heel_x),
            normal=normal,
            slip=slip,
            on_point=(heel_force > LOAD_TOL) != (toe_force > LOAD_TOL),
        )

    def _xz(self, site: int) -> tuple[float, float]:
        """A site's world x and z [m]."""
        return self._site_xpos.item(site, 0), self._site_xpos.item(site, 2)

    def _along(self, x: float, z: float) -> tuple[float, float]:
        """A world point's or velocity's (x, z) read along the ground and across it (itself on the flat floor)."""
        if self.turn == 1.0:
            return x, z
        at = complex(x, z) * self.turn
        return at.real, at.imag

    def crank_error(self, t: float) -> float:
        """The largest |crank - schedule| at ``t`` [rad] (the drives' lag not added)."""
        angles, _ = self._angles(t)
        qpos = self.data.qpos
        return max(abs(qpos.item(adr) - angle) for adr, angle in zip(self.qadr, angles))

    def hip(self) -> tuple[float, float]:
        """The hip's position along the ground [m] and its pitch from the ground's normal [rad] (as ours)."""
        qpos = self.data.qpos
        if not self.spatial:
            if self.turn == 1.0:
                return float(qpos[HIP_X]), float(qpos[HIP_PITCH])
            return (complex(qpos[HIP_X], qpos[HIP_Z]) * self.turn).real, float(qpos[HIP_PITCH]) - self.floor.slope
        return float(qpos[0]), self.attitude()[1]

    def attitude(self) -> tuple[float, float, float]:
        """The 3-D hip's roll, pitch (planar convention) and yaw [rad]."""
        w, x, y, z = self.data.qpos[3:7]
        return roll_pitch_yaw(np.array([0.0, 0.0, 0.0, x, y, z, w]))

    def start_sample(self) -> GaitSample:
        """The judge's first sample: a point within 1 um of the floor counts as loaded (as ours).

        MuJoCo's kinematics run first: before its first step the sites' positions are not yet computed.
        """
        self.mj.mj_kinematics(self.model, self.data)
        sample = self.sample(0.0)
        self._slot = 0  # the start's zero forces are no part of the first window
        feet = []
        for i, foot in enumerate(sample.feet):
            heights = [self._along(*self._xz(s))[1] - self.options.sole_radius for s in self.sites[i]]
            on = [h < 1e-6 for h in heights]
            feet.append(foot._replace(loaded=any(on), on_point=on[0] != on[1], normal=0.0, slip=0.0))
        return sample._replace(feet=(feet[0], feet[1]), motor_power=tuple(0.0 for _ in sample.motor_power))

    def broken(self) -> str:
        """Why MuJoCo's state is not to be trusted (empty: it is fine).

        On lists: a few dozen numbers, where numpy's per-call cost is most of the check's.
        """
        data = self.data
        counts = data.warning.number.tolist()
        for index, name in self._warnings:
            if counts[index]:
                return f"MuJoCo warned {name} (it reset the state)"
        qpos, qvel = data.qpos.tolist(), data.qvel.tolist()
        if not (all(map(math.isfinite, qpos)) and all(map(math.isfinite, qvel))):
            return "the state is not finite"
        if max(map(abs, qvel)) > SPEED_LIMIT:  # every number finite here: no NaN in the max
            return f"a velocity passed {SPEED_LIMIT:g}"
        return ""


def _judged(judge: GaitJudge, sample: GaitSample, twin: _Twin, t: float) -> bool:
    """Feed the judge one sample (and the 3-D hip's roll): True once the walk may stop."""
    decided = judge.update(sample)
    if not twin.spatial:
        return decided
    judge.roll(t, twin.attitude()[0])
    return judge.final(t)


def walk_in_mujoco(
    design,
    settings: WalkSettings | None = None,
    robot=None,
    options: MjcfOptions | None = None,
    spatial: bool = False,
) -> MujocoWalk:
    """Walk ``design`` in MuJoCo and judge it as :func:`walk_design` does (see the module docstring).

    Args:
        design: a :class:`~pasibot_pin.model.design.Design`.
        settings: :class:`~pasibot_pin.studies.walking.WalkSettings` (steps, mu; its ``dt`` is ours,
            MuJoCo steps at ``options.timestep``).
        robot: its two-legged robot, if already built.
        options: the export's contacts, drives and step (default :data:`MJ_WALK`; the design's
            spring and the walk's mu are filled in).
        spatial: walk the 3-D export (a free hip, the design's soles as boxes:
            ``design.footprint()``), judged as :func:`~pasibot_pin.studies.walking.walk_design_3d`
            (``tipped`` past :data:`~pasibot_pin.dynamics.verdict.TIP_LIMIT` of roll).

    Returns:
        :class:`MujocoWalk`; a walk that fails (or a MuJoCo that breaks) is its verdict.

    Raises:
        MissingExtraError: mujoco is not installed.
        ParameterError: bad settings or a crank speed below the walk's minimum.
        DesignError: the design cannot be built.

    """
    check_twin(design)
    mujoco = _mujoco()
    settings = WalkSettings() if settings is None else settings
    robot = design_robot(design, 2, visuals=False) if robot is None else robot
    options = mujoco_options(design, settings, robot, MJ_WALK if options is None else options)
    if spatial:
        options = replace(options, footprint=design.footprint())
    twin = _Twin(mujoco, robot, design, settings, options)
    h = float(twin.model.opt.timestep)
    every = max(1, round(SAMPLE_DT / h))
    judge = GaitJudge(twin.floor.omega, robot.geometry.L, twin.weight, settings.judged_by(), twin.start_sample())
    rows: list[tuple] = []
    crank_error, t = 0.0, 0.0
    for k in range(math.ceil(walk_duration(twin.floor.omega, settings.steps) / h - 1e-9)):
        try:
            twin.step(k * h)
        except mujoco.FatalError as err:
            judge.diverged(t, f"MuJoCo failed: {err}")
            break
        t = (k + 1) * h
        if (k + 1) % every:
            continue
        broken = twin.broken()
        if broken:
            judge.diverged(t, f"MuJoCo diverged: {broken}")
            break
        sample = twin.sample(t)
        crank_error = max(crank_error, twin.crank_error(t))
        feet = sample.feet
        rows.append((t, sample.hip_x, sample.hip_pitch, *(f.loaded for f in feet), *(f.normal for f in feet)))
        if _judged(judge, sample, twin, t):
            break
    trace = np.array(rows, dtype=float).reshape(-1, 7)
    return MujocoWalk(
        verdict=judge.verdict(t),
        omega=twin.floor.omega,
        dt=h,
        sample_dt=every * h,
        start_kind=twin.start_kind,
        t=trace[:, 0],
        hip_x=trace[:, 1],
        hip_pitch=trace[:, 2],
        loaded=trace[:, 3:5].astype(bool),
        normal=trace[:, 5:7],
        max_crank_error=crank_error,
        options=options,
        max_hip_roll_deg=math.degrees(judge.max_roll) if twin.spatial else math.nan,
    )
