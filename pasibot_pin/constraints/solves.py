"""The linear solves of the constraint core: the KKT solve, the torque split, square solves, M(q).

:func:`kkt_solve` is the package's one KKT solve (Pinocchio's ``forwardDynamics`` with our rows);
:func:`split_torques` splits joint torques into actuator torques and constraint forces;
:func:`inverse_lists` inverts a 3 x 3 on Python floats, without LAPACK's call cost;
the square solves raise the package's typed errors on a singular pose.

Units: SI.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from pasibot_pin.errors import ParameterError, SingularPoseError


def symmetric_mass_matrix(model: pin.Model, data: pin.Data, q: np.ndarray) -> np.ndarray:
    """Joint-space mass matrix M(q), both triangles filled, a new array [kg, kg.m, kg.m^2].

    Pin 4.1's ``crba`` binding returns M with its lower triangle copied from the upper one, in a
    new array (``tests/test_constraints.py`` holds it to that, bit for bit, on every variant).
    """
    return pin.crba(model, data, q)


def kkt_solve(model: pin.Model, data: pin.Data, tau: np.ndarray, jac: np.ndarray, gamma: np.ndarray):
    """Solve M a + h = tau + J^T lambda, J a = -gamma with M and h already in ``data``; returns (a, lambda).

    ``pin.forwardDynamics`` with the rows ``jac`` as its constraint Jacobian: a Cholesky
    factorisation of M (the upper triangle of ``data.M``) and of J M^-1 J^T (J must have full row
    rank). Every KKT solve of the package goes through here: the simulator's accelerations and
    impacts, the lockstep walks and the floor's contact QP (with H for M and g for h - tau).

    Args:
        model: the Pinocchio model.
        data: its data, holding M in ``data.M`` and h in ``data.nle``.
        tau: generalised force (nv,).
        jac: the rows' Jacobian J (m, nv).
        gamma: the rows' right-hand side: J a = -gamma (m,).

    Returns:
        (a (nv,), lambda (m,)), both new arrays.

    Raises:
        ValueError: a singular system (the constraint Jacobian lost rank) or a non-finite answer.

    """
    try:
        a = pin.forwardDynamics(model, data, tau, jac, gamma, 0.0)  # a new array
    except RuntimeError as err:
        raise SingularPoseError(f"KKT system singular: the constraint Jacobian lost rank: {err}") from err
    lam = data.lambda_c.copy()
    if not math.isfinite(a.dot(a) + lam.dot(lam)):  # a NaN or an infinity anywhere shows in the sum
        raise SingularPoseError("KKT solve returned non-finite values: the constraint Jacobian lost rank")
    return a, lam


def split_torques(tau: np.ndarray, s_matrix: np.ndarray, jac: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Solve tau = S^T u + J^T lambda (square) for (u, lambda), one sample or a batch.

    S selects the actuated coordinates (one 1 per row). The passive coordinates carry no actuator,
    so J_P^T lambda = tau_P is square (nv - n_u unknowns, one solve per sample) and then
    u = tau_A - J_A^T lambda.

    Args:
        tau: joint torques (nv,) or (N, nv) [N.m, N].
        s_matrix: the actuation S (n_u, nv), a selection of coordinates.
        jac: the constraint rows' Jacobian J (m, nv) or (N, m, nv), m = nv - n_u.

    Returns:
        (u (n_u,) or (N, n_u), lambda (m,) or (N, m)).

    Raises:
        ParameterError: S is not a selection of coordinates, or [S^T J^T] is not square.
        SingularPoseError: J_P^T is singular (the actuators cannot hold the motion at this pose).

    """
    actuated = np.argmax(s_matrix, axis=1)
    if not np.array_equal(s_matrix, np.eye(s_matrix.shape[1])[actuated]):
        raise ParameterError("split: S must select coordinates (one 1 per row, nothing else)")
    passive = np.nonzero(~s_matrix.any(axis=0))[0]
    single = np.ndim(tau) == 1
    tau_b = np.atleast_2d(tau)
    jac_t = np.swapaxes(jac[None] if single else jac, 1, 2)  # J^T (N, nv, m)
    if jac_t.shape[2] != len(passive):
        n_unknowns = jac_t.shape[2] + len(actuated)
        raise ParameterError(f"split: {n_unknowns} unknowns for nv = {jac_t.shape[1]}; the system must be square")
    try:
        lam = np.linalg.solve(jac_t[:, passive], tau_b[:, passive, None])
    except np.linalg.LinAlgError as err:
        raise SingularPoseError("split: [S^T J_c^T] is singular at this pose") from err
    if not np.all(np.isfinite(lam)):
        raise SingularPoseError("split: the actuator and constraint forces are not finite")
    u = tau_b[:, actuated] - (jac_t[:, actuated] @ lam)[:, :, 0]
    return (u[0], lam[0, :, 0]) if single else (u, lam[:, :, 0])


def square_solve_many(matrix: np.ndarray, rhs: np.ndarray, what: str) -> np.ndarray:
    """Solve a batch of square systems (N, n, n) x = (N, n), with the errors of :func:`square_solve`."""
    if matrix.shape[-2] != matrix.shape[-1]:
        raise ParameterError(
            f"{what}: constraints plus prescriptions give {matrix.shape[-2]} rows for nv = {matrix.shape[-1]}; "
            "prescribe exactly the free coordinates"
        )
    try:
        sol = np.linalg.solve(matrix, rhs[..., None])[..., 0]
    except np.linalg.LinAlgError as err:
        raise SingularPoseError(f"{what}: singular pose, the matrix lost rank") from err
    if not np.all(np.isfinite(sol)):
        raise SingularPoseError(f"{what}: singular pose, the solution is not finite")
    return sol


def square_solve(matrix: np.ndarray, rhs: np.ndarray, what: str) -> np.ndarray:
    """Solve a square system ``matrix`` x = ``rhs``; ValueError if not square, SingularPoseError if singular."""
    if matrix.shape[0] != matrix.shape[1]:
        raise ParameterError(
            f"{what}: constraints plus prescriptions give {matrix.shape[0]} rows for nv = {matrix.shape[1]}; "
            "prescribe exactly the free coordinates"
        )
    try:
        sol = np.linalg.solve(matrix, rhs)
    except np.linalg.LinAlgError as err:
        raise SingularPoseError(f"{what}: singular pose, the constraint Jacobian lost rank") from err
    if not np.all(np.isfinite(sol)):
        raise SingularPoseError(f"{what}: singular pose, the solution is not finite")
    return sol


def inverse_lists(matrix: list[list[float]]) -> list[list[float]]:
    """The inverse of a square matrix given as lists: up to 3 x 3 by cofactors over the determinant, larger by LAPACK.

    Raises:
        numpy.linalg.LinAlgError: the matrix is singular (a zero or non-finite determinant).

    """
    n = len(matrix)
    if n == 1:
        det = matrix[0][0]
        cofactors = [[1.0]]
    elif n == 2:
        (a, b), (c, d) = matrix
        det = a * d - b * c
        cofactors = [[d, -b], [-c, a]]
    elif n == 3:  # written out: the floor's step inverts two 3 x 3 per time step
        (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = matrix
        c00, c01, c02 = a11 * a22 - a12 * a21, a12 * a20 - a10 * a22, a10 * a21 - a11 * a20
        det = a00 * c00 + a01 * c01 + a02 * c02
        if det == 0.0 or not math.isfinite(det):
            raise np.linalg.LinAlgError("singular matrix")
        r = 1.0 / det
        return [
            [c00 * r, (a02 * a21 - a01 * a22) * r, (a01 * a12 - a02 * a11) * r],
            [c01 * r, (a00 * a22 - a02 * a20) * r, (a02 * a10 - a00 * a12) * r],
            [c02 * r, (a01 * a20 - a00 * a21) * r, (a00 * a11 - a01 * a10) * r],
        ]
    else:
        inverse = np.linalg.inv(np.array(matrix, dtype=float))
        if not np.all(np.isfinite(inverse)):
            raise np.linalg.LinAlgError("singular matrix")
        return inverse.tolist()
    if det == 0.0 or not math.isfinite(det):
        raise np.linalg.LinAlgError("singular matrix")
    r = 1.0 / det
    return [[c * r for c in row] for row in cofactors]


def frame_jacobian(model: pin.Model, data: pin.Data, q: np.ndarray, frame: int) -> np.ndarray:
    """The 6 x nv LOCAL_WORLD_ALIGNED Jacobian of a frame (linear, then angular rows)."""
    return pin.computeFrameJacobian(model, data, q, frame, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED).reshape(6, model.nv)
