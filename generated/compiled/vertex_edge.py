"""Vertex on straight edge (`vertex_edge`): generated kernels, compiled variant. DO NOT EDIT.

Written by `regenerate-equations` from derive/ through
templates/kernel_module_compiled.py.j2; `regenerate-equations --check` fails when this file is stale.
The same expressions as generated/vertex_edge.py (the NumPy kernels, the public API), for
scalars and compiled by numba: positional arguments in the order of ARGUMENTS, no `del` (numba
has none), and batch loops that read the state from (n, 3) pose and velocity arrays, so the
engine evaluates many contacts in one compiled call. Division by zero gives inf or NaN as in
the NumPy kernels (numba's "numpy" error model), not ZeroDivisionError: d' of two coincident
circle centres is undefined, and the engine decides what to do with a non-finite value.

Geometry columns (`geometry[k, c]`): px1 -> 0, py1 -> 1, ex2 -> 3, ey2 -> 4, nx2 -> 5, ny2 -> 6.
"""

import numba
import numpy as np

ARGUMENTS = {
    "gap": ("x1", "y1", "th1", "x2", "y2", "th2", "px1", "py1", "ex2", "ey2", "nx2", "ny2"),
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
        "ex2",
        "ey2",
        "nx2",
        "ny2",
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
        "ex2",
        "ey2",
        "nx2",
        "ny2",
    ),
    "jacobian": ("x1", "y1", "th1", "x2", "y2", "th2", "px1", "py1", "ex2", "ey2", "nx2", "ny2"),
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
        "ex2",
        "ey2",
        "nx2",
        "ny2",
    ),
    "gap_velocity_static2": ("th1", "vx1", "vy1", "w1", "th2", "px1", "py1", "nx2", "ny2"),
    "gap_acceleration_static2": (
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
    "jacobian_static2": ("th1", "th2", "px1", "py1", "nx2", "ny2"),
    "bias_static2": ("th1", "w1", "th2", "px1", "py1", "nx2", "ny2"),
}


@numba.njit(cache=True, error_model="numpy")
def gap(x1, y1, th1, x2, y2, th2, px1, py1, ex2, ey2, nx2, ny2):
    """Gap d (> 0 separated). Returns d."""
    e0 = np.cos(th2)
    e1 = np.sin(th2)
    e2 = np.cos(th1)
    e3 = np.sin(th1)
    dx = x1 - x2
    dy = y1 - y2
    n_x = e0 * nx2 - e1 * ny2
    n_y = e0 * ny2 + e1 * nx2
    v_x = dx - e0 * ex2 + e1 * ey2 + e2 * px1 - e3 * py1
    v_y = dy - e0 * ey2 - e1 * ex2 + e2 * py1 + e3 * px1
    return n_x * v_x + n_y * v_y


@numba.njit(cache=True, error_model="numpy")
def gap_velocity(
    x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, px1, py1, ex2, ey2, nx2, ny2
):
    """Exact d' for any state. Returns d1."""
    e0 = np.cos(th2)
    e1 = np.sin(th2)
    e2 = e0 * nx2 - e1 * ny2
    e3 = e0 * ny2 + e1 * nx2
    e4 = e0 * ex2
    e5 = np.cos(th1)
    e6 = np.sin(th1)
    e7 = e5 * px1 - e6 * py1
    e8 = e1 * ex2
    e9 = e0 * ey2
    e10 = e5 * py1 + e6 * px1
    dx = x1 - x2
    dy = y1 - y2
    n_x = e2
    n_y = e3
    n_x_t = -e3 * w2
    n_y_t = e2 * w2
    v_x = dx + e1 * ey2 - e4 + e7
    v_y = dy + e10 - e8 - e9
    v_x_t = -e10 * w1 + vx1 - vx2 + w2 * (e8 + e9)
    v_y_t = e7 * w1 + vy1 - vy2 + w2 * (e1 * ey2 - e4)
    return n_x * v_x_t + n_x_t * v_x + n_y * v_y_t + n_y_t * v_y


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
    ex2,
    ey2,
    nx2,
    ny2,
):
    """Exact d'' for any state. Returns d2."""
    e0 = np.cos(th2)
    e1 = np.sin(th2)
    e2 = e0 * nx2 - e1 * ny2
    e3 = e0 * ny2 + e1 * nx2
    e4 = -e3
    e5 = w2 * w2
    e6 = e0 * ex2
    e7 = np.cos(th1)
    e8 = np.sin(th1)
    e9 = e7 * px1 - e8 * py1
    e10 = e1 * ex2
    e11 = e0 * ey2
    e12 = e7 * py1 + e8 * px1
    e13 = e10 + e11
    e14 = -e12
    e15 = -e1 * ey2 + e6
    e16 = -e15
    e17 = w1 * w1
    dx = x1 - x2
    dy = y1 - y2
    n_x = e2
    n_y = e3
    n_x_t = e4 * w2
    n_y_t = e2 * w2
    n_x_tt = al2 * e4 - e2 * e5
    n_y_tt = al2 * e2 + e4 * e5
    v_x = dx + e1 * ey2 - e6 + e9
    v_y = dy - e10 - e11 + e12
    v_x_t = e13 * w2 + e14 * w1 + vx1 - vx2
    v_y_t = e16 * w2 + e9 * w1 + vy1 - vy2
    v_x_tt = al1 * e14 + al2 * e13 + ax1 - ax2 + e15 * e5 - e17 * e9
    v_y_tt = al1 * e9 + al2 * e16 + ay1 - ay2 + e13 * e5 + e14 * e17
    return (
        n_x * v_x_tt
        + 2 * n_x_t * v_x_t
        + n_x_tt * v_x
        + n_y * v_y_tt
        + 2 * n_y_t * v_y_t
        + n_y_tt * v_y
    )


@numba.njit(cache=True, error_model="numpy")
def jacobian(x1, y1, th1, x2, y2, th2, px1, py1, ex2, ey2, nx2, ny2):
    """Jacobian row of the gap: the A-matrix lever terms. Returns j1x, j1y, j1th, j2x, j2y, j2th."""
    e0 = np.cos(th2)
    e1 = np.sin(th2)
    e2 = e0 * nx2 - e1 * ny2
    e3 = e0 * ny2 + e1 * nx2
    e4 = e1 * ey2
    e5 = e0 * ex2
    e6 = np.cos(th1)
    e7 = np.sin(th1)
    e8 = e6 * px1 - e7 * py1
    e9 = e1 * ex2
    e10 = e0 * ey2
    e11 = e6 * py1 + e7 * px1
    dx = x1 - x2
    dy = y1 - y2
    n_x = e2
    n_y = e3
    v_x = dx + e4 - e5 + e8
    v_y = dy - e10 + e11 - e9
    return (
        n_x,
        n_y,
        -e11 * n_x + e8 * n_y,
        -n_x,
        -n_y,
        e2 * v_y - e3 * v_x + n_x * (e10 + e9) - n_y * (-e4 + e5),
    )


@numba.njit(cache=True, error_model="numpy")
def bias(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, px1, py1, ex2, ey2, nx2, ny2):
    """Velocity-dependent part of d'': the b-vector term. Returns b."""
    e0 = np.cos(th2)
    e1 = np.sin(th2)
    e2 = e0 * nx2 - e1 * ny2
    e3 = e0 * ny2 + e1 * nx2
    e4 = -e3
    e5 = w2 * w2
    e6 = e0 * ex2
    e7 = np.cos(th1)
    e8 = np.sin(th1)
    e9 = e7 * px1 - e8 * py1
    e10 = e1 * ex2
    e11 = e0 * ey2
    e12 = e7 * py1 + e8 * px1
    e13 = e10 + e11
    e14 = -e12
    e15 = -e1 * ey2 + e6
    e16 = w1 * w1
    dx = x1 - x2
    dy = y1 - y2
    n_x = e2
    n_y = e3
    n_x_t = e4 * w2
    n_y_t = e2 * w2
    n_x_tt = -e2 * e5
    n_y_tt = e4 * e5
    v_x = dx + e1 * ey2 - e6 + e9
    v_y = dy - e10 - e11 + e12
    v_x_t = e13 * w2 + e14 * w1 + vx1 - vx2
    v_y_t = -e15 * w2 + e9 * w1 + vy1 - vy2
    v_x_tt = e15 * e5 - e16 * e9
    v_y_tt = e13 * e5 + e14 * e16
    return (
        n_x * v_x_tt
        + 2 * n_x_t * v_x_t
        + n_x_tt * v_x
        + n_y * v_y_tt
        + 2 * n_y_t * v_y_t
        + n_y_tt * v_y
    )


@numba.njit(cache=True, error_model="numpy")
def gap_velocity_static2(th1, vx1, vy1, w1, th2, px1, py1, nx2, ny2):
    """Exact d' with body 2 fixed. Returns d1."""
    e0 = np.cos(th2)
    e1 = np.sin(th2)
    e2 = np.sin(th1)
    e3 = np.cos(th1)
    n_x = e0 * nx2 - e1 * ny2
    n_y = e0 * ny2 + e1 * nx2
    v_x_t = vx1 + w1 * (-e2 * px1 - e3 * py1)
    v_y_t = vy1 + w1 * (-e2 * py1 + e3 * px1)
    return n_x * v_x_t + n_y * v_y_t


@numba.njit(cache=True, error_model="numpy")
def gap_acceleration_static2(th1, w1, ax1, ay1, al1, th2, px1, py1, nx2, ny2):
    """Exact d'' with body 2 fixed. Returns d2."""
    e0 = np.cos(th2)
    e1 = np.sin(th2)
    e2 = np.sin(th1)
    e3 = np.cos(th1)
    e4 = -e2 * px1 - e3 * py1
    e5 = w1 * w1
    e6 = -e2 * py1 + e3 * px1
    n_x = e0 * nx2 - e1 * ny2
    n_y = e0 * ny2 + e1 * nx2
    v_x_tt = al1 * e4 + ax1 - e5 * e6
    v_y_tt = al1 * e6 + ay1 + e4 * e5
    return n_x * v_x_tt + n_y * v_y_tt


@numba.njit(cache=True, error_model="numpy")
def jacobian_static2(th1, th2, px1, py1, nx2, ny2):
    """Body-1 Jacobian row with body 2 fixed. Returns j1x, j1y, j1th."""
    e0 = np.cos(th2)
    e1 = np.sin(th2)
    e2 = np.sin(th1)
    e3 = np.cos(th1)
    n_x = e0 * nx2 - e1 * ny2
    n_y = e0 * ny2 + e1 * nx2
    return n_x, n_y, -n_x * (e2 * px1 + e3 * py1) + n_y * (-e2 * py1 + e3 * px1)


@numba.njit(cache=True, error_model="numpy")
def bias_static2(th1, w1, th2, px1, py1, nx2, ny2):
    """b-vector term with body 2 fixed. Returns b."""
    e0 = np.cos(th2)
    e1 = np.sin(th2)
    e2 = w1 * w1
    e3 = np.cos(th1)
    e4 = np.sin(th1)
    n_x = e0 * nx2 - e1 * ny2
    n_y = e0 * ny2 + e1 * nx2
    v_x_tt = e2 * (-e3 * px1 + e4 * py1)
    v_y_tt = e2 * (-e3 * py1 - e4 * px1)
    return n_x * v_x_tt + n_y * v_y_tt


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
            geometry[k, 6],
        )


@numba.njit(cache=True, error_model="numpy")
def batch_gap_velocity(poses, velocities, body1, body2, geometry, static2, members, out):
    """out[k] = d' of contact k, for k in members (static2[k]: body 2 fixed)."""
    for k in members:
        i = body1[k]
        j = body2[k]
        if static2[k]:
            out[k] = gap_velocity_static2(
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
                geometry[k, 6],
            )


@numba.njit(cache=True, error_model="numpy")
def batch_rows(poses, velocities, body1, body2, geometry, static2, members, jacobian_out, bias_out):
    """Jacobian row (6 numbers, body 1 then body 2) and bias of contact k, for k in members."""
    for k in members:
        i = body1[k]
        j = body2[k]
        if static2[k]:
            row = jacobian_static2(
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
            bias_out[k] = bias_static2(
                poses[i, 2],
                velocities[i, 2],
                poses[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 5],
                geometry[k, 6],
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
                geometry[k, 6],
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
                geometry[k, 6],
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
