"""Vertex on circular edge (`vertex_circle`): generated NumPy contact kernels. DO NOT EDIT.

Written by `regenerate-equations` from derive/ through
templates/kernel_module.py.j2; `regenerate-equations --check` fails when this file is stale.
Derivation: docs/derivations.pdf, section "Vertex on circular edge" (note eq. (5)-(8)).

Body 1: vertex p1 = (px1, py1).
Body 2: circular edge with centre c2 = (cx2, cy2) and signed radius r2; body 2 owns the normal n (body 2 -> body 1).
Every function takes keyword arguments only and broadcasts over NumPy arrays (or plain floats);
ARGUMENTS lists each function's arguments in order.

Design: the runtime assembles A = J M^-1 J^T from the `jacobian` rows (6 numbers per contact) and
b = J M^-1 F_ext + bias. Generating rows, not A entries per pair of contacts, keeps the kernels
O(contacts) and leaves the O(contacts^2) product to one dense matrix multiply, which NumPy does
faster than any per-pair generated expression; A is symmetric by construction.
"""

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


def gap(*, x1, y1, th1, x2, y2, th2, px1, py1, cx2, cy2, r2):
    """Gap d (> 0 separated).

    d = sigma |v| - r2,  v = p1 - c2,  sigma = sign(r2)
    Returns d.
    """
    e0 = np.sin(th2)
    e1 = np.cos(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th1)
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = -cx2 * e2 + cy2 * e0 + dx + e1 * px1 - e3 * py1
    del dx
    v_y = -cx2 * e0 - cy2 * e2 + dy + e1 * py1 + e3 * px1
    del dy, e0, e1, e2, e3
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    del v_x, v_y
    return -r2 + sg2 * v_len


def gap_velocity(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, px1, py1, cx2, cy2, r2):
    """Exact d' for any state.

    d' = n . v',  n = sigma v/|v|
    Returns d1.
    """
    e0 = np.sin(th2)
    e1 = np.cos(th2)
    e2 = cx2 * e1
    e3 = np.cos(th1)
    e4 = np.sin(th1)
    e5 = e3 * px1 - e4 * py1
    e6 = cx2 * e0
    e7 = cy2 * e1
    del e1
    e8 = e3 * py1 + e4 * px1
    del e3, e4
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = cy2 * e0 + dx - e2 + e5
    del dx
    v_y = dy - e6 - e7 + e8
    del dy
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    v_x_t = -e8 * w1 + vx1 - vx2 + w2 * (e6 + e7)
    del e6, e7, e8
    v_y_t = e5 * w1 + vy1 - vy2 + w2 * (cy2 * e0 - e2)
    del e0, e2, e5
    return sg2 * (v_x * v_x_t + v_y * v_y_t) / v_len


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
    cx2,
    cy2,
    r2,
):
    """Exact d'' for any state.

    d'' = n . v'' + sigma v_tan^2 / |v|,  v_tan = (v x v') / |v|   (= n' . v' + n . v'')
    Returns d2.
    """
    e0 = np.sin(th2)
    e1 = np.cos(th2)
    e2 = cx2 * e1
    e3 = np.cos(th1)
    e4 = np.sin(th1)
    e5 = e3 * px1 - e4 * py1
    e6 = cx2 * e0
    e7 = cy2 * e1
    del e1
    e8 = e3 * py1 + e4 * px1
    del e3, e4
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
    del dx, e0, e2
    v_y = dy - e6 - e7 + e8
    del dy, e6, e7, e8
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e13 = 1 / v_len
    del v_len
    v_x_t = e10 * w1 + e9 * w2 + vx1 - vx2
    v_y_t = e12 * w2 + e5 * w1 + vy1 - vy2
    v_tan = e13 * (v_x * v_y_t - v_x_t * v_y)
    del v_x_t, v_y_t
    v_x_tt = al1 * e10 + al2 * e9 + ax1 - ax2 + e11 * e15 - e14 * e5
    del e11
    v_y_tt = al1 * e5 + al2 * e12 + ay1 - ay2 + e10 * e14 + e15 * e9
    del e10, e12, e14, e15, e5, e9
    return sg2 * (e13 * v_tan * v_tan + e13 * (v_x * v_x_tt + v_y * v_y_tt))


def jacobian(*, x1, y1, th1, x2, y2, th2, px1, py1, cx2, cy2, r2):
    """Jacobian row of the gap: the A-matrix lever terms.

    (dd/dx1, dd/dy1, dd/dth1, dd/dx2, dd/dy2, dd/dth2) = the coefficients of the accelerations in d''; body 1: (n, R1 x n), body 2: -(n, U2 x n)
    Returns j1x, j1y, j1th, j2x, j2y, j2th.
    """
    e0 = np.sin(th2)
    e1 = cy2 * e0
    e2 = np.cos(th2)
    e3 = cx2 * e2
    e4 = np.cos(th1)
    e5 = np.sin(th1)
    e6 = e4 * px1 - e5 * py1
    e7 = cx2 * e0
    del e0
    e8 = cy2 * e2
    del e2
    e9 = e4 * py1 + e5 * px1
    del e4, e5
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = dx + e1 - e3 + e6
    del dx
    v_y = dy - e7 - e8 + e9
    del dy
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e10 = sg2 / v_len
    del sg2, v_len
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


def bias(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, px1, py1, cx2, cy2, r2):
    """Velocity-dependent part of d'': the b-vector term.

    d'' = n . v'' + sigma v_tan^2 / |v|,  v_tan = (v x v') / |v|   (= n' . v' + n . v'')  with ax1 = ay1 = al1 = ax2 = ay2 = al2 = 0
    Returns b.
    """
    e0 = np.sin(th2)
    e1 = np.cos(th2)
    e2 = cx2 * e1
    e3 = np.cos(th1)
    e4 = np.sin(th1)
    e5 = e3 * px1 - e4 * py1
    e6 = cx2 * e0
    e7 = cy2 * e1
    del e1
    e8 = e3 * py1 + e4 * px1
    del e3, e4
    e9 = e6 + e7
    e10 = -e8
    e11 = -cy2 * e0 + e2
    e13 = w1 * w1
    e14 = w2 * w2
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = cy2 * e0 + dx - e2 + e5
    del dx, e0, e2
    v_y = dy - e6 - e7 + e8
    del dy, e6, e7, e8
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e12 = 1 / v_len
    del v_len
    v_x_t = e10 * w1 + e9 * w2 + vx1 - vx2
    v_y_t = -e11 * w2 + e5 * w1 + vy1 - vy2
    v_tan = e12 * (v_x * v_y_t - v_x_t * v_y)
    del v_x_t, v_y_t
    v_x_tt = e11 * e14 - e13 * e5
    del e11, e5
    v_y_tt = e10 * e13 + e14 * e9
    del e10, e13, e14, e9
    return sg2 * (e12 * v_tan * v_tan + e12 * (v_x * v_x_tt + v_y * v_y_tt))


def gap_velocity_static2(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, px1, py1, cx2, cy2, r2):
    """Exact d' with body 2 fixed.

    d' = n . v',  n = sigma v/|v|  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns d1.
    """
    e0 = np.sin(th2)
    e1 = np.cos(th2)
    e2 = np.cos(th1)
    e3 = np.sin(th1)
    e4 = e2 * px1 - e3 * py1
    e5 = e2 * py1 + e3 * px1
    del e2, e3
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = -cx2 * e1 + cy2 * e0 + dx + e4
    del dx
    v_y = -cx2 * e0 - cy2 * e1 + dy + e5
    del dy, e0, e1
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    v_x_t = -e5 * w1 + vx1
    del e5
    v_y_t = e4 * w1 + vy1
    del e4
    return sg2 * (v_x * v_x_t + v_y * v_y_t) / v_len


def gap_acceleration_static2(
    *, x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1, x2, y2, th2, px1, py1, cx2, cy2, r2
):
    """Exact d'' with body 2 fixed.

    d'' = n . v'' + sigma v_tan^2 / |v|,  v_tan = (v x v') / |v|   (= n' . v' + n . v'')  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns d2.
    """
    e0 = np.sin(th2)
    e1 = np.cos(th2)
    e2 = np.cos(th1)
    e3 = np.sin(th1)
    e4 = e2 * px1 - e3 * py1
    e5 = e2 * py1 + e3 * px1
    del e2, e3
    e6 = -e5
    e8 = w1 * w1
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = -cx2 * e1 + cy2 * e0 + dx + e4
    del dx
    v_y = -cx2 * e0 - cy2 * e1 + dy + e5
    del dy, e0, e1, e5
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e7 = 1 / v_len
    del v_len
    v_x_t = e6 * w1 + vx1
    v_y_t = e4 * w1 + vy1
    v_tan = e7 * (v_x * v_y_t - v_x_t * v_y)
    del v_x_t, v_y_t
    v_x_tt = al1 * e6 + ax1 - e4 * e8
    v_y_tt = al1 * e4 + ay1 + e6 * e8
    del e4, e6, e8
    return sg2 * (e7 * v_tan * v_tan + e7 * (v_x * v_x_tt + v_y * v_y_tt))


def jacobian_static2(*, x1, y1, th1, x2, y2, th2, px1, py1, cx2, cy2, r2):
    """Body-1 Jacobian row with body 2 fixed.

    (dd/dx1, dd/dy1, dd/dth1) = (n, R1 x n)
    Returns j1x, j1y, j1th.
    """
    e0 = np.sin(th2)
    e1 = np.cos(th2)
    e2 = np.cos(th1)
    e3 = np.sin(th1)
    e4 = e2 * px1 - e3 * py1
    e5 = e2 * py1 + e3 * px1
    del e2, e3
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = -cx2 * e1 + cy2 * e0 + dx + e4
    del dx
    v_y = -cx2 * e0 - cy2 * e1 + dy + e5
    del dy, e0, e1
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e6 = sg2 / v_len
    del sg2, v_len
    return e6 * v_x, e6 * v_y, e6 * (e4 * v_y - e5 * v_x)


def bias_static2(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, px1, py1, cx2, cy2, r2):
    """b-vector term with body 2 fixed.

    d'' = n . v'' + sigma v_tan^2 / |v|,  v_tan = (v x v') / |v|   (= n' . v' + n . v'')  with ax1 = ay1 = al1 = ax2 = ay2 = al2 = 0  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns b.
    """
    e0 = np.sin(th2)
    e1 = np.cos(th2)
    e2 = np.cos(th1)
    e3 = np.sin(th1)
    e4 = e2 * px1 - e3 * py1
    e5 = e2 * py1 + e3 * px1
    del e2, e3
    e6 = -e5
    e8 = w1 * w1
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    v_x = -cx2 * e1 + cy2 * e0 + dx + e4
    del dx
    v_y = -cx2 * e0 - cy2 * e1 + dy + e5
    del dy, e0, e1, e5
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e7 = 1 / v_len
    del v_len
    v_x_t = e6 * w1 + vx1
    v_y_t = e4 * w1 + vy1
    v_tan = e7 * (v_x * v_y_t - v_x_t * v_y)
    del v_x_t, v_y_t
    v_x_tt = -e4 * e8
    del e4
    v_y_tt = e6 * e8
    del e6, e8
    return sg2 * (e7 * v_tan * v_tan + e7 * (v_x * v_x_tt + v_y * v_y_tt))
