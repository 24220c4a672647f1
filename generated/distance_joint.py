"""Distance joint (`distance_joint`): generated NumPy joint kernels. DO NOT EDIT.

Written by `regenerate-equations` from derive/joints.py through
templates/joint_module.py.j2; `regenerate-equations --check` fails when this file is stale.
Derivation: docs/derivations.pdf, section "Joints".

d = |p1 - p2| - length,
with the anchors p1 = X1 + R(th1) (px1, py1) of body 1 and p2 = X2 + R(th2) (px2, py2) of body 2
(body coordinates: origin at the centre of mass). For a
joint to the world use the *_static2 functions with x2 = y2 = th2 = 0 and the anchor in world
coordinates. One row; it needs |s| > 0 (length > 0: a zero length is a pin joint).
Every function takes keyword arguments only and broadcasts over NumPy arrays (or plain floats);
ARGUMENTS lists each function's arguments in order; an entry that is constant (a pin's unit
directions in `jacobian`) is a plain float, to broadcast against the others. The rows are
bilateral: the runtime assembles A = J M^-1 J^T and b = J M^-1 F_ext + bias from the `jacobian`
rows like a contact's, and the joint force may take either sign.
"""

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


def gap(*, x1, y1, th1, x2, y2, th2, px1, py1, px2, py2, length):
    """Constraint value d (0 when the joint holds).

    d = |s| - length,  s = p1 - p2 = X1 + R(th1) a1 - X2 - R(th2) a2
    Returns d.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e0 * px1 - e1 * py1
    l1_y = e0 * py1 + e1 * px1
    del e0, e1
    l2_x = e2 * px2 - e3 * py2
    l2_y = e2 * py2 + e3 * px2
    del e2, e3
    s_x = dx + l1_x - l2_x
    del dx, l1_x, l2_x
    s_y = dy + l1_y - l2_y
    del dy, l1_y, l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    del s_x, s_y
    return -length + s_len


def gap_velocity(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, px1, py1, px2, py2):
    """Exact d' for any state.

    d' = n . s',  n = s/|s|
    Returns d1.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    del e0, e1
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    e6 = e4 * px2 - e5 * py2
    e7 = e4 * py2 + e5 * px2
    del e4, e5
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    l1_x_t = -e3 * w1
    del e3
    l1_y_t = e2 * w1
    del e2
    l2_x = e6
    l2_y = e7
    l2_x_t = -e7 * w2
    del e7
    l2_y_t = e6 * w2
    del e6
    s_x = dx + l1_x - l2_x
    del dx, l1_x, l2_x
    s_y = dy + l1_y - l2_y
    del dy, l1_y, l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    s_x_t = l1_x_t - l2_x_t + vx1 - vx2
    del l1_x_t, l2_x_t
    s_y_t = l1_y_t - l2_y_t + vy1 - vy2
    del l1_y_t, l2_y_t
    return (s_x * s_x_t + s_y * s_y_t) / s_len


def gap_acceleration(
    *,
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
    """Exact d'' for any state.

    d'' = (s . s'' + s_tan^2)/|s|,  s_tan = (s x s')/|s|
    Returns d2.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    del e0, e1
    e4 = -e3
    e5 = w1 * w1
    e6 = np.cos(th2)
    e7 = np.sin(th2)
    e8 = e6 * px2 - e7 * py2
    e9 = e6 * py2 + e7 * px2
    del e6, e7
    e10 = -e9
    e11 = w2 * w2
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    del e3
    l1_x_t = e4 * w1
    l1_y_t = e2 * w1
    l1_x_tt = al1 * e4 - e2 * e5
    l1_y_tt = al1 * e2 + e4 * e5
    del e2, e4, e5
    l2_x = e8
    l2_y = e9
    del e9
    l2_x_t = e10 * w2
    l2_y_t = e8 * w2
    l2_x_tt = al2 * e10 - e11 * e8
    l2_y_tt = al2 * e8 + e10 * e11
    del e10, e11, e8
    s_x = dx + l1_x - l2_x
    del dx, l1_x, l2_x
    s_y = dy + l1_y - l2_y
    del dy, l1_y, l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    e12 = 1 / s_len
    del s_len
    s_x_t = l1_x_t - l2_x_t + vx1 - vx2
    del l1_x_t, l2_x_t
    s_y_t = l1_y_t - l2_y_t + vy1 - vy2
    del l1_y_t, l2_y_t
    s_tan = e12 * (s_x * s_y_t - s_x_t * s_y)
    del s_x_t, s_y_t
    s_x_tt = ax1 - ax2 + l1_x_tt - l2_x_tt
    del l1_x_tt, l2_x_tt
    s_y_tt = ay1 - ay2 + l1_y_tt - l2_y_tt
    del l1_y_tt, l2_y_tt
    return e12 * (s_tan * s_tan + s_x * s_x_tt + s_y * s_y_tt)


def jacobian(*, x1, y1, th1, x2, y2, th2, px1, py1, px2, py2):
    """Jacobian rows of the joint: the A-matrix lever terms.

    rows of (dd/dx1, dd/dy1, dd/dth1, dd/dx2, dd/dy2, dd/dth2) = the coefficients of the accelerations in d''
    Returns j1x, j1y, j1th, j2x, j2y, j2th.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    del e0, e1
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    e6 = e4 * px2 - e5 * py2
    e7 = e4 * py2 + e5 * px2
    del e4, e5
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    l2_x = e6
    l2_y = e7
    s_x = dx + l1_x - l2_x
    del dx, l1_x, l2_x
    s_y = dy + l1_y - l2_y
    del dy, l1_y, l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    e8 = 1 / s_len
    del s_len
    e9 = e8 * s_x
    e10 = e8 * s_y
    return e9, e10, e8 * (e2 * s_y - e3 * s_x), -e9, -e10, e8 * (-e6 * s_y + e7 * s_x)


def bias(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, px1, py1, px2, py2):
    """Velocity-dependent part of d'': the b-vector term.

    d'' = (s . s'' + s_tan^2)/|s|,  s_tan = (s x s')/|s|  with every acceleration zero
    Returns b.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    del e0, e1
    e4 = -e3
    e5 = w1 * w1
    e6 = np.cos(th2)
    e7 = np.sin(th2)
    e8 = e6 * px2 - e7 * py2
    e9 = e6 * py2 + e7 * px2
    del e6, e7
    e10 = -e9
    e11 = w2 * w2
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    del e3
    l1_x_t = e4 * w1
    l1_y_t = e2 * w1
    l1_x_tt = -e2 * e5
    del e2
    l1_y_tt = e4 * e5
    del e4, e5
    l2_x = e8
    l2_y = e9
    del e9
    l2_x_t = e10 * w2
    l2_y_t = e8 * w2
    l2_x_tt = -e11 * e8
    del e8
    l2_y_tt = e10 * e11
    del e10, e11
    s_x = dx + l1_x - l2_x
    del dx, l1_x, l2_x
    s_y = dy + l1_y - l2_y
    del dy, l1_y, l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    e12 = 1 / s_len
    del s_len
    s_x_t = l1_x_t - l2_x_t + vx1 - vx2
    del l1_x_t, l2_x_t
    s_y_t = l1_y_t - l2_y_t + vy1 - vy2
    del l1_y_t, l2_y_t
    s_tan = e12 * (s_x * s_y_t - s_x_t * s_y)
    del s_x_t, s_y_t
    s_x_tt = l1_x_tt - l2_x_tt
    del l1_x_tt, l2_x_tt
    s_y_tt = l1_y_tt - l2_y_tt
    del l1_y_tt, l2_y_tt
    return e12 * (s_tan * s_tan + s_x * s_x_tt + s_y * s_y_tt)


def gap_velocity_static2(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, px1, py1, px2, py2):
    """Exact d' for any state.

    d' = n . s',  n = s/|s|  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns d1.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    del e0, e1
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    l1_x_t = -e3 * w1
    del e3
    l1_y_t = e2 * w1
    del e2
    l2_x = e4 * px2 - e5 * py2
    l2_y = e4 * py2 + e5 * px2
    del e4, e5
    s_x = dx + l1_x - l2_x
    del dx, l1_x, l2_x
    s_y = dy + l1_y - l2_y
    del dy, l1_y, l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    s_x_t = l1_x_t + vx1
    del l1_x_t
    s_y_t = l1_y_t + vy1
    del l1_y_t
    return (s_x * s_x_t + s_y * s_y_t) / s_len


def gap_acceleration_static2(
    *, x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1, x2, y2, th2, px1, py1, px2, py2
):
    """Exact d'' for any state.

    d'' = (s . s'' + s_tan^2)/|s|,  s_tan = (s x s')/|s|  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns d2.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    del e0, e1
    e4 = -e3
    e5 = w1 * w1
    e6 = np.cos(th2)
    e7 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    del e3
    l1_x_t = e4 * w1
    l1_y_t = e2 * w1
    l1_x_tt = al1 * e4 - e2 * e5
    l1_y_tt = al1 * e2 + e4 * e5
    del e2, e4, e5
    l2_x = e6 * px2 - e7 * py2
    l2_y = e6 * py2 + e7 * px2
    del e6, e7
    s_x = dx + l1_x - l2_x
    del dx, l1_x, l2_x
    s_y = dy + l1_y - l2_y
    del dy, l1_y, l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    e8 = 1 / s_len
    del s_len
    s_x_t = l1_x_t + vx1
    del l1_x_t
    s_y_t = l1_y_t + vy1
    del l1_y_t
    s_tan = e8 * (s_x * s_y_t - s_x_t * s_y)
    del s_x_t, s_y_t
    s_x_tt = ax1 + l1_x_tt
    del l1_x_tt
    s_y_tt = ay1 + l1_y_tt
    del l1_y_tt
    return e8 * (s_tan * s_tan + s_x * s_x_tt + s_y * s_y_tt)


def jacobian_static2(*, x1, y1, th1, x2, y2, th2, px1, py1, px2, py2):
    """Jacobian rows of the joint: the A-matrix lever terms.

    rows of (dd/dx1, dd/dy1, dd/dth1, dd/dx2, dd/dy2, dd/dth2) = the coefficients of the accelerations in d''  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns j1x, j1y, j1th.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    del e0, e1
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    l2_x = e4 * px2 - e5 * py2
    l2_y = e4 * py2 + e5 * px2
    del e4, e5
    s_x = dx + l1_x - l2_x
    del dx, l1_x, l2_x
    s_y = dy + l1_y - l2_y
    del dy, l1_y, l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    e6 = 1 / s_len
    del s_len
    return e6 * s_x, e6 * s_y, e6 * (e2 * s_y - e3 * s_x)


def bias_static2(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, px1, py1, px2, py2):
    """Velocity-dependent part of d'': the b-vector term.

    d'' = (s . s'' + s_tan^2)/|s|,  s_tan = (s x s')/|s|  with every acceleration zero  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns b.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = e0 * px1 - e1 * py1
    e3 = e0 * py1 + e1 * px1
    del e0, e1
    e4 = -e3
    e5 = w1 * w1
    e6 = np.cos(th2)
    e7 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    l1_x = e2
    l1_y = e3
    del e3
    l1_x_t = e4 * w1
    l1_y_t = e2 * w1
    l1_x_tt = -e2 * e5
    del e2
    l1_y_tt = e4 * e5
    del e4, e5
    l2_x = e6 * px2 - e7 * py2
    l2_y = e6 * py2 + e7 * px2
    del e6, e7
    s_x = dx + l1_x - l2_x
    del dx, l1_x, l2_x
    s_y = dy + l1_y - l2_y
    del dy, l1_y, l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    e8 = 1 / s_len
    del s_len
    s_x_t = l1_x_t + vx1
    del l1_x_t
    s_y_t = l1_y_t + vy1
    del l1_y_t
    s_tan = e8 * (s_x * s_y_t - s_x_t * s_y)
    del s_x_t, s_y_t
    s_x_tt = l1_x_tt
    del l1_x_tt
    s_y_tt = l1_y_tt
    del l1_y_tt
    return e8 * (s_tan * s_tan + s_x * s_x_tt + s_y * s_y_tt)
