"""Benchmark: constrained inverse dynamics per sample vs one bare ``pin.rnea`` and vs the seed's method.

Measured in one run, on the same model (the ``spring`` biped, run 4: 5 rad/s, body 20 kg):

1. one bare ``pin.rnea(q, v, a)`` (nv = 19);
2. our constrained ID step for a sample on the manifold: rnea + the in-plane constraint
   Jacobian + the square split tau = S^T u + J_c^T lambda, with J_c from our vectorised
   ``ConstraintSystem`` or from Pinocchio's C++ ``getConstraintsJacobian``
   (``constraints.pinocchio_constraint_jacobian``, in-plane rows);
3. the whole per-sample pipeline of ``dynamics.inverse_dynamics`` (Newton for q, exact v and a
   with drift, the split and every joint reaction), batched over the samples of a sweep: the
   41-sample stance of the earlier benchmark (whose last sample, theta = 3 pi/2, starts the next
   stance: two batches) and one 400-sample stance;
4. the seed's Newton-Euler free-body method, in clean numpy: assemble A (48 x 48) and b from
   the joint positions, COM positions and COM accelerations of the 16 bodies, then solve
   A.F = b (its T_e is checked against ours).

Prints times and ratios. Run: ``.venv/bin/python benchmarks/bench_dynamics.py``.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pinocchio as pin

from pasibot_pin import constraints
from pasibot_pin.dynamics import inverse as dynamics
from pasibot_pin.dynamics import simulator as simulate
from pasibot_pin.model import closure, scenarios
from pasibot_pin.studies import spring_study

REPEAT = 200
G = 9.81


def best_time(func, repeat: int = REPEAT, rounds: int = 5) -> float:
    """Smallest mean time of ``rounds`` batches of ``repeat`` calls [s]."""
    best = math.inf
    for _ in range(rounds):
        start = time.perf_counter()
        for _ in range(repeat):
            func()
        best = min(best, (time.perf_counter() - start) / repeat)
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


def main() -> None:
    scenario = scenarios.SCENARIOS["run4"]
    choices = scenarios.PRESETS["default"]
    robot = dynamics.scenario_robot(scenario, choices)
    thetas = np.linspace(math.pi / 2, 3 * math.pi / 2, 41)
    res = dynamics.inverse_dynamics(robot, thetas, scenario.omega)
    model, data = robot.model, robot.data
    k = 17
    q, v, a = res.q[k], res.v[k], res.a[k]

    rs = robot.with_stance("right", q)
    rows = closure.system(rs, rs.constraint_models, dynamics._prescriptions(rs, "right", "level"))
    s_matrix = dynamics._actuation(rs, "right")

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

    t_rnea = best_time(lambda: pin.rnea(model, data, q, v, a), repeat=5000)
    t_step = best_time(constrained_step)
    t_step_pin = best_time(constrained_step_pin)
    t_fb = best_time(lambda: free_body_solve(geo))

    def pipeline(reactions: bool) -> float:
        """Per-sample cost of dynamics.inverse_dynamics over one stance (best of 7 runs) [s]."""
        best = math.inf
        for _ in range(7):
            start = time.perf_counter()
            dynamics.inverse_dynamics(robot, thetas, scenario.omega, reactions=reactions)
            best = min(best, (time.perf_counter() - start) / len(thetas))
        return best

    t_full = pipeline(True)
    t_bare = pipeline(False)
    long = np.linspace(math.pi / 2, 3 * math.pi / 2, 401)[:-1]
    best_long = math.inf
    for _ in range(5):
        start = time.perf_counter()
        dynamics.inverse_dynamics(robot, long, scenario.omega)
        best_long = min(best_long, (time.perf_counter() - start) / len(long))

    # forward dynamics and one RK4 step of the simulator (run 1's fitted spring, hip free)
    inputs = spring_study.scenario_inputs("run1")
    settings = simulate.SimulationSettings(omega=inputs.omega, spring=inputs.fit, dt=2e-3)
    sim = simulate.BipedSimulator(inputs.robot, settings)
    q0, v0, stance = sim.initial_state()
    cset = sim.constraint_set(stance, sim.ground_weld(stance, q0))
    t_fd = best_time(lambda: sim.acceleration(cset, 0.0, q0, v0))
    t_rk4 = best_time(lambda: sim.step(cset, 0.0, q0, v0, 2e-3), repeat=50)
    t_rnea_sim = best_time(lambda: pin.rnea(inputs.robot.model, inputs.robot.data, q0, v0, v0), repeat=5000)
    from pasibot_pin.dynamics.floor import FloorSettings, FloorSimulator

    floor = FloorSimulator(inputs.robot, FloorSettings(omega=inputs.omega, spring=inputs.fit))
    fq, fv = floor.initial_state()
    t_floor = best_time(lambda: floor.step(0.0, fq, fv, floor.settings.dt), repeat=50)

    def line(label: str, seconds: float, ref: float, goal: str) -> None:
        print(f"{label:58s}: {seconds * 1e6:9.1f} us = {seconds / ref:7.1f} x rnea   ({goal})")

    print(f"model nv = {model.nv}, sample theta = {thetas[k]:.3f} rad, omega = {scenario.omega} rad/s")
    print(
        f"free-body check: T_a {fb[('st', 'Ta')]:.6f} vs ours {u[0]:.6f} N.m; "
        f"T_e {fb[('st', 'Te')]:.6f} vs {-u[2]:.6f} N.m"
    )
    print(f"{'bare pin.rnea':58s}: {t_rnea * 1e6:9.2f} us")
    line("full sample: q, v, a, ID, every reaction", t_full, t_rnea, "goal <= 30")
    line("full sample without reactions", t_bare, t_rnea, "goal <= 15")
    line("full sample, every reaction, one 400-sample stance", best_long, t_rnea, "")
    line("constrained ID step alone (rnea + J_c + split)", t_step, t_rnea, "")
    line("the same, J_c from Pinocchio's getConstraintsJacobian", t_step_pin, t_rnea, "")
    line("one forward-dynamics evaluation (KKT, simulator rows)", t_fd, t_rnea_sim, "goal <= 20")
    line("one RK4 step with projection", t_rk4, t_rnea_sim, "goal <= 100")
    line("one floor step (contact QP + projection)", t_floor, t_rnea_sim, "goal <= 2 x the welded step")
    print(
        f"floor step / welded RK4 step: {t_floor / t_rk4:5.2f}; simulated time per wall second: "
        f"welded {2e-3 / t_rk4:5.1f}, floor {floor.settings.dt / t_floor:5.1f}   (goal: 10 s of walking < 10 s wall)"
    )
    print(f"{'seed free-body A.F = b (assemble + solve)':58s}: {t_fb * 1e6:9.1f} us")
    print(f"full sample speed-up over the free-body method: {t_fb / t_full:6.2f} x   (goal >= 10)")
    print(f"the same with one 400-sample stance:            {t_fb / best_long:6.2f} x")


if __name__ == "__main__":
    main()
