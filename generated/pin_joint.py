"""Pin joint (`pin_joint`): generated NumPy joint kernels. DO NOT EDIT.

Written by `regenerate-equations` from derive/joints.py through
templates/joint_module.py.j2; `regenerate-equations --check` fails when this file is stale.
Derivation: docs/derivations.pdf, section "Joints".

d = s = p1 - p2 (two rows: x and y in world axes),
with the anchors p1 = X1 + R(th1) (px1, py1) of body 1 and p2 = X2 + R(th2) (px2, py2) of body 2
(body coordinates: origin at the centre of mass). For a
joint to the world use the *_static2 functions with x2 = y2 = th2 = 0 and the anchor in world
coordinates. Two rows, x and y of s = p1 - p2 in world axes (outputs end in _x, _y).
Every function takes keyword arguments only and broadcasts over NumPy arrays (or plain floats);
ARGUMENTS lists each function's arguments in order; an entry that is constant (a pin's unit
directions in `jacobian`) is a plain float, to broadcast against the others. The rows are
bilateral: the runtime assembles A = J M^-1 J^T and b = J M^-1 F_ext + bias from the `jacobian`
rows like a contact's, and the joint force may take either sign.
"""

import numpy as np

ARGUMENTS = {
    "gap": ("x1", "y1", "th1", "x2", "y2", "th2", "px1", "py1", "px2", "py2"),
    "gap_velocity": (
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
        "px2",
        "py2",
    ),
    "gap_acceleration": (
        "th1",
        "w1",
        "ax1",
        "ay1",
        "al1",
        "th2",
        "w2",
        "ax2",
        "ay2",
        "al2",
        "px1",
        "py1",
        "px2",
        "py2",
    ),
    "jacobian": ("th1", "th2", "px1", "py1", "px2", "py2"),
    "bias": ("th1", "w1", "th2", "w2", "px1", "py1", "px2", "py2"),
    "gap_velocity_static2": ("th1", "vx1", "vy1", "w1", "px1", "py1"),
    "gap_acceleration_static2": ("th1", "w1", "ax1", "ay1", "al1", "px1", "py1"),
    "jacobian_static2": ("th1", "px1", "py1"),
    "bias_static2": ("th1", "w1", "px1", "py1"),
}


def gap(*, x1, y1, th1, x2, y2, th2, px1, py1, px2, py2):
    """Constraint value d (0 when the joint holds).

    d = (s_x, s_y),  s = p1 - p2 = X1 + R(th1) a1 - X2 - R(th2) a2
    Returns d_x, d_y.
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
    return s_x, s_y


def gap_velocity(*, th1, vx1, vy1, w1, th2, vx2, vy2, w2, px1, py1, px2, py2):
    """Exact d' for any state.

    d' = s'
    Returns d1_x, d1_y.
    """
    e0 = np.sin(th1)
    e1 = np.cos(th1)
    e2 = np.sin(th2)
    e3 = np.cos(th2)
    l1_x_t = w1 * (-e0 * px1 - e1 * py1)
    l1_y_t = w1 * (-e0 * py1 + e1 * px1)
    del e0, e1
    l2_x_t = w2 * (-e2 * px2 - e3 * py2)
    l2_y_t = w2 * (-e2 * py2 + e3 * px2)
    del e2, e3
    s_x_t = l1_x_t - l2_x_t + vx1 - vx2
    del l1_x_t, l2_x_t
    s_y_t = l1_y_t - l2_y_t + vy1 - vy2
    del l1_y_t, l2_y_t
    return s_x_t, s_y_t


def gap_acceleration(*, th1, w1, ax1, ay1, al1, th2, w2, ax2, ay2, al2, px1, py1, px2, py2):
    """Exact d'' for any state.

    d'' = s''
    Returns d2_x, d2_y.
    """
    e0 = np.sin(th1)
    e1 = np.cos(th1)
    e2 = -e0 * px1 - e1 * py1
    e3 = w1 * w1
    e4 = -e0 * py1 + e1 * px1
    del e0, e1
    e5 = np.sin(th2)
    e6 = np.cos(th2)
    e7 = -e5 * px2 - e6 * py2
    e8 = w2 * w2
    e9 = -e5 * py2 + e6 * px2
    del e5, e6
    l1_x_tt = al1 * e2 - e3 * e4
    l1_y_tt = al1 * e4 + e2 * e3
    del e2, e3, e4
    l2_x_tt = al2 * e7 - e8 * e9
    l2_y_tt = al2 * e9 + e7 * e8
    del e7, e8, e9
    s_x_tt = ax1 - ax2 + l1_x_tt - l2_x_tt
    del l1_x_tt, l2_x_tt
    s_y_tt = ay1 - ay2 + l1_y_tt - l2_y_tt
    del l1_y_tt, l2_y_tt
    return s_x_tt, s_y_tt


def jacobian(*, th1, th2, px1, py1, px2, py2):
    """Jacobian rows of the joint: the A-matrix lever terms.

    rows of (dd/dx1, dd/dy1, dd/dth1, dd/dx2, dd/dy2, dd/dth2) = the coefficients of the accelerations in d''
    Returns j1x_x, j1y_x, j1th_x, j2x_x, j2y_x, j2th_x, j1x_y, j1y_y, j1th_y, j2x_y, j2y_y, j2th_y.
    """
    e0 = np.sin(th1)
    e1 = np.cos(th1)
    e2 = np.sin(th2)
    e3 = np.cos(th2)
    return (
        1.0,
        0.0,
        -e0 * px1 - e1 * py1,
        -1.0,
        0.0,
        e2 * px2 + e3 * py2,
        0.0,
        1.0,
        -e0 * py1 + e1 * px1,
        0.0,
        -1.0,
        e2 * py2 - e3 * px2,
    )


def bias(*, th1, w1, th2, w2, px1, py1, px2, py2):
    """Velocity-dependent part of d'': the b-vector term.

    d'' = s''  with every acceleration zero
    Returns b_x, b_y.
    """
    e0 = w1 * w1
    e1 = np.cos(th1)
    e2 = np.sin(th1)
    e3 = w2 * w2
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    l1_x_tt = e0 * (-e1 * px1 + e2 * py1)
    l1_y_tt = e0 * (-e1 * py1 - e2 * px1)
    del e0, e1, e2
    l2_x_tt = e3 * (-e4 * px2 + e5 * py2)
    l2_y_tt = e3 * (-e4 * py2 - e5 * px2)
    del e3, e4, e5
    s_x_tt = l1_x_tt - l2_x_tt
    del l1_x_tt, l2_x_tt
    s_y_tt = l1_y_tt - l2_y_tt
    del l1_y_tt, l2_y_tt
    return s_x_tt, s_y_tt


def gap_velocity_static2(*, th1, vx1, vy1, w1, px1, py1):
    """Exact d' for any state.

    d' = s'  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns d1_x, d1_y.
    """
    e0 = np.sin(th1)
    e1 = np.cos(th1)
    l1_x_t = w1 * (-e0 * px1 - e1 * py1)
    l1_y_t = w1 * (-e0 * py1 + e1 * px1)
    del e0, e1
    s_x_t = l1_x_t + vx1
    del l1_x_t
    s_y_t = l1_y_t + vy1
    del l1_y_t
    return s_x_t, s_y_t


def gap_acceleration_static2(*, th1, w1, ax1, ay1, al1, px1, py1):
    """Exact d'' for any state.

    d'' = s''  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns d2_x, d2_y.
    """
    e0 = np.sin(th1)
    e1 = np.cos(th1)
    e2 = -e0 * px1 - e1 * py1
    e3 = w1 * w1
    e4 = -e0 * py1 + e1 * px1
    del e0, e1
    l1_x_tt = al1 * e2 - e3 * e4
    l1_y_tt = al1 * e4 + e2 * e3
    del e2, e3, e4
    s_x_tt = ax1 + l1_x_tt
    del l1_x_tt
    s_y_tt = ay1 + l1_y_tt
    del l1_y_tt
    return s_x_tt, s_y_tt


def jacobian_static2(*, th1, px1, py1):
    """Jacobian rows of the joint: the A-matrix lever terms.

    rows of (dd/dx1, dd/dy1, dd/dth1, dd/dx2, dd/dy2, dd/dth2) = the coefficients of the accelerations in d''  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns j1x_x, j1y_x, j1th_x, j1x_y, j1y_y, j1th_y.
    """
    e0 = np.sin(th1)
    e1 = np.cos(th1)
    return 1.0, 0.0, -e0 * px1 - e1 * py1, 0.0, 1.0, -e0 * py1 + e1 * px1


def bias_static2(*, th1, w1, px1, py1):
    """Velocity-dependent part of d'': the b-vector term.

    d'' = s''  with every acceleration zero  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns b_x, b_y.
    """
    e0 = w1 * w1
    e1 = np.cos(th1)
    e2 = np.sin(th1)
    l1_x_tt = e0 * (-e1 * px1 + e2 * py1)
    l1_y_tt = e0 * (-e1 * py1 - e2 * px1)
    del e0, e1, e2
    s_x_tt = l1_x_tt
    del l1_x_tt
    s_y_tt = l1_y_tt
    del l1_y_tt
    return s_x_tt, s_y_tt
