"""Vertex on straight edge (`vertex_edge`): generated NumPy contact kernels. DO NOT EDIT.

Written by `regenerate-equations` from derive/ through
templates/kernel_module.py.j2; `regenerate-equations --check` fails when this file is stale.
Derivation: docs/derivations.pdf, section "Vertex on straight edge" (note eq. (1)-(4)).

Body 1: vertex p1 = (px1, py1).
Body 2: straight edge through e2 = (ex2, ey2) with outward unit normal (nx2, ny2); body 2 owns the normal n (body 2 -> body 1).
Every function takes keyword arguments only and broadcasts over NumPy arrays (or plain floats);
ARGUMENTS lists each function's arguments in order.

Design: the runtime assembles A = J M^-1 J^T from the `jacobian` rows (6 numbers per contact) and
b = J M^-1 F_ext + bias. Generating rows, not A entries per pair of contacts, keeps the kernels
O(contacts) and leaves the O(contacts^2) product to one dense matrix multiply, which NumPy does
faster than any per-pair generated expression; A is symmetric by construction.
"""

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


def gap(*, x1, y1, th1, x2, y2, th2, px1, py1, ex2, ey2, nx2, ny2):
    """Gap d (> 0 separated).

    d = n . (p1 - e2),  n = R(th2) (nx2, ny2)
    Returns d.
    """
    e0 = np.cos(th2)
    e1 = np.sin(th2)
    e2 = np.cos(th1)
    e3 = np.sin(th1)
    dx = x1 - x2
    dy = y1 - y2
    n_x = e0 * nx2 - e1 * ny2
    n_y = e0 * ny2 + e1 * nx2
    v_x = dx - e0 * ex2 + e1 * ey2 + e2 * px1 - e3 * py1
    del dx
    v_y = dy - e0 * ey2 - e1 * ex2 + e2 * py1 + e3 * px1
    del dy, e0, e1, e2, e3
    return n_x * v_x + n_y * v_y


def gap_velocity(
    *, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, px1, py1, ex2, ey2, nx2, ny2
):
    """Exact d' for any state.

    d' = n' . (p1 - e2) + n . (p1' - e2')
    Returns d1.
    """
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
    del e0
    e10 = e5 * py1 + e6 * px1
    del e5, e6
    dx = x1 - x2
    dy = y1 - y2
    n_x = e2
    n_y = e3
    n_x_t = -e3 * w2
    del e3
    n_y_t = e2 * w2
    del e2
    v_x = dx + e1 * ey2 - e4 + e7
    del dx
    v_y = dy + e10 - e8 - e9
    del dy
    v_x_t = -e10 * w1 + vx1 - vx2 + w2 * (e8 + e9)
    del e10, e8, e9
    v_y_t = e7 * w1 + vy1 - vy2 + w2 * (e1 * ey2 - e4)
    del e1, e4, e7
    return n_x * v_x_t + n_x_t * v_x + n_y * v_y_t + n_y_t * v_y


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
    ex2,
    ey2,
    nx2,
    ny2,
):
    """Exact d'' for any state.

    d'' = n'' . (p1 - e2) + 2 n' . (p1' - e2') + n . (p1'' - e2'')
    Returns d2.
    """
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
    del e0
    e12 = e7 * py1 + e8 * px1
    del e7, e8
    e13 = e10 + e11
    e14 = -e12
    e15 = -e1 * ey2 + e6
    e16 = -e15
    e17 = w1 * w1
    dx = x1 - x2
    dy = y1 - y2
    n_x = e2
    n_y = e3
    del e3
    n_x_t = e4 * w2
    n_y_t = e2 * w2
    n_x_tt = al2 * e4 - e2 * e5
    n_y_tt = al2 * e2 + e4 * e5
    del e2, e4
    v_x = dx + e1 * ey2 - e6 + e9
    del dx, e1, e6
    v_y = dy - e10 - e11 + e12
    del dy, e10, e11, e12
    v_x_t = e13 * w2 + e14 * w1 + vx1 - vx2
    v_y_t = e16 * w2 + e9 * w1 + vy1 - vy2
    v_x_tt = al1 * e14 + al2 * e13 + ax1 - ax2 + e15 * e5 - e17 * e9
    del e15
    v_y_tt = al1 * e9 + al2 * e16 + ay1 - ay2 + e13 * e5 + e14 * e17
    del e13, e14, e16, e17, e5, e9
    return (
        n_x * v_x_tt
        + 2 * n_x_t * v_x_t
        + n_x_tt * v_x
        + n_y * v_y_tt
        + 2 * n_y_t * v_y_t
        + n_y_tt * v_y
    )


def jacobian(*, x1, y1, th1, x2, y2, th2, px1, py1, ex2, ey2, nx2, ny2):
    """Jacobian row of the gap: the A-matrix lever terms.

    (dd/dx1, dd/dy1, dd/dth1, dd/dx2, dd/dy2, dd/dth2) = the coefficients of the accelerations in d''; body 1: (n, R1 x n), body 2: -(n, R2 x n)
    Returns j1x, j1y, j1th, j2x, j2y, j2th.
    """
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
    del e1
    e10 = e0 * ey2
    del e0
    e11 = e6 * py1 + e7 * px1
    del e6, e7
    dx = x1 - x2
    dy = y1 - y2
    n_x = e2
    n_y = e3
    v_x = dx + e4 - e5 + e8
    del dx
    v_y = dy - e10 + e11 - e9
    del dy
    return (
        n_x,
        n_y,
        -e11 * n_x + e8 * n_y,
        -n_x,
        -n_y,
        e2 * v_y - e3 * v_x + n_x * (e10 + e9) - n_y * (-e4 + e5),
    )


def bias(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, px1, py1, ex2, ey2, nx2, ny2):
    """Velocity-dependent part of d'': the b-vector term.

    d'' = n'' . (p1 - e2) + 2 n' . (p1' - e2') + n . (p1'' - e2'')  with ax1 = ay1 = al1 = ax2 = ay2 = al2 = 0
    Returns b.
    """
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
    del e0
    e12 = e7 * py1 + e8 * px1
    del e7, e8
    e13 = e10 + e11
    e14 = -e12
    e15 = -e1 * ey2 + e6
    e16 = w1 * w1
    dx = x1 - x2
    dy = y1 - y2
    n_x = e2
    n_y = e3
    del e3
    n_x_t = e4 * w2
    n_y_t = e2 * w2
    n_x_tt = -e2 * e5
    del e2
    n_y_tt = e4 * e5
    del e4
    v_x = dx + e1 * ey2 - e6 + e9
    del dx, e1, e6
    v_y = dy - e10 - e11 + e12
    del dy, e10, e11, e12
    v_x_t = e13 * w2 + e14 * w1 + vx1 - vx2
    v_y_t = -e15 * w2 + e9 * w1 + vy1 - vy2
    v_x_tt = e15 * e5 - e16 * e9
    del e15, e9
    v_y_tt = e13 * e5 + e14 * e16
    del e13, e14, e16, e5
    return (
        n_x * v_x_tt
        + 2 * n_x_t * v_x_t
        + n_x_tt * v_x
        + n_y * v_y_tt
        + 2 * n_y_t * v_y_t
        + n_y_tt * v_y
    )


def gap_velocity_static2(*, th1, vx1, vy1, w1, th2, px1, py1, nx2, ny2):
    """Exact d' with body 2 fixed.

    d' = n' . (p1 - e2) + n . (p1' - e2')  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns d1.
    """
    e0 = np.cos(th2)
    e1 = np.sin(th2)
    e2 = np.sin(th1)
    e3 = np.cos(th1)
    n_x = e0 * nx2 - e1 * ny2
    n_y = e0 * ny2 + e1 * nx2
    del e0, e1
    v_x_t = vx1 + w1 * (-e2 * px1 - e3 * py1)
    v_y_t = vy1 + w1 * (-e2 * py1 + e3 * px1)
    del e2, e3
    return n_x * v_x_t + n_y * v_y_t


def gap_acceleration_static2(*, th1, w1, ax1, ay1, al1, th2, px1, py1, nx2, ny2):
    """Exact d'' with body 2 fixed.

    d'' = n'' . (p1 - e2) + 2 n' . (p1' - e2') + n . (p1'' - e2'')  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns d2.
    """
    e0 = np.cos(th2)
    e1 = np.sin(th2)
    e2 = np.sin(th1)
    e3 = np.cos(th1)
    e4 = -e2 * px1 - e3 * py1
    e5 = w1 * w1
    e6 = -e2 * py1 + e3 * px1
    del e2, e3
    n_x = e0 * nx2 - e1 * ny2
    n_y = e0 * ny2 + e1 * nx2
    del e0, e1
    v_x_tt = al1 * e4 + ax1 - e5 * e6
    v_y_tt = al1 * e6 + ay1 + e4 * e5
    del e4, e5, e6
    return n_x * v_x_tt + n_y * v_y_tt


def jacobian_static2(*, th1, th2, px1, py1, nx2, ny2):
    """Body-1 Jacobian row with body 2 fixed.

    (dd/dx1, dd/dy1, dd/dth1) = (n, R1 x n)
    Returns j1x, j1y, j1th.
    """
    e0 = np.cos(th2)
    e1 = np.sin(th2)
    e2 = np.sin(th1)
    e3 = np.cos(th1)
    n_x = e0 * nx2 - e1 * ny2
    n_y = e0 * ny2 + e1 * nx2
    del e0, e1
    return n_x, n_y, -n_x * (e2 * px1 + e3 * py1) + n_y * (-e2 * py1 + e3 * px1)


def bias_static2(*, th1, w1, th2, px1, py1, nx2, ny2):
    """b-vector term with body 2 fixed.

    d'' = n'' . (p1 - e2) + 2 n' . (p1' - e2') + n . (p1'' - e2'')  with ax1 = ay1 = al1 = ax2 = ay2 = al2 = 0  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns b.
    """
    e0 = np.cos(th2)
    e1 = np.sin(th2)
    e2 = w1 * w1
    e3 = np.cos(th1)
    e4 = np.sin(th1)
    n_x = e0 * nx2 - e1 * ny2
    n_y = e0 * ny2 + e1 * nx2
    del e0, e1
    v_x_tt = e2 * (-e3 * px1 + e4 * py1)
    v_y_tt = e2 * (-e3 * py1 - e4 * px1)
    del e2, e3, e4
    return n_x * v_x_tt + n_y * v_y_tt
