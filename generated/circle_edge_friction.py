"""Circular edge on straight edge (`circle_edge_friction`): generated tangential (friction) kernels. DO NOT EDIT.

Written by `regenerate-equations` from derive/friction.py through
templates/friction_module.py.j2; `regenerate-equations --check` fails when this file is stale.
Derivation: docs/derivations.pdf, section "Tangential (friction) rows".

t = n turned by +90 degrees = (-n_y, n_x), n the normal of generated/circle_edge.py (body 2 ->
body 1). The contact points are material points on the common normal, equal at a contact (d = 0):
p1 = c1 - r1 n, the point of body 1's circle nearest the edge's line; p2 = p1 - d n, the foot of
the perpendicular from c1 on that line.
v_t = (u1(p1) - u2(p2)) . t with u_i the velocity of body i's material point there.
Arguments and geometry columns are those of generated/circle_edge.py.

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
        "th1",
        "vx1",
        "vy1",
        "w1",
        "th2",
        "vx2",
        "vy2",
        "w2",
        "cx1",
        "cy1",
        "r1",
        "ex2",
        "ey2",
        "nx2",
        "ny2",
    ),
    "tangent_acceleration": (
        "th1",
        "vx1",
        "vy1",
        "w1",
        "ax1",
        "ay1",
        "al1",
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
        "ex2",
        "ey2",
        "nx2",
        "ny2",
    ),
    "tangent_jacobian": ("th1", "th2", "cx1", "cy1", "r1", "ex2", "ey2", "nx2", "ny2"),
    "tangent_bias": (
        "th1",
        "vx1",
        "vy1",
        "w1",
        "th2",
        "vx2",
        "vy2",
        "w2",
        "cx1",
        "cy1",
        "ex2",
        "ey2",
        "nx2",
        "ny2",
    ),
    "tangent_velocity_static2": (
        "th1",
        "vx1",
        "vy1",
        "w1",
        "th2",
        "cx1",
        "cy1",
        "r1",
        "nx2",
        "ny2",
    ),
    "tangent_acceleration_static2": (
        "th1",
        "w1",
        "ax1",
        "ay1",
        "al1",
        "th2",
        "cx1",
        "cy1",
        "r1",
        "nx2",
        "ny2",
    ),
    "tangent_jacobian_static2": ("th1", "th2", "cx1", "cy1", "r1", "nx2", "ny2"),
    "tangent_bias_static2": ("th1", "w1", "th2", "cx1", "cy1", "nx2", "ny2"),
}


def tangent_velocity(*, th1, vx1, vy1, w1, th2, vx2, vy2, w2, cx1, cy1, r1, ex2, ey2, nx2, ny2):
    """Tangential relative velocity v_t of the contact points (exact, any state).

    v_t = t.(V1 - V2) + w1 l1 - w2 l2,  t = (-n_y, n_x),  l_i = (p_i - X_i).n
    Returns vt.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    l1_x = cx1 * e0 - cy1 * e1
    l1_y = cx1 * e1 + cy1 * e0
    del e0, e1
    l2_x = e2 * ex2 - e3 * ey2
    l2_y = e2 * ey2 + e3 * ex2
    n_x = e2 * nx2 - e3 * ny2
    n_y = e2 * ny2 + e3 * nx2
    del e2, e3
    return (
        n_x * (vy1 - vy2)
        - n_y * (vx1 - vx2)
        + w1 * (l1_x * n_x + l1_y * n_y - r1)
        - w2 * (l2_x * n_x + l2_y * n_y)
    )


def tangent_acceleration(
    *,
    th1,
    vx1,
    vy1,
    w1,
    ax1,
    ay1,
    al1,
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
    ex2,
    ey2,
    nx2,
    ny2,
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
    e6 = e4 * ex2 - e5 * ey2
    e7 = e4 * ey2 + e5 * ex2
    e8 = e4 * nx2 - e5 * ny2
    e9 = e4 * ny2 + e5 * nx2
    del e4, e5
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
    n_x = e8
    n_y = e9
    n_x_t = -e9 * w2
    del e9
    n_y_t = e8 * w2
    del e8
    return (
        al1 * (l1_x * n_x + l1_y * n_y - r1)
        - al2 * (l2_x * n_x + l2_y * n_y)
        + n_x * (ay1 - ay2)
        + n_x_t * (vy1 - vy2)
        - n_y * (ax1 - ax2)
        - n_y_t * (vx1 - vx2)
        + w1 * (l1_x * n_x_t + l1_x_t * n_x + l1_y * n_y_t + l1_y_t * n_y)
        - w2 * (l2_x * n_x_t + l2_x_t * n_x + l2_y * n_y_t + l2_y_t * n_y)
    )


def tangent_jacobian(*, th1, th2, cx1, cy1, r1, ex2, ey2, nx2, ny2):
    """Tangential Jacobian row J_t: v_t = J_t . velocities, the A-matrix row of friction.

    (t_x, t_y, l1, -t_x, -t_y, -l2) = d v_t / d(vx1, vy1, w1, vx2, vy2, w2) = the coefficients of the accelerations in d/dt v_t
    Returns j1x, j1y, j1th, j2x, j2y, j2th.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    l1_x = cx1 * e0 - cy1 * e1
    l1_y = cx1 * e1 + cy1 * e0
    del e0, e1
    l2_x = e2 * ex2 - e3 * ey2
    l2_y = e2 * ey2 + e3 * ex2
    n_x = e2 * nx2 - e3 * ny2
    n_y = e2 * ny2 + e3 * nx2
    del e2, e3
    return -n_y, n_x, l1_x * n_x + l1_y * n_y - r1, n_y, -n_x, -l2_x * n_x - l2_y * n_y


def tangent_bias(*, th1, vx1, vy1, w1, th2, vx2, vy2, w2, cx1, cy1, ex2, ey2, nx2, ny2):
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
    e6 = e4 * ex2 - e5 * ey2
    e7 = e4 * ey2 + e5 * ex2
    e8 = e4 * nx2 - e5 * ny2
    e9 = e4 * ny2 + e5 * nx2
    del e4, e5
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
    n_x = e8
    n_y = e9
    n_x_t = -e9 * w2
    del e9
    n_y_t = e8 * w2
    del e8
    return (
        n_x_t * (vy1 - vy2)
        - n_y_t * (vx1 - vx2)
        + w1 * (l1_x * n_x_t + l1_x_t * n_x + l1_y * n_y_t + l1_y_t * n_y)
        - w2 * (l2_x * n_x_t + l2_x_t * n_x + l2_y * n_y_t + l2_y_t * n_y)
    )


def tangent_velocity_static2(*, th1, vx1, vy1, w1, th2, cx1, cy1, r1, nx2, ny2):
    """Tangential relative velocity v_t of the contact points (exact, any state).

    v_t = t.(V1 - V2) + w1 l1 - w2 l2,  t = (-n_y, n_x),  l_i = (p_i - X_i).n  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns vt.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    l1_x = cx1 * e0 - cy1 * e1
    l1_y = cx1 * e1 + cy1 * e0
    del e0, e1
    n_x = e2 * nx2 - e3 * ny2
    n_y = e2 * ny2 + e3 * nx2
    del e2, e3
    return n_x * vy1 - n_y * vx1 + w1 * (l1_x * n_x + l1_y * n_y - r1)


def tangent_acceleration_static2(*, th1, w1, ax1, ay1, al1, th2, cx1, cy1, r1, nx2, ny2):
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
    l1_x = e2
    l1_y = e3
    l1_x_t = -e3 * w1
    del e3
    l1_y_t = e2 * w1
    del e2
    n_x = e4 * nx2 - e5 * ny2
    n_y = e4 * ny2 + e5 * nx2
    del e4, e5
    return (
        al1 * (l1_x * n_x + l1_y * n_y - r1)
        - ax1 * n_y
        + ay1 * n_x
        + w1 * (l1_x_t * n_x + l1_y_t * n_y)
    )


def tangent_jacobian_static2(*, th1, th2, cx1, cy1, r1, nx2, ny2):
    """Tangential Jacobian row J_t: v_t = J_t . velocities, the A-matrix row of friction.

    (t_x, t_y, l1, -t_x, -t_y, -l2) = d v_t / d(vx1, vy1, w1, vx2, vy2, w2) = the coefficients of the accelerations in d/dt v_t  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns j1x, j1y, j1th.
    """
    e0 = np.cos(th1)
    e1 = np.sin(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    l1_x = cx1 * e0 - cy1 * e1
    l1_y = cx1 * e1 + cy1 * e0
    del e0, e1
    n_x = e2 * nx2 - e3 * ny2
    n_y = e2 * ny2 + e3 * nx2
    del e2, e3
    return -n_y, n_x, l1_x * n_x + l1_y * n_y - r1


def tangent_bias_static2(*, th1, w1, th2, cx1, cy1, nx2, ny2):
    """Velocity-dependent part of d/dt v_t: the b-vector term of friction.

    d/dt v_t = t'.(V1 - V2) + t.(A1 - A2) + al1 l1 + w1 l1' - al2 l2 - w2 l2'  with every acceleration zero  [body 2 fixed: v2 = w2 = a2 = al2 = 0]
    Returns bt.
    """
    e0 = np.sin(th1)
    e1 = np.cos(th1)
    e2 = np.cos(th2)
    e3 = np.sin(th2)
    l1_x_t = w1 * (-cx1 * e0 - cy1 * e1)
    l1_y_t = w1 * (cx1 * e1 - cy1 * e0)
    del e0, e1
    n_x = e2 * nx2 - e3 * ny2
    n_y = e2 * ny2 + e3 * nx2
    del e2, e3
    return w1 * (l1_x_t * n_x + l1_y_t * n_y)
