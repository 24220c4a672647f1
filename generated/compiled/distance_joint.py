"""Distance joint (`distance_joint`): generated joint kernels, compiled variant. DO NOT EDIT.

Written by `regenerate-equations` from derive/joints.py through
templates/joint_module_compiled.py.j2; `regenerate-equations --check` fails when this file is
stale. The same expressions as generated/distance_joint.py (the NumPy kernels, the public API),
compiled by numba, with batch loops over joints k: poses and velocities (n, 3), body1, body2 (a
negative body2[k] is the world: pose 0 and at rest, anchor 2 in world coordinates), geometry
(m, 7), static2 (m,) booleans (body 2 fixed), members: the joints to evaluate. The joint has
1 row(s): gap, rate and bias outputs are (m, 1), Jacobians (m, 1, 6).
Division by zero gives inf or NaN as in the NumPy kernels (numba's "numpy" error model): a
distance joint's direction is undefined when its anchors coincide.

Geometry columns (`geometry[k, c]`): px1 -> 0, py1 -> 1, px2 -> 3, py2 -> 4, length -> 5.
"""

import numba
import numpy as np

ARGUMENTS = {
    "gap": ("x1", "y1", "th1", "x2", "y2", "th2", "px1", "py1", "px2", "py2", "length"),
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
        "px2",
        "py2",
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
        "px2",
        "py2",
    ),
    "jacobian": ("x1", "y1", "th1", "x2", "y2", "th2", "px1", "py1", "px2", "py2"),
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
        "px2",
        "py2",
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
        "px2",
        "py2",
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
        "px2",
        "py2",
    ),
    "jacobian_static2": ("x1", "y1", "th1", "x2", "y2", "th2", "px1", "py1", "px2", "py2"),
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
        "px2",
        "py2",
    ),
}


@numba.njit(cache=True, error_model="numpy")
def gap(x1, y1, th1, x2, y2, th2, px1, py1, px2, py2, length):
    """Constraint value d (0 when the joint holds). Returns d."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e0 * px1 - e1 * py1
    l1_y = e0 * py1 + e1 * px1
    l2_x = e2 * px2 - e3 * py2
    l2_y = e2 * py2 + e3 * px2
    s_x = dx + l1_x - l2_x
    s_y = dy + l1_y - l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    return -length + s_len


@numba.njit(cache=True, error_model="numpy")
def gap_velocity(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, px1, py1, px2, py2):
    """Exact d' for any state. Returns d1."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    e6 = e4 * px2 - e5 * py2
    e7 = e4 * py2 + e5 * px2
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    l1_x_t = -e3 * w1
    l1_y_t = e2 * w1
    l2_x = e6
    l2_y = e7
    l2_x_t = -e7 * w2
    l2_y_t = e6 * w2
    s_x = dx + l1_x - l2_x
    s_y = dy + l1_y - l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    s_x_t = l1_x_t - l2_x_t + vx1 - vx2
    s_y_t = l1_y_t - l2_y_t + vy1 - vy2
    return (s_x * s_x_t + s_y * s_y_t) / s_len


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
    px2,
    py2,
):
    """Exact d'' for any state. Returns d2."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    e4 = -e3
    e5 = w1 * w1
    e6 = np.cos(th2)
    e7 = np.sin(th2)
    e8 = e6 * px2 - e7 * py2
    e9 = e6 * py2 + e7 * px2
    e10 = -e9
    e11 = w2 * w2
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    l1_x_t = e4 * w1
    l1_y_t = e2 * w1
    l1_x_tt = al1 * e4 - e2 * e5
    l1_y_tt = al1 * e2 + e4 * e5
    l2_x = e8
    l2_y = e9
    l2_x_t = e10 * w2
    l2_y_t = e8 * w2
    l2_x_tt = al2 * e10 - e11 * e8
    l2_y_tt = al2 * e8 + e10 * e11
    s_x = dx + l1_x - l2_x
    s_y = dy + l1_y - l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    e12 = 1 / s_len
    s_x_t = l1_x_t - l2_x_t + vx1 - vx2
    s_y_t = l1_y_t - l2_y_t + vy1 - vy2
    s_tan = e12 * (s_x * s_y_t - s_x_t * s_y)
    s_x_tt = ax1 - ax2 + l1_x_tt - l2_x_tt
    s_y_tt = ay1 - ay2 + l1_y_tt - l2_y_tt
    return e12 * (s_tan * s_tan + s_x * s_x_tt + s_y * s_y_tt)


@numba.njit(cache=True, error_model="numpy")
def jacobian(x1, y1, th1, x2, y2, th2, px1, py1, px2, py2):
    """Jacobian rows of the joint: the A-matrix lever terms. Returns j1x, j1y, j1th, j2x, j2y, j2th."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    e6 = e4 * px2 - e5 * py2
    e7 = e4 * py2 + e5 * px2
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    l2_x = e6
    l2_y = e7
    s_x = dx + l1_x - l2_x
    s_y = dy + l1_y - l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    e8 = 1 / s_len
    e9 = e8 * s_x
    e10 = e8 * s_y
    return e9, e10, e8 * (e2 * s_y - e3 * s_x), -e9, -e10, e8 * (-e6 * s_y + e7 * s_x)


@numba.njit(cache=True, error_model="numpy")
def bias(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, px1, py1, px2, py2):
    """Velocity-dependent part of d'': the b-vector term. Returns b."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    e4 = -e3
    e5 = w1 * w1
    e6 = np.cos(th2)
    e7 = np.sin(th2)
    e8 = e6 * px2 - e7 * py2
    e9 = e6 * py2 + e7 * px2
    e10 = -e9
    e11 = w2 * w2
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    l1_x_t = e4 * w1
    l1_y_t = e2 * w1
    l1_x_tt = -e2 * e5
    l1_y_tt = e4 * e5
    l2_x = e8
    l2_y = e9
    l2_x_t = e10 * w2
    l2_y_t = e8 * w2
    l2_x_tt = -e11 * e8
    l2_y_tt = e10 * e11
    s_x = dx + l1_x - l2_x
    s_y = dy + l1_y - l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    e12 = 1 / s_len
    s_x_t = l1_x_t - l2_x_t + vx1 - vx2
    s_y_t = l1_y_t - l2_y_t + vy1 - vy2
    s_tan = e12 * (s_x * s_y_t - s_x_t * s_y)
    s_x_tt = l1_x_tt - l2_x_tt
    s_y_tt = l1_y_tt - l2_y_tt
    return e12 * (s_tan * s_tan + s_x * s_x_tt + s_y * s_y_tt)


@numba.njit(cache=True, error_model="numpy")
def gap_velocity_static2(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, px1, py1, px2, py2):
    """Exact d' for any state. Returns d1."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    l1_x_t = -e3 * w1
    l1_y_t = e2 * w1
    l2_x = e4 * px2 - e5 * py2
    l2_y = e4 * py2 + e5 * px2
    s_x = dx + l1_x - l2_x
    s_y = dy + l1_y - l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    s_x_t = l1_x_t + vx1
    s_y_t = l1_y_t + vy1
    return (s_x * s_x_t + s_y * s_y_t) / s_len


@numba.njit(cache=True, error_model="numpy")
def gap_acceleration_static2(
    x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1, x2, y2, th2, px1, py1, px2, py2
):
    """Exact d'' for any state. Returns d2."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    e4 = -e3
    e5 = w1 * w1
    e6 = np.cos(th2)
    e7 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    l1_x_t = e4 * w1
    l1_y_t = e2 * w1
    l1_x_tt = al1 * e4 - e2 * e5
    l1_y_tt = al1 * e2 + e4 * e5
    l2_x = e6 * px2 - e7 * py2
    l2_y = e6 * py2 + e7 * px2
    s_x = dx + l1_x - l2_x
    s_y = dy + l1_y - l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    e8 = 1 / s_len
    s_x_t = l1_x_t + vx1
    s_y_t = l1_y_t + vy1
    s_tan = e8 * (s_x * s_y_t - s_x_t * s_y)
    s_x_tt = ax1 + l1_x_tt
    s_y_tt = ay1 + l1_y_tt
    return e8 * (s_tan * s_tan + s_x * s_x_tt + s_y * s_y_tt)


@numba.njit(cache=True, error_model="numpy")
def jacobian_static2(x1, y1, th1, x2, y2, th2, px1, py1, px2, py2):
    """Jacobian rows of the joint: the A-matrix lever terms. Returns j1x, j1y, j1th."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    l2_x = e4 * px2 - e5 * py2
    l2_y = e4 * py2 + e5 * px2
    s_x = dx + l1_x - l2_x
    s_y = dy + l1_y - l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    e6 = 1 / s_len
    return e6 * s_x, e6 * s_y, e6 * (e2 * s_y - e3 * s_x)


@numba.njit(cache=True, error_model="numpy")
def bias_static2(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, px1, py1, px2, py2):
    """Velocity-dependent part of d'': the b-vector term. Returns b."""
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    e4 = -e3
    e5 = w1 * w1
    e6 = np.cos(th2)
    e7 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    l1_x_t = e4 * w1
    l1_y_t = e2 * w1
    l1_x_tt = -e2 * e5
    l1_y_tt = e4 * e5
    l2_x = e6 * px2 - e7 * py2
    l2_y = e6 * py2 + e7 * px2
    s_x = dx + l1_x - l2_x
    s_y = dy + l1_y - l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    e8 = 1 / s_len
    s_x_t = l1_x_t + vx1
    s_y_t = l1_y_t + vy1
    s_tan = e8 * (s_x * s_y_t - s_x_t * s_y)
    s_x_tt = l1_x_tt
    s_y_tt = l1_y_tt
    return e8 * (s_tan * s_tan + s_x * s_x_tt + s_y * s_y_tt)


@numba.njit(cache=True, error_model="numpy")
def body2_pose(poses, j):
    """Body 2's pose; j < 0 is the world (origin, angle 0)."""
    if j < 0:
        return 0.0, 0.0, 0.0
    return poses[j, 0], poses[j, 1], poses[j, 2]


@numba.njit(cache=True, error_model="numpy")
def batch_gap(poses, body1, body2, geometry, members, out):
    """out[k, r] = d of row r of joint k, for k in members."""
    for k in members:
        i = body1[k]
        x2, y2, th2 = body2_pose(poses, body2[k])
        out[k, 0] = gap(
            poses[i, 0],
            poses[i, 1],
            poses[i, 2],
            x2,
            y2,
            th2,
            geometry[k, 0],
            geometry[k, 1],
            geometry[k, 3],
            geometry[k, 4],
            geometry[k, 5],
        )


@numba.njit(cache=True, error_model="numpy")
def batch_gap_velocity(poses, velocities, body1, body2, geometry, static2, members, out):
    """out[k, r] = d' of row r of joint k (static2[k] or body2[k] < 0: body 2 fixed)."""
    for k in members:
        i = body1[k]
        j = body2[k]
        x2, y2, th2 = body2_pose(poses, j)
        if static2[k] or j < 0:
            out[k, 0] = gap_velocity_static2(
                poses[i, 0],
                poses[i, 1],
                poses[i, 2],
                velocities[i, 0],
                velocities[i, 1],
                velocities[i, 2],
                x2,
                y2,
                th2,
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 3],
                geometry[k, 4],
            )
        else:
            out[k, 0] = gap_velocity(
                poses[i, 0],
                poses[i, 1],
                poses[i, 2],
                velocities[i, 0],
                velocities[i, 1],
                velocities[i, 2],
                x2,
                y2,
                th2,
                velocities[j, 0],
                velocities[j, 1],
                velocities[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 3],
                geometry[k, 4],
            )


@numba.njit(cache=True, error_model="numpy")
def batch_rows(poses, velocities, body1, body2, geometry, static2, members, jacobian_out, bias_out):
    """Jacobian rows (jacobian_out[k, r]: 6 numbers, body 1 then body 2) and biases of joint k."""
    for k in members:
        i = body1[k]
        j = body2[k]
        x2, y2, th2 = body2_pose(poses, j)
        if static2[k] or j < 0:
            row = jacobian_static2(
                poses[i, 0],
                poses[i, 1],
                poses[i, 2],
                x2,
                y2,
                th2,
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 3],
                geometry[k, 4],
            )
            for c in range(3):
                jacobian_out[k, 0, c] = row[c]
                jacobian_out[k, 0, 3 + c] = 0.0
            bias_out[k, 0] = bias_static2(
                poses[i, 0],
                poses[i, 1],
                poses[i, 2],
                velocities[i, 0],
                velocities[i, 1],
                velocities[i, 2],
                x2,
                y2,
                th2,
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 3],
                geometry[k, 4],
            )
        else:
            row = jacobian(
                poses[i, 0],
                poses[i, 1],
                poses[i, 2],
                x2,
                y2,
                th2,
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 3],
                geometry[k, 4],
            )
            for c in range(6):
                jacobian_out[k, 0, c] = row[c]
            bias_out[k, 0] = bias(
                poses[i, 0],
                poses[i, 1],
                poses[i, 2],
                velocities[i, 0],
                velocities[i, 1],
                velocities[i, 2],
                x2,
                y2,
                th2,
                velocities[j, 0],
                velocities[j, 1],
                velocities[j, 2],
                geometry[k, 0],
                geometry[k, 1],
                geometry[k, 3],
                geometry[k, 4],
            )


@numba.njit(cache=True, error_model="numpy")
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
    """d, d', the Jacobian rows and the biases of joint k, for k in members."""
    batch_gap(poses, body1, body2, geometry, members, gap_out)
    batch_gap_velocity(poses, velocities, body1, body2, geometry, static2, members, rate_out)
    batch_rows(poses, velocities, body1, body2, geometry, static2, members, jacobian_out, bias_out)
