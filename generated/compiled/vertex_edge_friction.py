"""Vertex on straight edge (`vertex_edge_friction`): tangential (friction) kernels, compiled variant. DO NOT EDIT.

Written by `regenerate-equations` from derive/friction.py through
templates/friction_module_compiled.py.j2; `regenerate-equations --check` fails when this file is
stale. The same expressions as generated/vertex_edge_friction.py (the NumPy kernels, the public API),
compiled by numba, with batch loops over contacts of the same conventions as the normal rows'
(generated/compiled/vertex_edge.py: poses and velocities (n, 3), body1, body2, geometry
(m, 7), static2 (m,) booleans, members: the contacts to evaluate). Division by zero gives inf
or NaN as in the NumPy kernels (numba's "numpy" error model): the normal, hence t, of coincident
circle centres is undefined.

Geometry columns (`geometry[k, c]`): px1 -> 0, py1 -> 1, ex2 -> 3, ey2 -> 4, nx2 -> 5, ny2 -> 6.
"""

import numba
import numpy as np

ARGUMENTS = {
    "tangent_velocity": (
        "th1",
        "vx1",
        "vy1",
        "w1",
        "th2",
        "vx2",
        "vy2",
        "w2",
        "px1",
        "py1",
        "ex2",
        "ey2",
        "nx2",
        "ny2",
    ),
    "tangent_acceleration": (
        "th1",
        "vx1",
        "vy1",
        "w1",
        "ax1",
        "ay1",
        "al1",
        "th2",
        "vx2",
        "vy2",
        "w2",
        "ax2",
        "ay2",
        "al2",
        "px1",
        "py1",
        "ex2",
        "ey2",
        "nx2",
        "ny2",
    ),
    "tangent_jacobian": ("th1", "th2", "px1", "py1", "ex2", "ey2", "nx2", "ny2"),
    "tangent_bias": (
        "th1",
        "vx1",
        "vy1",
        "w1",
        "th2",
        "vx2",
        "vy2",
        "w2",
        "px1",
        "py1",
        "ex2",
        "ey2",
        "nx2",
        "ny2",
    ),
    "tangent_velocity_static2": ("th1", "vx1", "vy1", "w1", "th2", "px1", "py1", "nx2", "ny2"),
    "tangent_acceleration_static2": (
        "th1",
        "w1",
        "ax1",
        "ay1",
        "al1",
        "th2",
        "px1",
        "py1",
        "nx2",
        "ny2",
    ),
    "tangent_jacobian_static2": ("th1", "th2", "px1", "py1", "nx2", "ny2"),
    "tangent_bias_static2": ("th1", "w1", "th2", "px1", "py1", "nx2", "ny2"),
}


@numba.njit(cache=True, error_model="numpy")
def tangent_velocity(th1, vx1, vy1, w1, th2, vx2, vy2, w2, px1, py1, ex2, ey2, nx2, ny2):
    """Tangential relative velocity v_t of the contact points (exact, any state). Returns vt."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    l1_x = e0 * px1 - e1 * py1
    l1_y = e0 * py1 + e1 * px1
    l2_x = e2 * ex2 - e3 * ey2
    l2_y = e2 * ey2 + e3 * ex2
    n_x = e2 * nx2 - e3 * ny2
    n_y = e2 * ny2 + e3 * nx2
    return (
        n_x * (vy1 - vy2)
        - n_y * (vx1 - vx2)
        + w1 * (l1_x * n_x + l1_y * n_y)
        - w2 * (l2_x * n_x + l2_y * n_y)
    )


@numba.njit(cache=True, error_model="numpy")
def tangent_acceleration(
    th1, vx1, vy1, w1, ax1, ay1, al1, th2, vx2, vy2, w2, ax2, ay2, al2, px1, py1, ex2, ey2, nx2, ny2
):
    """Exact d/dt v_t for any state. Returns at."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    e6 = e4 * ex2 - e5 * ey2
    e7 = e4 * ey2 + e5 * ex2
    e8 = e4 * nx2 - e5 * ny2
    e9 = e4 * ny2 + e5 * nx2
    l1_x = e2
    l1_y = e3
    l1_x_t = -e3 * w1
    l1_y_t = e2 * w1
    l2_x = e6
    l2_y = e7
    l2_x_t = -e7 * w2
    l2_y_t = e6 * w2
    n_x = e8
    n_y = e9
    n_x_t = -e9 * w2
    n_y_t = e8 * w2
    return (
        al1 * (l1_x * n_x + l1_y * n_y)
        - al2 * (l2_x * n_x + l2_y * n_y)
        + n_x * (ay1 - ay2)
        + n_x_t * (vy1 - vy2)
        - n_y * (ax1 - ax2)
        - n_y_t * (vx1 - vx2)
        + w1 * (l1_x * n_x_t + l1_x_t * n_x + l1_y * n_y_t + l1_y_t * n_y)
        - w2 * (l2_x * n_x_t + l2_x_t * n_x + l2_y * n_y_t + l2_y_t * n_y)
    )


@numba.njit(cache=True, error_model="numpy")
def tangent_jacobian(th1, th2, px1, py1, ex2, ey2, nx2, ny2):
    """Tangential Jacobian row J_t: v_t = J_t . velocities, the A-matrix row of friction. Returns j1x, j1y, j1th, j2x, j2y, j2th."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    l1_x = e0 * px1 - e1 * py1
    l1_y = e0 * py1 + e1 * px1
    l2_x = e2 * ex2 - e3 * ey2
    l2_y = e2 * ey2 + e3 * ex2
    n_x = e2 * nx2 - e3 * ny2
    n_y = e2 * ny2 + e3 * nx2
    return -n_y, n_x, l1_x * n_x + l1_y * n_y, n_y, -n_x, -l2_x * n_x - l2_y * n_y


@numba.njit(cache=True, error_model="numpy")
def tangent_bias(th1, vx1, vy1, w1, th2, vx2, vy2, w2, px1, py1, ex2, ey2, nx2, ny2):
    """Velocity-dependent part of d/dt v_t: the b-vector term of friction. Returns bt."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    e6 = e4 * ex2 - e5 * ey2
    e7 = e4 * ey2 + e5 * ex2
    e8 = e4 * nx2 - e5 * ny2
    e9 = e4 * ny2 + e5 * nx2
    l1_x = e2
    l1_y = e3
    l1_x_t = -e3 * w1
    l1_y_t = e2 * w1
    l2_x = e6
    l2_y = e7
    l2_x_t = -e7 * w2
    l2_y_t = e6 * w2
    n_x = e8
    n_y = e9
    n_x_t = -e9 * w2
    n_y_t = e8 * w2
    return (
        n_x_t * (vy1 - vy2)
        - n_y_t * (vx1 - vx2)
        + w1 * (l1_x * n_x_t + l1_x_t * n_x + l1_y * n_y_t + l1_y_t * n_y)
        - w2 * (l2_x * n_x_t + l2_x_t * n_x + l2_y * n_y_t + l2_y_t * n_y)
    )


@numba.njit(cache=True, error_model="numpy")
def tangent_velocity_static2(th1, vx1, vy1, w1, th2, px1, py1, nx2, ny2):
    """Tangential relative velocity v_t of the contact points (exact, any state). Returns vt."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    l1_x = e0 * px1 - e1 * py1
    l1_y = e0 * py1 + e1 * px1
    n_x = e2 * nx2 - e3 * ny2
    n_y = e2 * ny2 + e3 * nx2
    return n_x * vy1 - n_y * vx1 + w1 * (l1_x * n_x + l1_y * n_y)


@numba.njit(cache=True, error_model="numpy")
def tangent_acceleration_static2(th1, w1, ax1, ay1, al1, th2, px1, py1, nx2, ny2):
    """Exact d/dt v_t for any state. Returns at."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    l1_x = e2
    l1_y = e3
    l1_x_t = -e3 * w1
    l1_y_t = e2 * w1
    n_x = e4 * nx2 - e5 * ny2
    n_y = e4 * ny2 + e5 * nx2
    return (
        al1 * (l1_x * n_x + l1_y * n_y) - ax1 * n_y + ay1 * n_x + w1 * (l1_x_t * n_x + l1_y_t * n_y)
    )


@numba.njit(cache=True, error_model="numpy")
def tangent_jacobian_static2(th1, th2, px1, py1, nx2, ny2):
    """Tangential Jacobian row J_t: v_t = J_t . velocities, the A-matrix row of friction. Returns j1x, j1y, j1th."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    l1_x = e0 * px1 - e1 * py1
    l1_y = e0 * py1 + e1 * px1
    n_x = e2 * nx2 - e3 * ny2
    n_y = e2 * ny2 + e3 * nx2
    return -n_y, n_x, l1_x * n_x + l1_y * n_y


@numba.njit(cache=True, error_model="numpy")
def tangent_bias_static2(th1, w1, th2, px1, py1, nx2, ny2):
    """Velocity-dependent part of d/dt v_t: the b-vector term of friction. Returns bt."""
    e0 = np.sin(th1)
    e1 = np.cos(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    l1_x_t = w1 * (-e0 * px1 - e1 * py1)
    l1_y_t = w1 * (-e0 * py1 + e1 * px1)
    n_x = e2 * nx2 - e3 * ny2
    n_y = e2 * ny2 + e3 * nx2
    return w1 * (l1_x_t * n_x + l1_y_t * n_y)


@numba.njit(cache=True, error_model="numpy")
def batch_tangent_velocity(poses, velocities, body1, body2, geometry, static2, members, out):
    """out[k] = v_t of contact k, for k in members (static2[k]: body 2 fixed)."""
    for k in members:
        i = body1[k]
        j = body2[k]
        if static2[k]:
            out[k] = tangent_velocity_static2(
                poses[i, 2],
                velocities[i, 0],
                velocities[i, 1],
                velocities[i, 2],
                poses[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 5],
                geometry[k, 6],
            )
        else:
            out[k] = tangent_velocity(
                poses[i, 2],
                velocities[i, 0],
                velocities[i, 1],
                velocities[i, 2],
                poses[j, 2],
                velocities[j, 0],
                velocities[j, 1],
                velocities[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 3],
                geometry[k, 4],
                geometry[k, 5],
                geometry[k, 6],
            )


@numba.njit(cache=True, error_model="numpy")
def batch_tangent_rows(
    poses, velocities, body1, body2, geometry, static2, members, jacobian_out, bias_out
):
    """Tangential Jacobian row (6 numbers, body 1 then body 2) and bias of contact k."""
    for k in members:
        i = body1[k]
        j = body2[k]
        if static2[k]:
            row = tangent_jacobian_static2(
                poses[i, 2],
                poses[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 5],
                geometry[k, 6],
            )
            for c in range(3):
                jacobian_out[k, c] = row[c]
                jacobian_out[k, 3 + c] = 0.0
            bias_out[k] = tangent_bias_static2(
                poses[i, 2],
                velocities[i, 2],
                poses[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 5],
                geometry[k, 6],
            )
        else:
            row = tangent_jacobian(
                poses[i, 2],
                poses[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 3],
                geometry[k, 4],
                geometry[k, 5],
                geometry[k, 6],
            )
            for c in range(6):
                jacobian_out[k, c] = row[c]
            bias_out[k] = tangent_bias(
                poses[i, 2],
                velocities[i, 0],
                velocities[i, 1],
                velocities[i, 2],
                poses[j, 2],
                velocities[j, 0],
                velocities[j, 1],
                velocities[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 3],
                geometry[k, 4],
                geometry[k, 5],
                geometry[k, 6],
            )


@numba.njit(cache=True, error_model="numpy")
def batch_tangent_all(
    poses, velocities, body1, body2, geometry, static2, members, rate_out, jacobian_out, bias_out
):
    """v_t, the tangential Jacobian row and bias of contact k, for k in members."""
    batch_tangent_velocity(poses, velocities, body1, body2, geometry, static2, members, rate_out)
    batch_tangent_rows(
        poses, velocities, body1, body2, geometry, static2, members, jacobian_out, bias_out
    )
