"""Circular edge on circular edge (`circle_circle_friction`): tangential (friction) kernels, compiled variant. DO NOT EDIT.

Written by `regenerate-equations` from derive/friction.py through
templates/friction_module_compiled.py.j2; `regenerate-equations --check` fails when this file is
stale. The same expressions as generated/circle_circle_friction.py (the NumPy kernels, the public API),
compiled by numba, with batch loops over contacts of the same conventions as the normal rows'
(generated/compiled/circle_circle.py: poses and velocities (n, 3), body1, body2, geometry
(m, 7), static2 (m,) booleans, members: the contacts to evaluate). Division by zero gives inf
or NaN as in the NumPy kernels (numba's "numpy" error model): the normal, hence t, of coincident
circle centres is undefined.

Geometry columns (`geometry[k, c]`): cx1 -> 0, cy1 -> 1, r1 -> 2, cx2 -> 3, cy2 -> 4, r2 -> 5.
"""

import numba
import numpy as np

ARGUMENTS = {
    "tangent_velocity": (
        "x1",
        "y1",
        "th1",
        "vx1",
        "vy1",
        "w1",
        "x2",
        "y2",
        "th2",
        "vx2",
        "vy2",
        "w2",
        "cx1",
        "cy1",
        "r1",
        "cx2",
        "cy2",
        "r2",
    ),
    "tangent_acceleration": (
        "x1",
        "y1",
        "th1",
        "vx1",
        "vy1",
        "w1",
        "ax1",
        "ay1",
        "al1",
        "x2",
        "y2",
        "th2",
        "vx2",
        "vy2",
        "w2",
        "ax2",
        "ay2",
        "al2",
        "cx1",
        "cy1",
        "r1",
        "cx2",
        "cy2",
        "r2",
    ),
    "tangent_jacobian": (
        "x1",
        "y1",
        "th1",
        "x2",
        "y2",
        "th2",
        "cx1",
        "cy1",
        "r1",
        "cx2",
        "cy2",
        "r2",
    ),
    "tangent_bias": (
        "x1",
        "y1",
        "th1",
        "vx1",
        "vy1",
        "w1",
        "x2",
        "y2",
        "th2",
        "vx2",
        "vy2",
        "w2",
        "cx1",
        "cy1",
        "cx2",
        "cy2",
        "r2",
    ),
    "tangent_velocity_static2": (
        "x1",
        "y1",
        "th1",
        "vx1",
        "vy1",
        "w1",
        "x2",
        "y2",
        "th2",
        "cx1",
        "cy1",
        "r1",
        "cx2",
        "cy2",
        "r2",
    ),
    "tangent_acceleration_static2": (
        "x1",
        "y1",
        "th1",
        "vx1",
        "vy1",
        "w1",
        "ax1",
        "ay1",
        "al1",
        "x2",
        "y2",
        "th2",
        "cx1",
        "cy1",
        "r1",
        "cx2",
        "cy2",
        "r2",
    ),
    "tangent_jacobian_static2": (
        "x1",
        "y1",
        "th1",
        "x2",
        "y2",
        "th2",
        "cx1",
        "cy1",
        "r1",
        "cx2",
        "cy2",
        "r2",
    ),
    "tangent_bias_static2": (
        "x1",
        "y1",
        "th1",
        "vx1",
        "vy1",
        "w1",
        "x2",
        "y2",
        "th2",
        "cx1",
        "cy1",
        "cx2",
        "cy2",
        "r2",
    ),
}


@numba.njit(cache=True, error_model="numpy")
def tangent_velocity(
    x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, cx1, cy1, r1, cx2, cy2, r2
):
    """Tangential relative velocity v_t of the contact points (exact, any state). Returns vt."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    l1_x = cx1 * e0 - cy1 * e1
    l1_y = cx1 * e1 + cy1 * e0
    l2_x = cx2 * e2 - cy2 * e3
    l2_y = cx2 * e3 + cy2 * e2
    v_x = dx + l1_x - l2_x
    v_y = dy + l1_y - l2_y
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e4 = sg2 / v_len
    n_x = e4 * v_x
    n_y = e4 * v_y
    return (
        n_x * (vy1 - vy2)
        - n_y * (vx1 - vx2)
        + w1 * (l1_x * n_x + l1_y * n_y - r1)
        - w2 * (l2_x * n_x + l2_y * n_y + r2)
    )


@numba.njit(cache=True, error_model="numpy")
def tangent_acceleration(
    x1,
    y1,
    th1,
    vx1,
    vy1,
    w1,
    ax1,
    ay1,
    al1,
    x2,
    y2,
    th2,
    vx2,
    vy2,
    w2,
    ax2,
    ay2,
    al2,
    cx1,
    cy1,
    r1,
    cx2,
    cy2,
    r2,
):
    """Exact d/dt v_t for any state. Returns at."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = cx1 * e0 - cy1 * e1
    e3 = cx1 * e1 + cy1 * e0
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    e6 = cx2 * e4 - cy2 * e5
    e7 = cx2 * e5 + cy2 * e4
    e8 = vx1 - vx2
    e9 = vy1 - vy2
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    l1_x = e2
    l1_y = e3
    l1_x_t = -e3 * w1
    l1_y_t = e2 * w1
    l2_x = e6
    l2_y = e7
    l2_x_t = -e7 * w2
    l2_y_t = e6 * w2
    v_x = dx + l1_x - l2_x
    v_y = dy + l1_y - l2_y
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e10 = 1 / v_len
    e11 = e10 * sg2
    v_x_t = e8 + l1_x_t - l2_x_t
    v_y_t = e9 + l1_y_t - l2_y_t
    v_tan = e10 * (v_x * v_y_t - v_x_t * v_y)
    e12 = e10 * v_tan
    n_x = e11 * v_x
    n_y = e11 * v_y
    n_x_t = -e12 * n_y
    n_y_t = e12 * n_x
    return (
        al1 * (l1_x * n_x + l1_y * n_y - r1)
        - al2 * (l2_x * n_x + l2_y * n_y + r2)
        - e8 * n_y_t
        + e9 * n_x_t
        + n_x * (ay1 - ay2)
        - n_y * (ax1 - ax2)
        + w1 * (l1_x * n_x_t + l1_x_t * n_x + l1_y * n_y_t + l1_y_t * n_y)
        - w2 * (l2_x * n_x_t + l2_x_t * n_x + l2_y * n_y_t + l2_y_t * n_y)
    )


@numba.njit(cache=True, error_model="numpy")
def tangent_jacobian(x1, y1, th1, x2, y2, th2, cx1, cy1, r1, cx2, cy2, r2):
    """Tangential Jacobian row J_t: v_t = J_t . velocities, the A-matrix row of friction. Returns j1x, j1y, j1th, j2x, j2y, j2th."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    l1_x = cx1 * e0 - cy1 * e1
    l1_y = cx1 * e1 + cy1 * e0
    l2_x = cx2 * e2 - cy2 * e3
    l2_y = cx2 * e3 + cy2 * e2
    v_x = dx + l1_x - l2_x
    v_y = dy + l1_y - l2_y
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e4 = sg2 / v_len
    n_x = e4 * v_x
    n_y = e4 * v_y
    return -n_y, n_x, l1_x * n_x + l1_y * n_y - r1, n_y, -n_x, -l2_x * n_x - l2_y * n_y - r2


@numba.njit(cache=True, error_model="numpy")
def tangent_bias(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, cx1, cy1, cx2, cy2, r2):
    """Velocity-dependent part of d/dt v_t: the b-vector term of friction. Returns bt."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = cx1 * e0 - cy1 * e1
    e3 = cx1 * e1 + cy1 * e0
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    e6 = cx2 * e4 - cy2 * e5
    e7 = cx2 * e5 + cy2 * e4
    e8 = vx1 - vx2
    e9 = vy1 - vy2
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    l1_x = e2
    l1_y = e3
    l1_x_t = -e3 * w1
    l1_y_t = e2 * w1
    l2_x = e6
    l2_y = e7
    l2_x_t = -e7 * w2
    l2_y_t = e6 * w2
    v_x = dx + l1_x - l2_x
    v_y = dy + l1_y - l2_y
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e10 = 1 / v_len
    e11 = e10 * sg2
    v_x_t = e8 + l1_x_t - l2_x_t
    v_y_t = e9 + l1_y_t - l2_y_t
    v_tan = e10 * (v_x * v_y_t - v_x_t * v_y)
    e12 = e10 * v_tan
    n_x = e11 * v_x
    n_y = e11 * v_y
    n_x_t = -e12 * n_y
    n_y_t = e12 * n_x
    return (
        -e8 * n_y_t
        + e9 * n_x_t
        + w1 * (l1_x * n_x_t + l1_x_t * n_x + l1_y * n_y_t + l1_y_t * n_y)
        - w2 * (l2_x * n_x_t + l2_x_t * n_x + l2_y * n_y_t + l2_y_t * n_y)
    )


@numba.njit(cache=True, error_model="numpy")
def tangent_velocity_static2(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, cx1, cy1, r1, cx2, cy2, r2):
    """Tangential relative velocity v_t of the contact points (exact, any state). Returns vt."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    l1_x = cx1 * e0 - cy1 * e1
    l1_y = cx1 * e1 + cy1 * e0
    l2_x = cx2 * e2 - cy2 * e3
    l2_y = cx2 * e3 + cy2 * e2
    v_x = dx + l1_x - l2_x
    v_y = dy + l1_y - l2_y
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e4 = sg2 / v_len
    n_x = e4 * v_x
    n_y = e4 * v_y
    return n_x * vy1 - n_y * vx1 + w1 * (l1_x * n_x + l1_y * n_y - r1)


@numba.njit(cache=True, error_model="numpy")
def tangent_acceleration_static2(
    x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1, x2, y2, th2, cx1, cy1, r1, cx2, cy2, r2
):
    """Exact d/dt v_t for any state. Returns at."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = cx1 * e0 - cy1 * e1
    e3 = cx1 * e1 + cy1 * e0
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    l1_x = e2
    l1_y = e3
    l1_x_t = -e3 * w1
    l1_y_t = e2 * w1
    l2_x = cx2 * e4 - cy2 * e5
    l2_y = cx2 * e5 + cy2 * e4
    v_x = dx + l1_x - l2_x
    v_y = dy + l1_y - l2_y
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e6 = 1 / v_len
    e7 = e6 * sg2
    v_x_t = l1_x_t + vx1
    v_y_t = l1_y_t + vy1
    v_tan = e6 * (v_x * v_y_t - v_x_t * v_y)
    e8 = e6 * v_tan
    n_x = e7 * v_x
    n_y = e7 * v_y
    n_x_t = -e8 * n_y
    n_y_t = e8 * n_x
    return (
        al1 * (l1_x * n_x + l1_y * n_y - r1)
        - ax1 * n_y
        + ay1 * n_x
        + n_x_t * vy1
        - n_y_t * vx1
        + w1 * (l1_x * n_x_t + l1_x_t * n_x + l1_y * n_y_t + l1_y_t * n_y)
    )


@numba.njit(cache=True, error_model="numpy")
def tangent_jacobian_static2(x1, y1, th1, x2, y2, th2, cx1, cy1, r1, cx2, cy2, r2):
    """Tangential Jacobian row J_t: v_t = J_t . velocities, the A-matrix row of friction. Returns j1x, j1y, j1th."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    l1_x = cx1 * e0 - cy1 * e1
    l1_y = cx1 * e1 + cy1 * e0
    l2_x = cx2 * e2 - cy2 * e3
    l2_y = cx2 * e3 + cy2 * e2
    v_x = dx + l1_x - l2_x
    v_y = dy + l1_y - l2_y
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e4 = sg2 / v_len
    n_x = e4 * v_x
    n_y = e4 * v_y
    return -n_y, n_x, l1_x * n_x + l1_y * n_y - r1


@numba.njit(cache=True, error_model="numpy")
def tangent_bias_static2(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, cx1, cy1, cx2, cy2, r2):
    """Velocity-dependent part of d/dt v_t: the b-vector term of friction. Returns bt."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = cx1 * e0 - cy1 * e1
    e3 = cx1 * e1 + cy1 * e0
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    l1_x = e2
    l1_y = e3
    l1_x_t = -e3 * w1
    l1_y_t = e2 * w1
    l2_x = cx2 * e4 - cy2 * e5
    l2_y = cx2 * e5 + cy2 * e4
    v_x = dx + l1_x - l2_x
    v_y = dy + l1_y - l2_y
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e6 = 1 / v_len
    e7 = e6 * sg2
    v_x_t = l1_x_t + vx1
    v_y_t = l1_y_t + vy1
    v_tan = e6 * (v_x * v_y_t - v_x_t * v_y)
    e8 = e6 * v_tan
    n_x = e7 * v_x
    n_y = e7 * v_y
    n_x_t = -e8 * n_y
    n_y_t = e8 * n_x
    return (
        n_x_t * vy1 - n_y_t * vx1 + w1 * (l1_x * n_x_t + l1_x_t * n_x + l1_y * n_y_t + l1_y_t * n_y)
    )


@numba.njit(cache=True, error_model="numpy")
def batch_tangent_velocity(poses, velocities, body1, body2, geometry, static2, members, out):
    """out[k] = v_t of contact k, for k in members (static2[k]: body 2 fixed)."""
    for k in members:
        i = body1[k]
        j = body2[k]
        if static2[k]:
            out[k] = tangent_velocity_static2(
                poses[i, 0],
                poses[i, 1],
                poses[i, 2],
                velocities[i, 0],
                velocities[i, 1],
                velocities[i, 2],
                poses[j, 0],
                poses[j, 1],
                poses[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 2],
                geometry[k, 3],
                geometry[k, 4],
                geometry[k, 5],
            )
        else:
            out[k] = tangent_velocity(
                poses[i, 0],
                poses[i, 1],
                poses[i, 2],
                velocities[i, 0],
                velocities[i, 1],
                velocities[i, 2],
                poses[j, 0],
                poses[j, 1],
                poses[j, 2],
                velocities[j, 0],
                velocities[j, 1],
                velocities[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 2],
                geometry[k, 3],
                geometry[k, 4],
                geometry[k, 5],
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
                poses[i, 0],
                poses[i, 1],
                poses[i, 2],
                poses[j, 0],
                poses[j, 1],
                poses[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 2],
                geometry[k, 3],
                geometry[k, 4],
                geometry[k, 5],
            )
            for c in range(3):
                jacobian_out[k, c] = row[c]
                jacobian_out[k, 3 + c] = 0.0
            bias_out[k] = tangent_bias_static2(
                poses[i, 0],
                poses[i, 1],
                poses[i, 2],
                velocities[i, 0],
                velocities[i, 1],
                velocities[i, 2],
                poses[j, 0],
                poses[j, 1],
                poses[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 3],
                geometry[k, 4],
                geometry[k, 5],
            )
        else:
            row = tangent_jacobian(
                poses[i, 0],
                poses[i, 1],
                poses[i, 2],
                poses[j, 0],
                poses[j, 1],
                poses[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 2],
                geometry[k, 3],
                geometry[k, 4],
                geometry[k, 5],
            )
            for c in range(6):
                jacobian_out[k, c] = row[c]
            bias_out[k] = tangent_bias(
                poses[i, 0],
                poses[i, 1],
                poses[i, 2],
                velocities[i, 0],
                velocities[i, 1],
                velocities[i, 2],
                poses[j, 0],
                poses[j, 1],
                poses[j, 2],
                velocities[j, 0],
                velocities[j, 1],
                velocities[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 3],
                geometry[k, 4],
                geometry[k, 5],
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
