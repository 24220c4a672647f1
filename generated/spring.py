"""Spring with a dashpot (`spring`): generated NumPy applied-force kernels. DO NOT EDIT.

Written by `regenerate-equations` from derive/applied.py through
templates/applied_module.py.j2; `regenerate-equations --check` fails when this file is stale.
Derivation: docs/derivations.pdf, section "Applied forces".

V = stiffness/2 (|s| - rest_length)^2,  s = p1 - p2 = X1 + R(th1) a1 - X2 - R(th2) a2,  R = damping/2 (d|s|/dt)^2:
the generalized forces Q = -dV/dq - dR/dq' on (x1, y1, th1, x2, y2, th2), by SymPy: the force and
torque on each body (body coordinates: origin at the centre of mass), which the runtime adds to
the free accelerations as Q / m and Q / I at every stage; `potential` (if there is one) is what
run.energy adds. A spring to the world: `force_static2` and `potential` with x2 = y2 = th2 = 0 and anchor 2 in world coordinates. Where the anchors coincide the direction s/|s| is taken as 0.
Every function takes keyword arguments only and broadcasts over NumPy arrays (or plain floats);
ARGUMENTS lists each function's arguments in order.
"""

import numpy as np

ARGUMENTS = {
    "force": (
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
        "rest_length",
        "stiffness",
        "damping",
    ),
    "force_static2": (
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
        "rest_length",
        "stiffness",
        "damping",
    ),
    "potential": (
        "x1",
        "y1",
        "th1",
        "x2",
        "y2",
        "th2",
        "px1",
        "py1",
        "px2",
        "py2",
        "rest_length",
        "stiffness",
    ),
}


def force(
    *,
    x1,
    y1,
    th1,
    vx1,
    vy1,
    w1,
    x2,
    y2,
    th2,
    vx2,
    vy2,
    w2,
    px1,
    py1,
    px2,
    py2,
    rest_length,
    stiffness,
    damping,
):
    """Generalized forces Q = -dV/dq - dR/dq': force and torque on each body (N, N m).

    V = stiffness/2 (|s| - rest_length)^2,  s = p1 - p2 = X1 + R(th1) a1 - X2 - R(th2) a2,  R = damping/2 (d|s|/dt)^2
    Returns fx1, fy1, tau1, fx2, fy2, tau2.
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
    del dx
    s_y = dy + l1_y - l2_y
    del dy
    e17 = -l2_x * s_y + l2_y * s_x
    del l2_x, l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    e11 = rest_length - s_len
    e12 = -e11 * stiffness
    e16 = e11 * stiffness
    s_inv = 1 / np.where(s_len > 0, s_len, np.inf)
    del s_len
    e8 = s_inv * s_x
    e13 = s_inv * s_y
    e15 = s_inv * (-l1_x * s_y + l1_y * s_x)
    del l1_x, l1_y
    s_x_t = l1_x_t - l2_x_t + vx1 - vx2
    del l1_x_t, l2_x_t
    s_y_t = l1_y_t - l2_y_t + vy1 - vy2
    del l1_y_t, l2_y_t
    s_rate = s_inv * (s_x * s_x_t + s_y * s_y_t)
    del s_x, s_x_t, s_y, s_y_t
    e9 = damping * s_rate
    del s_rate
    e10 = e8 * e9
    e14 = e13 * e9
    return (
        -e10 - e12 * e8,
        -e12 * e13 - e14,
        -e15 * e16 + e15 * e9,
        e10 - e16 * e8,
        -e13 * e16 + e14,
        e11 * e17 * s_inv * stiffness - e17 * e9 * s_inv,
    )


def force_static2(
    *, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, px1, py1, px2, py2, rest_length, stiffness, damping
):
    """Q = -dV/dq - dR/dq' on body 1 with body 2 at rest (the world, or a fixed body).

    V = stiffness/2 (|s| - rest_length)^2,  s = p1 - p2 = X1 + R(th1) a1 - X2 - R(th2) a2,  R = damping/2 (d|s|/dt)^2  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns fx1, fy1, tau1.
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
    del dx, l2_x
    s_y = dy + l1_y - l2_y
    del dy, l2_y
    s_len = np.sqrt(s_x * s_x + s_y * s_y)
    e8 = rest_length - s_len
    e9 = -e8 * stiffness
    s_inv = 1 / np.where(s_len > 0, s_len, np.inf)
    del s_len
    e6 = s_inv * s_x
    e10 = s_inv * s_y
    e11 = s_inv * (-l1_x * s_y + l1_y * s_x)
    del l1_x, l1_y
    s_x_t = l1_x_t + vx1
    del l1_x_t
    s_y_t = l1_y_t + vy1
    del l1_y_t
    s_rate = s_inv * (s_x * s_x_t + s_y * s_y_t)
    del s_inv, s_x, s_x_t, s_y, s_y_t
    e7 = damping * s_rate
    del s_rate
    return -e6 * e7 - e6 * e9, -e10 * e7 - e10 * e9, e11 * e7 - e11 * e8 * stiffness


def potential(*, x1, y1, th1, x2, y2, th2, px1, py1, px2, py2, rest_length, stiffness):
    """Potential energy V (J): run.energy adds it.

    V = stiffness/2 (|s| - rest_length)^2,  s = p1 - p2 = X1 + R(th1) a1 - X2 - R(th2) a2
    Returns V.
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
    return (1 / 2) * stiffness * (-rest_length + s_len) * (-rest_length + s_len)
