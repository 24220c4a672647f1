"""Vertex on circular edge (`vertex_circle`): generated kernels, compiled variant. DO NOT EDIT.

Written by `regenerate-equations` from derive/ through
templates/kernel_module_compiled.py.j2; `regenerate-equations --check` fails when this file is stale.
The same expressions as generated/vertex_circle.py (the NumPy kernels, the public API), for
scalars and compiled by numba: positional arguments in the order of ARGUMENTS, no `del` (numba
has none), and batch loops that read the state from (n, 3) pose and velocity arrays, so the
engine evaluates many contacts in one compiled call. Division by zero gives inf or NaN as in
the NumPy kernels (numba's "numpy" error model), not ZeroDivisionError: d' of two coincident
circle centres is undefined, and the engine decides what to do with a non-finite value.

Geometry columns (`geometry[k, c]`): px1 -> 0, py1 -> 1, cx2 -> 3, cy2 -> 4, r2 -> 5.
"""

import numba
import numpy as np

ARGUMENTS = {
    "gap": ("x1", "y1", "th1", "x2", "y2", "th2", "px1", "py1", "cx2", "cy2", "r2"),
    "gap_velocity": (
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
        "px1",
        "py1",
        "cx2",
        "cy2",
        "r2",
    ),
    "gap_acceleration": (
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
        "px1",
        "py1",
        "cx2",
        "cy2",
        "r2",
    ),
    "jacobian": ("x1", "y1", "th1", "x2", "y2", "th2", "px1", "py1", "cx2", "cy2", "r2"),
    "bias": (
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
        "px1",
        "py1",
        "cx2",
        "cy2",
        "r2",
    ),
    "gap_velocity_static2": (
        "x1",
        "y1",
        "th1",
        "vx1",
        "vy1",
        "w1",
        "x2",
        "y2",
        "th2",
        "px1",
        "py1",
        "cx2",
        "cy2",
        "r2",
    ),
    "gap_acceleration_static2": (
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
        "px1",
        "py1",
        "cx2",
        "cy2",
        "r2",
    ),
    "jacobian_static2": ("x1", "y1", "th1", "x2", "y2", "th2", "px1", "py1", "cx2", "cy2", "r2"),
    "bias_static2": (
        "x1",
        "y1",
        "th1",
        "vx1",
        "vy1",
        "w1",
        "x2",
        "y2",
        "th2",
        "px1",
        "py1",
        "cx2",
        "cy2",
        "r2",
    ),
}


@numba.njit(cache=True, error_model="numpy")
def gap(x1, y1, th1, x2, y2, th2, px1, py1, cx2, cy2, r2):
    """Gap d (> 0 separated). Returns d."""
    e0 = np.sin(th2)
    e1 = np.cos(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th1)
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = -cx2 * e2 + cy2 * e0 + dx + e1 * px1 - e3 * py1
    v_y = -cx2 * e0 - cy2 * e2 + dy + e1 * py1 + e3 * px1
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    return -r2 + sg2 * v_len


@numba.njit(cache=True, error_model="numpy")
def gap_velocity(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, px1, py1, cx2, cy2, r2):
    """Exact d' for any state. Returns d1."""
    e0 = np.sin(th2)
    e1 = np.cos(th2)
    e2 = cx2 * e1
    e3 = np.cos(th1)
    e4 = np.sin(th1)
    e5 = e3 * px1 - e4 * py1
    e6 = cx2 * e0
    e7 = cy2 * e1
    e8 = e3 * py1 + e4 * px1
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = cy2 * e0 + dx - e2 + e5
    v_y = dy - e6 - e7 + e8
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    v_x_t = -e8 * w1 + vx1 - vx2 + w2 * (e6 + e7)
    v_y_t = e5 * w1 + vy1 - vy2 + w2 * (cy2 * e0 - e2)
    return sg2 * (v_x * v_x_t + v_y * v_y_t) / v_len


@numba.njit(cache=True, error_model="numpy")
def gap_acceleration(
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
    px1,
    py1,
    cx2,
    cy2,
    r2,
):
    """Exact d'' for any state. Returns d2."""
    e0 = np.sin(th2)
    e1 = np.cos(th2)
    e2 = cx2 * e1
    e3 = np.cos(th1)
    e4 = np.sin(th1)
    e5 = e3 * px1 - e4 * py1
    e6 = cx2 * e0
    e7 = cy2 * e1
    e8 = e3 * py1 + e4 * px1
    e9 = e6 + e7
    e10 = -e8
    e11 = -cy2 * e0 + e2
    e12 = -e11
    e14 = w1 * w1
    e15 = w2 * w2
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = cy2 * e0 + dx - e2 + e5
    v_y = dy - e6 - e7 + e8
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e13 = 1 / v_len
    v_x_t = e10 * w1 + e9 * w2 + vx1 - vx2
    v_y_t = e12 * w2 + e5 * w1 + vy1 - vy2
    v_tan = e13 * (v_x * v_y_t - v_x_t * v_y)
    v_x_tt = al1 * e10 + al2 * e9 + ax1 - ax2 + e11 * e15 - e14 * e5
    v_y_tt = al1 * e5 + al2 * e12 + ay1 - ay2 + e10 * e14 + e15 * e9
    return sg2 * (e13 * v_tan * v_tan + e13 * (v_x * v_x_tt + v_y * v_y_tt))


@numba.njit(cache=True, error_model="numpy")
def jacobian(x1, y1, th1, x2, y2, th2, px1, py1, cx2, cy2, r2):
    """Jacobian row of the gap: the A-matrix lever terms. Returns j1x, j1y, j1th, j2x, j2y, j2th."""
    e0 = np.sin(th2)
    e1 = cy2 * e0
    e2 = np.cos(th2)
    e3 = cx2 * e2
    e4 = np.cos(th1)
    e5 = np.sin(th1)
    e6 = e4 * px1 - e5 * py1
    e7 = cx2 * e0
    e8 = cy2 * e2
    e9 = e4 * py1 + e5 * px1
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = dx + e1 - e3 + e6
    v_y = dy - e7 - e8 + e9
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e10 = sg2 / v_len
    e11 = e10 * v_x
    e12 = e10 * v_y
    return (
        e11,
        e12,
        e10 * (e6 * v_y - e9 * v_x),
        -e11,
        -e12,
        e10 * (v_x * (e7 + e8) - v_y * (-e1 + e3)),
    )


@numba.njit(cache=True, error_model="numpy")
def bias(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, px1, py1, cx2, cy2, r2):
    """Velocity-dependent part of d'': the b-vector term. Returns b."""
    e0 = np.sin(th2)
    e1 = np.cos(th2)
    e2 = cx2 * e1
    e3 = np.cos(th1)
    e4 = np.sin(th1)
    e5 = e3 * px1 - e4 * py1
    e6 = cx2 * e0
    e7 = cy2 * e1
    e8 = e3 * py1 + e4 * px1
    e9 = e6 + e7
    e10 = -e8
    e11 = -cy2 * e0 + e2
    e13 = w1 * w1
    e14 = w2 * w2
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = cy2 * e0 + dx - e2 + e5
    v_y = dy - e6 - e7 + e8
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e12 = 1 / v_len
    v_x_t = e10 * w1 + e9 * w2 + vx1 - vx2
    v_y_t = -e11 * w2 + e5 * w1 + vy1 - vy2
    v_tan = e12 * (v_x * v_y_t - v_x_t * v_y)
    v_x_tt = e11 * e14 - e13 * e5
    v_y_tt = e10 * e13 + e14 * e9
    return sg2 * (e12 * v_tan * v_tan + e12 * (v_x * v_x_tt + v_y * v_y_tt))


@numba.njit(cache=True, error_model="numpy")
def gap_velocity_static2(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, px1, py1, cx2, cy2, r2):
    """Exact d' with body 2 fixed. Returns d1."""
    e0 = np.sin(th2)
    e1 = np.cos(th2)
    e2 = np.cos(th1)
    e3 = np.sin(th1)
    e4 = e2 * px1 - e3 * py1
    e5 = e2 * py1 + e3 * px1
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = -cx2 * e1 + cy2 * e0 + dx + e4
    v_y = -cx2 * e0 - cy2 * e1 + dy + e5
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    v_x_t = -e5 * w1 + vx1
    v_y_t = e4 * w1 + vy1
    return sg2 * (v_x * v_x_t + v_y * v_y_t) / v_len


@numba.njit(cache=True, error_model="numpy")
def gap_acceleration_static2(
    x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1, x2, y2, th2, px1, py1, cx2, cy2, r2
):
    """Exact d'' with body 2 fixed. Returns d2."""
    e0 = np.sin(th2)
    e1 = np.cos(th2)
    e2 = np.cos(th1)
    e3 = np.sin(th1)
    e4 = e2 * px1 - e3 * py1
    e5 = e2 * py1 + e3 * px1
    e6 = -e5
    e8 = w1 * w1
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = -cx2 * e1 + cy2 * e0 + dx + e4
    v_y = -cx2 * e0 - cy2 * e1 + dy + e5
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e7 = 1 / v_len
    v_x_t = e6 * w1 + vx1
    v_y_t = e4 * w1 + vy1
    v_tan = e7 * (v_x * v_y_t - v_x_t * v_y)
    v_x_tt = al1 * e6 + ax1 - e4 * e8
    v_y_tt = al1 * e4 + ay1 + e6 * e8
    return sg2 * (e7 * v_tan * v_tan + e7 * (v_x * v_x_tt + v_y * v_y_tt))


@numba.njit(cache=True, error_model="numpy")
def jacobian_static2(x1, y1, th1, x2, y2, th2, px1, py1, cx2, cy2, r2):
    """Body-1 Jacobian row with body 2 fixed. Returns j1x, j1y, j1th."""
    e0 = np.sin(th2)
    e1 = np.cos(th2)
    e2 = np.cos(th1)
    e3 = np.sin(th1)
    e4 = e2 * px1 - e3 * py1
    e5 = e2 * py1 + e3 * px1
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = -cx2 * e1 + cy2 * e0 + dx + e4
    v_y = -cx2 * e0 - cy2 * e1 + dy + e5
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e6 = sg2 / v_len
    return e6 * v_x, e6 * v_y, e6 * (e4 * v_y - e5 * v_x)


@numba.njit(cache=True, error_model="numpy")
def bias_static2(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, px1, py1, cx2, cy2, r2):
    """b-vector term with body 2 fixed. Returns b."""
    e0 = np.sin(th2)
    e1 = np.cos(th2)
    e2 = np.cos(th1)
    e3 = np.sin(th1)
    e4 = e2 * px1 - e3 * py1
    e5 = e2 * py1 + e3 * px1
    e6 = -e5
    e8 = w1 * w1
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = -cx2 * e1 + cy2 * e0 + dx + e4
    v_y = -cx2 * e0 - cy2 * e1 + dy + e5
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e7 = 1 / v_len
    v_x_t = e6 * w1 + vx1
    v_y_t = e4 * w1 + vy1
    v_tan = e7 * (v_x * v_y_t - v_x_t * v_y)
    v_x_tt = -e4 * e8
    v_y_tt = e6 * e8
    return sg2 * (e7 * v_tan * v_tan + e7 * (v_x * v_x_tt + v_y * v_y_tt))


@numba.njit(cache=True, error_model="numpy")
def batch_gap(poses, body1, body2, geometry, members, out):
    """out[k] = d of contact k, for k in members."""
    for k in members:
        i = body1[k]
        j = body2[k]
        out[k] = gap(
            poses[i, 0],
            poses[i, 1],
            poses[i, 2],
            poses[j, 0],
            poses[j, 1],
            poses[j, 2],
            geometry[k, 0],
            geometry[k, 1],
            geometry[k, 3],
            geometry[k, 4],
            geometry[k, 5],
        )


@numba.njit(cache=True, error_model="numpy")
def batch_gap_velocity(poses, velocities, body1, body2, geometry, static2, members, out):
    """out[k] = d' of contact k, for k in members (static2[k]: body 2 fixed)."""
    for k in members:
        i = body1[k]
        j = body2[k]
        if static2[k]:
            out[k] = gap_velocity_static2(
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
            out[k] = gap_velocity(
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
def batch_rows(poses, velocities, body1, body2, geometry, static2, members, jacobian_out, bias_out):
    """Jacobian row (6 numbers, body 1 then body 2) and bias of contact k, for k in members."""
    for k in members:
        i = body1[k]
        j = body2[k]
        if static2[k]:
            row = jacobian_static2(
                poses[i, 0],
                poses[i, 1],
                poses[i, 2],
                poses[j, 0],
                poses[j, 1],
                poses[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 3],
                geometry[k, 4],
                geometry[k, 5],
            )
            for c in range(3):
                jacobian_out[k, c] = row[c]
                jacobian_out[k, 3 + c] = 0.0
            bias_out[k] = bias_static2(
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
            row = jacobian(
                poses[i, 0],
                poses[i, 1],
                poses[i, 2],
                poses[j, 0],
                poses[j, 1],
                poses[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 3],
                geometry[k, 4],
                geometry[k, 5],
            )
            for c in range(6):
                jacobian_out[k, c] = row[c]
            bias_out[k] = bias(
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


@numba.njit(cache=True)
def batch_all(
    poses,
    velocities,
    body1,
    body2,
    geometry,
    static2,
    members,
    gap_out,
    rate_out,
    jacobian_out,
    bias_out,
):
    """d, d', the Jacobian row and the bias of contact k, for k in members."""
    batch_gap(poses, body1, body2, geometry, members, gap_out)
    batch_gap_velocity(poses, velocities, body1, body2, geometry, static2, members, rate_out)
    batch_rows(poses, velocities, body1, body2, geometry, static2, members, jacobian_out, bias_out)
