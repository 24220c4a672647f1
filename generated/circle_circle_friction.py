"""Circular edge on circular edge (`circle_circle_friction`): generated tangential (friction) kernels. DO NOT EDIT.

Written by `regenerate-equations` from derive/friction.py through
templates/friction_module.py.j2; `regenerate-equations --check` fails when this file is stale.
Derivation: docs/derivations.pdf, section "Tangential (friction) rows".

t = n turned by +90 degrees = (-n_y, n_x), n the normal of generated/circle_circle.py (body 2 ->
body 1). The contact points are material points on the common normal, equal at a contact (d = 0):
p1 = c1 - r1 n, the point of body 1's circle facing body 2; p2 = p1 - d n = c2 + r2 n, the point of
body 2's circular edge on the line of the centres.
v_t = (u1(p1) - u2(p2)) . t with u_i the velocity of body i's material point there.
Arguments and geometry columns are those of generated/circle_circle.py.

A friction force f_t t on body 1 at p1 (and -f_t t on body 2 at p2) enters like a normal force:
its row `tangent_jacobian` (v_t = J_t . velocities) goes beside the normal rows in A = J M^-1 J^T,
and d/dt v_t = J_t . accelerations + tangent_bias (sticking keeps it 0). v_t > 0: body 1's
contact point slides along +t relative to body 2's, so kinetic friction has f_t = -mu f_n.
A separate module from the normal kernels, so a scene with every friction coefficient 0 never
imports it.
"""

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


def tangent_velocity(
    *, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, cx1, cy1, r1, cx2, cy2, r2
):
    """Tangential relative velocity v_t of the contact points (exact, any state).

    v_t = t.(V1 - V2) + w1 l1 - w2 l2,  t = (-n_y, n_x),  l_i = (p_i - X_i).n
    Returns vt.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    l1_x = cx1 * e0 - cy1 * e1
    l1_y = cx1 * e1 + cy1 * e0
    del e0, e1
    l2_x = cx2 * e2 - cy2 * e3
    l2_y = cx2 * e3 + cy2 * e2
    del e2, e3
    v_x = dx + l1_x - l2_x
    del dx
    v_y = dy + l1_y - l2_y
    del dy
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e4 = sg2 / v_len
    del sg2, v_len
    n_x = e4 * v_x
    del v_x
    n_y = e4 * v_y
    del e4, v_y
    return (
        n_x * (vy1 - vy2)
        - n_y * (vx1 - vx2)
        + w1 * (l1_x * n_x + l1_y * n_y - r1)
        - w2 * (l2_x * n_x + l2_y * n_y + r2)
    )


def tangent_acceleration(
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
    cx1,
    cy1,
    r1,
    cx2,
    cy2,
    r2,
):
    """Exact d/dt v_t for any state.

    d/dt v_t = t'.(V1 - V2) + t.(A1 - A2) + al1 l1 + w1 l1' - al2 l2 - w2 l2'
    Returns at.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = cx1 * e0 - cy1 * e1
    e3 = cx1 * e1 + cy1 * e0
    del e0, e1
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    e6 = cx2 * e4 - cy2 * e5
    e7 = cx2 * e5 + cy2 * e4
    del e4, e5
    e8 = vx1 - vx2
    e9 = vy1 - vy2
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
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
    v_x = dx + l1_x - l2_x
    del dx
    v_y = dy + l1_y - l2_y
    del dy
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e10 = 1 / v_len
    del v_len
    e11 = e10 * sg2
    del sg2
    v_x_t = e8 + l1_x_t - l2_x_t
    v_y_t = e9 + l1_y_t - l2_y_t
    v_tan = e10 * (v_x * v_y_t - v_x_t * v_y)
    del v_x_t, v_y_t
    e12 = e10 * v_tan
    del e10, v_tan
    n_x = e11 * v_x
    del v_x
    n_y = e11 * v_y
    del e11, v_y
    n_x_t = -e12 * n_y
    n_y_t = e12 * n_x
    del e12
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


def tangent_jacobian(*, x1, y1, th1, x2, y2, th2, cx1, cy1, r1, cx2, cy2, r2):
    """Tangential Jacobian row J_t: v_t = J_t . velocities, the A-matrix row of friction.

    (t_x, t_y, l1, -t_x, -t_y, -l2) = d v_t / d(vx1, vy1, w1, vx2, vy2, w2) = the coefficients of the accelerations in d/dt v_t
    Returns j1x, j1y, j1th, j2x, j2y, j2th.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    l1_x = cx1 * e0 - cy1 * e1
    l1_y = cx1 * e1 + cy1 * e0
    del e0, e1
    l2_x = cx2 * e2 - cy2 * e3
    l2_y = cx2 * e3 + cy2 * e2
    del e2, e3
    v_x = dx + l1_x - l2_x
    del dx
    v_y = dy + l1_y - l2_y
    del dy
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e4 = sg2 / v_len
    del sg2, v_len
    n_x = e4 * v_x
    del v_x
    n_y = e4 * v_y
    del e4, v_y
    return -n_y, n_x, l1_x * n_x + l1_y * n_y - r1, n_y, -n_x, -l2_x * n_x - l2_y * n_y - r2


def tangent_bias(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, cx1, cy1, cx2, cy2, r2):
    """Velocity-dependent part of d/dt v_t: the b-vector term of friction.

    d/dt v_t = t'.(V1 - V2) + t.(A1 - A2) + al1 l1 + w1 l1' - al2 l2 - w2 l2'  with every acceleration zero
    Returns bt.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = cx1 * e0 - cy1 * e1
    e3 = cx1 * e1 + cy1 * e0
    del e0, e1
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    e6 = cx2 * e4 - cy2 * e5
    e7 = cx2 * e5 + cy2 * e4
    del e4, e5
    e8 = vx1 - vx2
    e9 = vy1 - vy2
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
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
    v_x = dx + l1_x - l2_x
    del dx
    v_y = dy + l1_y - l2_y
    del dy
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e10 = 1 / v_len
    del v_len
    e11 = e10 * sg2
    del sg2
    v_x_t = e8 + l1_x_t - l2_x_t
    v_y_t = e9 + l1_y_t - l2_y_t
    v_tan = e10 * (v_x * v_y_t - v_x_t * v_y)
    del v_x_t, v_y_t
    e12 = e10 * v_tan
    del e10, v_tan
    n_x = e11 * v_x
    del v_x
    n_y = e11 * v_y
    del e11, v_y
    n_x_t = -e12 * n_y
    n_y_t = e12 * n_x
    del e12
    return (
        -e8 * n_y_t
        + e9 * n_x_t
        + w1 * (l1_x * n_x_t + l1_x_t * n_x + l1_y * n_y_t + l1_y_t * n_y)
        - w2 * (l2_x * n_x_t + l2_x_t * n_x + l2_y * n_y_t + l2_y_t * n_y)
    )


def tangent_velocity_static2(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, cx1, cy1, r1, cx2, cy2, r2):
    """Tangential relative velocity v_t of the contact points (exact, any state).

    v_t = t.(V1 - V2) + w1 l1 - w2 l2,  t = (-n_y, n_x),  l_i = (p_i - X_i).n  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns vt.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    l1_x = cx1 * e0 - cy1 * e1
    l1_y = cx1 * e1 + cy1 * e0
    del e0, e1
    l2_x = cx2 * e2 - cy2 * e3
    l2_y = cx2 * e3 + cy2 * e2
    del e2, e3
    v_x = dx + l1_x - l2_x
    del dx, l2_x
    v_y = dy + l1_y - l2_y
    del dy, l2_y
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e4 = sg2 / v_len
    del sg2, v_len
    n_x = e4 * v_x
    del v_x
    n_y = e4 * v_y
    del e4, v_y
    return n_x * vy1 - n_y * vx1 + w1 * (l1_x * n_x + l1_y * n_y - r1)


def tangent_acceleration_static2(
    *, x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1, x2, y2, th2, cx1, cy1, r1, cx2, cy2, r2
):
    """Exact d/dt v_t for any state.

    d/dt v_t = t'.(V1 - V2) + t.(A1 - A2) + al1 l1 + w1 l1' - al2 l2 - w2 l2'  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns at.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = cx1 * e0 - cy1 * e1
    e3 = cx1 * e1 + cy1 * e0
    del e0, e1
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    l1_x = e2
    l1_y = e3
    l1_x_t = -e3 * w1
    del e3
    l1_y_t = e2 * w1
    del e2
    l2_x = cx2 * e4 - cy2 * e5
    l2_y = cx2 * e5 + cy2 * e4
    del e4, e5
    v_x = dx + l1_x - l2_x
    del dx, l2_x
    v_y = dy + l1_y - l2_y
    del dy, l2_y
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e6 = 1 / v_len
    del v_len
    e7 = e6 * sg2
    del sg2
    v_x_t = l1_x_t + vx1
    v_y_t = l1_y_t + vy1
    v_tan = e6 * (v_x * v_y_t - v_x_t * v_y)
    del v_x_t, v_y_t
    e8 = e6 * v_tan
    del e6, v_tan
    n_x = e7 * v_x
    del v_x
    n_y = e7 * v_y
    del e7, v_y
    n_x_t = -e8 * n_y
    n_y_t = e8 * n_x
    del e8
    return (
        al1 * (l1_x * n_x + l1_y * n_y - r1)
        - ax1 * n_y
        + ay1 * n_x
        + n_x_t * vy1
        - n_y_t * vx1
        + w1 * (l1_x * n_x_t + l1_x_t * n_x + l1_y * n_y_t + l1_y_t * n_y)
    )


def tangent_jacobian_static2(*, x1, y1, th1, x2, y2, th2, cx1, cy1, r1, cx2, cy2, r2):
    """Tangential Jacobian row J_t: v_t = J_t . velocities, the A-matrix row of friction.

    (t_x, t_y, l1, -t_x, -t_y, -l2) = d v_t / d(vx1, vy1, w1, vx2, vy2, w2) = the coefficients of the accelerations in d/dt v_t  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns j1x, j1y, j1th.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    l1_x = cx1 * e0 - cy1 * e1
    l1_y = cx1 * e1 + cy1 * e0
    del e0, e1
    l2_x = cx2 * e2 - cy2 * e3
    l2_y = cx2 * e3 + cy2 * e2
    del e2, e3
    v_x = dx + l1_x - l2_x
    del dx, l2_x
    v_y = dy + l1_y - l2_y
    del dy, l2_y
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e4 = sg2 / v_len
    del sg2, v_len
    n_x = e4 * v_x
    del v_x
    n_y = e4 * v_y
    del e4, v_y
    return -n_y, n_x, l1_x * n_x + l1_y * n_y - r1


def tangent_bias_static2(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, cx1, cy1, cx2, cy2, r2):
    """Velocity-dependent part of d/dt v_t: the b-vector term of friction.

    d/dt v_t = t'.(V1 - V2) + t.(A1 - A2) + al1 l1 + w1 l1' - al2 l2 - w2 l2'  with every acceleration zero  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns bt.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = cx1 * e0 - cy1 * e1
    e3 = cx1 * e1 + cy1 * e0
    del e0, e1
    e4 = np.cos(th2)
    e5 = np.sin(th2)
    dx = x1 - x2
    dy = y1 - y2
    sg2 = np.copysign(1.0, r2)
    l1_x = e2
    l1_y = e3
    l1_x_t = -e3 * w1
    del e3
    l1_y_t = e2 * w1
    del e2
    l2_x = cx2 * e4 - cy2 * e5
    l2_y = cx2 * e5 + cy2 * e4
    del e4, e5
    v_x = dx + l1_x - l2_x
    del dx, l2_x
    v_y = dy + l1_y - l2_y
    del dy, l2_y
    v_len = np.sqrt(v_x * v_x + v_y * v_y)
    e6 = 1 / v_len
    del v_len
    e7 = e6 * sg2
    del sg2
    v_x_t = l1_x_t + vx1
    v_y_t = l1_y_t + vy1
    v_tan = e6 * (v_x * v_y_t - v_x_t * v_y)
    del v_x_t, v_y_t
    e8 = e6 * v_tan
    del e6, v_tan
    n_x = e7 * v_x
    del v_x
    n_y = e7 * v_y
    del e7, v_y
    n_x_t = -e8 * n_y
    n_y_t = e8 * n_x
    del e8
    return (
        n_x_t * vy1 - n_y_t * vx1 + w1 * (l1_x * n_x_t + l1_x_t * n_x + l1_y * n_y_t + l1_y_t * n_y)
    )
