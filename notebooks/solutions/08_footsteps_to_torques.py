"""Solutions of notebook 08_footsteps_to_torques.ipynb (from footsteps to torques)."""

import numpy as np


def retimed_phase(t, t_i, tau_i, t_end):
    """Paper B eq. (12): τ(t) = τ^i + (1 − τ^i)(t − t^i)/(T_des − t^i), clipped to [0, 1]."""
    tau = tau_i + (1.0 - tau_i) * (t - t_i) / (t_end - t_i)
    return min(1.0, max(0.0, tau))


def quintic_coefficients(T, x0, v0, a0, x1, v1, a1):
    """c_0..c_5 of the quintic on [0, T] from its end positions, velocities and accelerations (a 6 x 6 solve)."""
    rows = []
    for s in (0.0, T):
        rows.append([s**k for k in range(6)])
        rows.append([k * s ** (k - 1) if k >= 1 else 0.0 for k in range(6)])
        rows.append([k * (k - 1) * s ** (k - 2) if k >= 2 else 0.0 for k in range(6)])
    rhs = [x0, v0, a0, x1, v1, a1]
    return np.linalg.solve(np.array(rows, dtype=float), np.array(rhs, dtype=float))


def friction_pyramid_rows(R_sole, mu):
    """Rows ±f_x − μ f_z, ±f_y − μ f_z of the sole-frame force f_s = R_soleᵀ f, on the world wrench [f; τ]."""
    Rt = np.asarray(R_sole, dtype=float).T
    fx, fy, fz = Rt  # each row maps the world force to one sole-frame component
    rows = np.zeros((4, 6))
    rows[:, :3] = [fx - mu * fz, -fx - mu * fz, fy - mu * fz, -fy - mu * fz]
    return rows


def center_of_pressure(wrench, p_sole):
    """CoP on the plane z = p_z: p + (−τ_y/f_z, τ_x/f_z, 0)."""
    w = np.asarray(wrench, dtype=float)
    p = np.asarray(p_sole, dtype=float)
    f, tau = w[:3], w[3:]
    return p + np.array([-tau[1] / f[2], tau[0] / f[2], 0.0])


def com_task_row(terms, ref, kp, kd):
    """The COM task's block (J, b) of ‖J q̈ − b‖²_W: J = J_com, b = a* − J̇v with
    a* = a_ref + kp (c_ref − c) + kd (ċ_ref − ċ) (all (3,), per axis)."""
    J = np.asarray(terms["J_com"], dtype=float)
    a_star = (np.asarray(ref.com_acc, dtype=float) + kp * (np.asarray(ref.com_pos, dtype=float) - terms["com"])
              + kd * (np.asarray(ref.com_vel, dtype=float) - terms["vcom"]))
    return J, a_star - np.asarray(terms["drift_com"], dtype=float)
