"""Benchmark: constrained inverse dynamics per sample vs one bare ``pin.rnea`` and vs the seed's method.

Measured in one run, on the same model (the ``spring`` biped, run 4: 5 rad/s, body 20 kg):

1. one bare ``pin.rnea(q, v, a)`` (nv = 19);
2. our constrained ID step for a sample on the manifold: rnea + the in-plane constraint
   Jacobian + the square split tau = S^T u + J_c^T lambda, with J_c from our vectorised
   ``ConstraintSystem`` or from Pinocchio's C++ ``getConstraintsJacobian``
   (``constraints.pinocchio_constraint_jacobian``, in-plane rows);
3. the whole per-sample pipeline of ``dynamics.inverse_dynamics``, batched over the samples of a
   sweep: q, v and a from the closed form on jets (a batched evaluation of the rows checks the
   closure; Newton only where it is open), tau and every joint reaction from the batched planar
   Newton-Euler (``dynamics.planar_id``: no per-sample Pinocchio call), the split on the passive
   rows: the 41-sample stance theta in [pi/2, 3 pi/2] (one batch: a sweep ending at touchdown
   keeps its stance) and one 400-sample stance;
4. the seed's Newton-Euler free-body method, in clean numpy: assemble A (48 x 48) and b from
   the joint positions, COM positions and COM accelerations of the 16 bodies, then solve
   A.F = b (its T_e is checked against ours).

5. the same method batched over the whole stance (:class:`SeedFreeBodyBatch`): the fair
   comparison. "One full sample" is the same unit of work on both sides: from a crank angle
   to T_a, T_e and every joint force, batched over the same 41-sample stance. The seed's side
   includes its kinematics (closed-form assembly at theta and theta +- 0.1 rad for its
   second-difference accelerations) and its batched 48 x 48 solves; ours includes Newton for q,
   exact v and a, the ID, the split and every reaction. Our pipeline with the seed's own
   accelerations (``accelerations="central"``) gives the same T_a, T_e to 1e-9 (checked). The
   issue's old ratio (the seed's assemble + solve alone, for one sample in a Python loop, its
   kinematics given for free, over our batched sample) is printed too, labelled as such, and
   the same port called one sample at a time with its kinematics (5. on a one-sample batch).

Every case is timed in each of ``ROUNDS`` rounds, in turn (interleaved), and keeps its best round.
Times are the process's CPU time (user + sys, ``time.process_time``), not wall time: on a shared
machine the process is descheduled for whole milliseconds, which a wall clock charges to whichever
case is running, while its CPU time does not count them; the best of the interleaved rounds then
sheds what remains (cache and memory contention). BLAS runs on one thread: on this 2-core
machine its worker threads, left spinning after a batched solve, slow every measurement that
follows (a bare rnea by up to 2x).

Prints times and ratios. Run: ``.venv/bin/python benchmarks/bench_dynamics.py``.
"""

from __future__ import annotations

import math
import os
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before numpy loads OpenBLAS (see the docstring)

import numpy as np
import pinocchio as pin

from pasibot_pin import constraints
from pasibot_pin.constraints.planar import PlanarRowBlocks
from pasibot_pin.constraints.system import planar_kinematics
from pasibot_pin.dynamics import inverse as dynamics
from pasibot_pin.dynamics import simulator as simulate
from pasibot_pin.dynamics import stance_plan
from pasibot_pin.model import closure, scenarios
from pasibot_pin.model.scenario_robots import scenario_robot
from pasibot_pin.studies import spring_study

REPEAT = 200
ROUNDS = 25
CLOCK = time.process_time
"""CPU time of the process (user + sys) [s]: see the docstring."""
G = 9.81


def best_time(func, repeat: int = REPEAT, rounds: int = 5) -> float:
    """Smallest mean time of ``rounds`` batches of ``repeat`` calls [s]."""
    best = math.inf
    for _ in range(rounds):
        start = CLOCK()
        for _ in range(repeat):
            func()
        best = min(best, (CLOCK() - start) / repeat)
    return best


# --------------------------------------------------------------------------- the seed's free-body method
LINKS = {
    "L1": "j0_crank",
    "L2": "j1",
    "L3": "j3",
    "L4": "j4",
    "L5": "j6",
    "L6": "j8_l6",
    "L7": "j8_l7",
    "foot": "j13_ankle",
}
# joint -> (point name, body receiving +F, body receiving -F)
JOINTS = [
    ("j0", "p0", "L1", "body"),
    ("j1", "p1", "L2", "L1"),
    ("j2", "p2", "L2", "L3"),
    ("j3", "p3", "L3", "body"),
    ("j4", "p4", "L4", "L2"),
    ("j5", "p5", "L4", "L6"),
    ("j6", "p6", "L5", "L4"),
    ("j7", "p7", "L5", "L7"),
    ("j8_l6", "p8", "L6", "body"),
    ("j8_l7", "p8", "L7", "body"),
    ("j13", "p13", "foot", "L5"),
]


def sample_geometry(robot, q, v, a, stance="right"):
    """Joint points, COM positions, COM accelerations and masses of a sample (world x, z) [m, m/s^2, kg]."""
    model, data = robot.model, robot.data
    pin.forwardKinematics(model, data, q, v, a)
    pin.updateFramePlacements(model, data)
    out = {"points": {}, "com": {}, "acc": {}, "mass": {}}
    for side, tag in ((stance, "st"), ("left" if stance == "right" else "right", "sw")):
        joint_point = {
            "p0": "j0_crank",
            "p1": "j1",
            "p3": "j3",
            "p4": "j4",
            "p6": "j6",
            "p8": "j8_l6",
            "p13": "j13_ankle",
        }
        for name, joint in joint_point.items():
            out["points"][(tag, name)] = data.oMi[model.getJointId(f"{side}_{joint}")].translation[[0, 2]].copy()
        for name, frame in (("p2", "loop_j2_a"), ("p5", "loop_j5_a"), ("p7", "loop_j7_a")):
            out["points"][(tag, name)] = data.oMf[model.getFrameId(f"{side}_{frame}")].translation[[0, 2]].copy()
        for body, joint in LINKS.items():
            if tag == "st" and body == "foot":
                continue  # the stance foot is the ground
            jid = model.getJointId(f"{side}_{joint}")
            out_key = (tag, body)
            com_world, acc = _com_state(data, jid, model.inertias[jid].lever)
            out["com"][out_key], out["acc"][out_key] = com_world, acc
            out["mass"][out_key] = model.inertias[jid].mass
    hip = model.getJointId("hip_planar")
    out["com"][("x", "body")], out["acc"][("x", "body")] = _com_state(data, hip, model.inertias[hip].lever)
    out["mass"][("x", "body")] = model.inertias[hip].mass
    return out


def _com_state(data, jid, lever):
    placement = pin.SE3(np.eye(3), lever)
    vel, acc = placement.actInv(data.v[jid]), placement.actInv(data.a[jid])
    rot = data.oMi[jid].rotation
    classical = rot @ (acc.linear + np.cross(vel.angular, vel.linear))
    return data.oMi[jid].act(lever)[[0, 2]], classical[[0, 2]]


def free_body_solve(geo):
    """Assemble and solve the seed's A.F = b: 48 unknowns (22 joint forces x 2 + 4 torques)."""
    bodies = list(geo["com"])
    row = {b: 3 * k for k, b in enumerate(bodies)}
    unknowns = [(tag, j[0]) for tag in ("st", "sw") for j in JOINTS]
    col = {u: 2 * k for k, u in enumerate(unknowns)}
    torque_col = {("st", "Ta"): 44, ("st", "Te"): 45, ("sw", "Ta"): 46, ("sw", "Te"): 47}
    n = 48
    a_mat, b_vec = np.zeros((n, n)), np.zeros(n)
    for tag in ("st", "sw"):
        for name, point, first, second in JOINTS:
            p = geo["points"][(tag, point)]
            c = col[(tag, name)]
            for body, sign in ((first, 1.0), (second, -1.0)):
                key = ("x", "body") if body == "body" else (tag, body)
                if key not in row:
                    continue
                r = row[key]
                arm = p - geo["com"][key]
                a_mat[r, c] += sign
                a_mat[r + 1, c + 1] += sign
                a_mat[r + 2, c] -= sign * arm[1]
                a_mat[r + 2, c + 1] += sign * arm[0]
        a_mat[row[(tag, "L1")] + 2, torque_col[(tag, "Ta")]] += 1.0
        a_mat[row[("x", "body")] + 2, torque_col[(tag, "Ta")]] -= 1.0
        a_mat[row[(tag, "L5")] + 2, torque_col[(tag, "Te")]] += 1.0
        if (tag, "foot") in row:
            a_mat[row[(tag, "foot")] + 2, torque_col[(tag, "Te")]] -= 1.0
    for key, r in row.items():
        m = geo["mass"][key]
        b_vec[r] = m * geo["acc"][key][0]
        b_vec[r + 1] = m * (geo["acc"][key][1] + G)
    sol = np.linalg.solve(a_mat, b_vec)
    return {k: sol[c] for k, c in torque_col.items()}


class SeedFreeBodyBatch:
    """The seed's free-body method for a whole stance at once, in vectorised numpy (the fair port).

    Everything the seed computes from a crank angle, for N samples together:

    1. its kinematics: the closed-form assembly of the three crank angles theta - d, theta,
       theta + d of every sample (``closure.analytic_configurations``, the loop equations solved
       in closed form, as the seed's DH tables do), then the world (x, z) of the 20 joint points
       and the 16 centres of mass (``PlanarRowBlocks.positions``: a few complex products);
    2. its accelerations: second differences of the COM positions, d / omega apart in time;
    3. A (N, 48, 48) and b (N, 48) from index tables built once (the +-1 entries are constant,
       the lever arms are filled in one fancy assignment), and one batched ``np.linalg.solve``.

    The same equations as :func:`free_body_solve` (checked against it and against our inverse
    dynamics with the same second-difference accelerations).
    """

    def __init__(self, robot, stance: str = "right"):
        model = robot.model
        self.robot, self.stance = robot, stance
        swing = "left" if stance == "right" else "right"
        sides = {"st": stance, "sw": swing}
        ends, names = [], []  # (joint, translation) of every point, then of every COM
        joint_point = {
            "p0": "j0_crank",
            "p1": "j1",
            "p3": "j3",
            "p4": "j4",
            "p6": "j6",
            "p8": "j8_l6",
            "p13": "j13_ankle",
        }
        for tag, side in sides.items():
            for name, joint in joint_point.items():
                ends.append((model.getJointId(f"{side}_{joint}"), np.zeros(3)))
                names.append(("point", tag, name))
            for name, frame in (("p2", "loop_j2_a"), ("p5", "loop_j5_a"), ("p7", "loop_j7_a")):
                f = model.frames[model.getFrameId(f"{side}_{frame}")]
                ends.append((int(f.parentJoint), np.array(f.placement.translation)))
                names.append(("point", tag, name))
        bodies = []
        for tag, side in sides.items():
            for body, joint in LINKS.items():
                if tag == "st" and body == "foot":
                    continue
                bodies.append(((tag, body), model.getJointId(f"{side}_{joint}")))
        bodies.append((("x", "body"), model.getJointId("hip_planar")))
        for key, jid in bodies:
            ends.append((jid, np.array(model.inertias[jid].lever)))
            names.append(("com",) + key)
        joints = np.array([e[0] for e in ends])
        trans = np.array([e[1] for e in ends])
        rots = np.repeat(np.eye(3)[None], len(ends), axis=0)
        kin = planar_kinematics(model)
        self.ends = PlanarRowBlocks(kin.ends(joints, trans, rots), [(k, -1) for k in range(len(ends))], [])
        index = {name: k for k, name in enumerate(names)}
        self.n_points = sum(1 for n in names if n[0] == "point")
        self.mass = np.array([model.inertias[jid].mass for _, jid in bodies])
        body_row = {key: 3 * k for k, (key, _) in enumerate(bodies)}
        com_of = {key: index[("com",) + key] - self.n_points for key, _ in bodies}
        unknowns = [(tag, j[0]) for tag in ("st", "sw") for j in JOINTS]
        col = {u: 2 * k for k, u in enumerate(unknowns)}
        torque_col = {("st", "Ta"): 44, ("st", "Te"): 45, ("sw", "Ta"): 46, ("sw", "Te"): 47}
        n = 48
        a0 = np.zeros((n, n))
        arm_rows, arm_cols, arm_points, arm_coms, arm_signs = [], [], [], [], []
        for tag in ("st", "sw"):
            for name, point, first, second in JOINTS:
                c = col[(tag, name)]
                for body, sign in ((first, 1.0), (second, -1.0)):
                    key = ("x", "body") if body == "body" else (tag, body)
                    if key not in body_row:
                        continue
                    r = body_row[key]
                    a0[r, c] += sign
                    a0[r + 1, c + 1] += sign
                    arm_rows.append(r + 2)
                    arm_cols.append(c)
                    arm_points.append(index[("point", tag, point)])
                    arm_coms.append(com_of[key])
                    arm_signs.append(sign)
            a0[body_row[(tag, "L1")] + 2, torque_col[(tag, "Ta")]] += 1.0
            a0[body_row[("x", "body")] + 2, torque_col[(tag, "Ta")]] -= 1.0
            a0[body_row[(tag, "L5")] + 2, torque_col[(tag, "Te")]] += 1.0
            if (tag, "foot") in body_row:
                a0[body_row[(tag, "foot")] + 2, torque_col[(tag, "Te")]] -= 1.0
        assert len(set(zip(arm_rows, arm_cols))) == len(arm_rows)  # each lever-arm entry is written once
        self.a0 = a0
        self.arm_rows, self.arm_cols = np.array(arm_rows), np.array(arm_cols)
        self.arm_points, self.arm_coms, self.arm_signs = np.array(arm_points), np.array(arm_coms), np.array(arm_signs)
        self.force_rows = np.array([body_row[key] for key, _ in bodies])
        self.torque_col = torque_col

    def run(self, thetas: np.ndarray, omega: float, step: float = 0.1) -> dict:
        """T_a, T_e of both legs (N,) [N.m] along ``thetas`` (right crank, stance ``self.stance``)."""
        n = len(thetas)
        shifted = np.concatenate((thetas - step, thetas, thetas + step))
        q = closure.analytic_configurations(self.robot, shifted, None, 0.0, 0.0, self.stance, 0.0)[0]
        where = self.ends.positions(q)  # (3N, points + COMs), complex x + i z [m]
        points = where[n : 2 * n, : self.n_points]
        coms = where[:, self.n_points :]
        com = coms[n : 2 * n]
        acc = (coms[2 * n :] - 2.0 * com + coms[:n]) / (step / omega) ** 2
        arm = points[:, self.arm_points] - com[:, self.arm_coms]
        a_mat = np.repeat(self.a0[None], n, axis=0)
        a_mat[:, self.arm_rows, self.arm_cols] = -self.arm_signs * arm.imag
        a_mat[:, self.arm_rows, self.arm_cols + 1] = self.arm_signs * arm.real
        b_vec = np.zeros((n, 48))
        b_vec[:, self.force_rows] = self.mass * acc.real
        b_vec[:, self.force_rows + 1] = self.mass * (acc.imag + G)
        sol = np.linalg.solve(a_mat, b_vec[:, :, None])[:, :, 0]
        return {k: sol[:, c] for k, c in self.torque_col.items()}


def main() -> None:
    scenario = scenarios.SCENARIOS["run4"]
    choices = scenarios.PRESETS["default"]
    robot = scenario_robot(scenario, choices)
    thetas = np.linspace(math.pi / 2, 3 * math.pi / 2, 41)
    res = dynamics.inverse_dynamics(robot, thetas, scenario.omega)
    model, data = robot.model, robot.data
    k = 17
    q, v, a = res.q[k], res.v[k], res.a[k]

    rs = robot.with_stance("right", q)
    rows = closure.system(rs, rs.constraint_models, stance_plan.prescriptions(rs, "right", "level"))
    s_matrix = stance_plan.actuation(rs, "right")

    def constrained_step():
        tau = pin.rnea(model, rs.data, q, v, a)
        jc = rows.constraint_jacobian(q)
        return constraints.split_torques(tau, s_matrix, jc)

    cdata = model.createData()
    index, sign = constraints.inplane_rows(rs.constraint_models)

    def constrained_step_pin():
        tau = pin.rnea(model, cdata, q, v, a)
        jac = constraints.pinocchio_constraint_jacobian(model, cdata, rs.constraint_models, q)
        return constraints.split_torques(tau, s_matrix, jac[index] * sign)

    u, _ = constrained_step()
    u_pin, _ = constrained_step_pin()
    assert np.allclose(u, u_pin, rtol=1e-10, atol=1e-10)
    geo = sample_geometry(rs, q, v, a)
    fb = free_body_solve(geo)
    assert abs(fb[("st", "Te")] + u[2]) < 1e-6 * max(1.0, abs(u[2])), (fb, u)
    assert abs(fb[("st", "Ta")] - u[0]) < 1e-6 * max(1.0, abs(u[0])), (fb, u)

    # the seed's method over the same stance, vectorised, checked against our inverse dynamics with
    # the same second-difference accelerations (the seed's: COM positions d = 0.1 rad apart)
    seed = SeedFreeBodyBatch(robot)
    seed_torques = seed.run(thetas, scenario.omega)
    central = dynamics.inverse_dynamics(robot, thetas, scenario.omega, accelerations="central", step=0.1)
    for key, ours in ((("st", "Ta"), central.Ta), (("st", "Te"), central.Te), (("sw", "Ta"), central.Ta_swing)):
        assert np.allclose(seed_torques[key], ours, rtol=1e-9, atol=1e-9), key
    batch_geo = sample_geometry(rs, q, v, a)  # the per-sample loop port, geometry given (the old line)
    assert abs(free_body_solve(batch_geo)[("st", "Te")] - fb[("st", "Te")]) < 1e-12

    # forward dynamics and one RK4 step of the simulator (run 1's fitted spring, hip free)
    inputs = spring_study.scenario_inputs("run1")
    settings = simulate.SimulationSettings(omega=inputs.omega, spring=inputs.fit, dt=2e-3)
    sim = simulate.BipedSimulator(inputs.robot, settings)
    q0, v0, stance = sim.initial_state()
    cset = sim.constraint_set(stance, sim.ground_weld(stance, q0))
    from pasibot_pin.dynamics.floor.engine import FloorSimulator
    from pasibot_pin.dynamics.floor.settings import FloorSettings

    floor = FloorSimulator(inputs.robot, FloorSettings(omega=inputs.omega, spring=inputs.fit))
    fq, fv = floor.initial_state()
    long = np.linspace(math.pi / 2, 3 * math.pi / 2, 401)[:-1]
    sim_model, sim_data = inputs.robot.model, inputs.robot.data

    # Every case is timed in each of ROUNDS rounds, in turn, and keeps its best round: on a shared
    # machine a busy moment then slows one round of every case, not all rounds of one case.
    cases = {
        "rnea": (lambda: pin.rnea(model, data, q, v, a), 2000, 1),
        "rnea_sim": (lambda: pin.rnea(sim_model, sim_data, q0, v0, v0), 2000, 1),
        "step": (constrained_step, 100, 1),
        "step_pin": (constrained_step_pin, 50, 1),
        "full": (lambda: dynamics.inverse_dynamics(robot, thetas, scenario.omega), 3, len(thetas)),
        "bare": (lambda: dynamics.inverse_dynamics(robot, thetas, scenario.omega, reactions=False), 3, len(thetas)),
        "long": (lambda: dynamics.inverse_dynamics(robot, long, scenario.omega), 1, len(long)),
        "central": (
            lambda: dynamics.inverse_dynamics(robot, thetas, scenario.omega, accelerations="central"),
            1,
            len(thetas),
        ),
        "seed_batch": (lambda: seed.run(thetas, scenario.omega), 3, len(thetas)),
        "seed_loop": (lambda: free_body_solve(geo), 20, 1),
        "seed_loop_kin": (lambda: [seed.run(thetas[k : k + 1], scenario.omega) for k in range(len(thetas))], 1, 41),
        "fd": (lambda: sim.acceleration(cset, 0.0, q0, v0), 100, 1),
        "rk4": (lambda: sim.step(cset, 0.0, q0, v0, 2e-3), 10, 1),
        "floor": (lambda: floor.step(0.0, fq, fv, floor.settings.dt), 10, 1),
    }
    best = dict.fromkeys(cases, math.inf)
    for _ in range(ROUNDS):
        for name, (func, repeat, per) in cases.items():
            start = CLOCK()
            for _ in range(repeat):
                func()
            best[name] = min(best[name], (CLOCK() - start) / (repeat * per))
    t_rnea, t_rnea_sim = best["rnea"], best["rnea_sim"]

    def line(label: str, seconds: float, ref: float, goal: str) -> None:
        print(f"{label:58s}: {seconds * 1e6:9.1f} us = {seconds / ref:7.1f} x rnea   ({goal})")

    print(f"model nv = {model.nv}, sample theta = {thetas[k]:.3f} rad, omega = {scenario.omega} rad/s")
    print(
        f"free-body check: T_a {fb[('st', 'Ta')]:.6f} vs ours {u[0]:.6f} N.m; "
        f"T_e {fb[('st', 'Te')]:.6f} vs {-u[2]:.6f} N.m"
    )
    print(f"{'bare pin.rnea':58s}: {t_rnea * 1e6:9.2f} us")
    line("full sample: q, v, a, ID, every reaction", best["full"], t_rnea, "goal <= 30")
    line("full sample without reactions", best["bare"], t_rnea, "goal <= 15")
    line("full sample, every reaction, one 400-sample stance", best["long"], t_rnea, "")
    line("full sample, the seed's second-difference accelerations", best["central"], t_rnea, "")
    line("constrained ID step alone (rnea + J_c + split)", best["step"], t_rnea, "")
    line("the same, J_c from Pinocchio's getConstraintsJacobian", best["step_pin"], t_rnea, "")
    line("one forward-dynamics evaluation (KKT, simulator rows)", best["fd"], t_rnea_sim, "goal <= 20")
    line("one RK4 step with projection", best["rk4"], t_rnea_sim, "goal <= 100")
    line("one floor step (contact QP + projection)", best["floor"], t_rnea_sim, "goal <= 2 x the welded step")
    print(
        f"floor step / welded RK4 step: {best['floor'] / best['rk4']:5.2f}; simulated time per wall second: "
        f"welded {2e-3 / best['rk4']:5.1f}, floor {floor.settings.dt / best['floor']:5.1f}   "
        "(goal: 10 s of walking < 10 s wall)"
    )
    line("seed free-body, whole stance batched: kinematics, A, solve", best["seed_batch"], t_rnea, "")
    line("seed free-body, A.F = b alone, one sample (geometry given)", best["seed_loop"], t_rnea, "")
    line("seed free-body, one sample per call, its kinematics included", best["seed_loop_kin"], t_rnea, "")
    full, bare, batch, loop = best["full"], best["bare"], best["seed_batch"], best["seed_loop"]
    print(
        "speed-up of one full sample over the seed's free-body method (goal >= 10):\n"
        "  the issue's metric: the seed's port per sample (its A.F = b, geometry given, one sample in a\n"
        "  Python loop, as the issue measured it) over our full sample, batched over the 41-sample stance:\n"
        f"    ours with every reaction:    {loop / full:6.2f} x\n"
        f"    ours without reactions:      {loop / bare:6.2f} x\n"
        "  the seed's port one sample per call with its kinematics (the batched port below, called per\n"
        "  sample: closed-form assembly at theta and theta +- 0.1 rad, A, solve) over our batched full sample:\n"
        f"    ours with every reaction:    {best['seed_loop_kin'] / full:6.2f} x\n"
        "  like for like: both batched over the same 41-sample stance, from crank angles to T_a, T_e\n"
        "  and every joint force (the seed's side with its kinematics):\n"
        f"    ours with every reaction:    {batch / full:6.2f} x\n"
        f"    ours without reactions:      {batch / bare:6.2f} x\n"
        f"    ours, the seed's second differences (same T): {batch / best['central']:6.2f} x\n"
        "  the floor: like for like, 10 x needs a full sample in "
        f"{batch / 10 * 1e6:.1f} us = {batch / 10 / t_rnea:.2f} x rnea; the issue's metric, 10 x needs\n"
        f"  {loop / 10 * 1e6:.1f} us = {loop / 10 / t_rnea:.2f} x rnea"
    )


if __name__ == "__main__":
    main()
