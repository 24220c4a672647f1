"""Mutual gravitation (`mutual_gravity`): generated NumPy applied-force kernels. DO NOT EDIT.

Written by `regenerate-equations` from derive/applied.py through
templates/applied_module.py.j2; `regenerate-equations --check` fails when this file is stale.
Derivation: docs/derivations.pdf, section "Applied forces".

V = -G m1 m2 / r,  r = |X1 - X2|,  R = 0:
the generalized forces Q = -dV/dq - dR/dq' on (x1, y1, th1, x2, y2, th2), by SymPy: the force and
torque on each body (body coordinates: origin at the centre of mass), which the runtime adds to
the free accelerations as Q / m and Q / I at every stage; `potential` (if there is one) is what
run.energy adds. One pair of bodies: the runtime sums it over every pair of moving bodies.
Every function takes keyword arguments only and broadcasts over NumPy arrays (or plain floats);
ARGUMENTS lists each function's arguments in order.
"""

import numpy as np

ARGUMENTS = {
    "force": ("x1", "y1", "x2", "y2", "G", "m1", "m2"),
    "potential": ("x1", "y1", "x2", "y2", "G", "m1", "m2"),
}


def force(*, x1, y1, x2, y2, G, m1, m2):
    """Generalized forces Q = -dV/dq - dR/dq': force and torque on each body (N, N m).

    V = -G m1 m2 / r,  r = |X1 - X2|,  R = 0
    Returns fx1, fy1, tau1, fx2, fy2, tau2.
    """
    dx = x1 - x2
    dy = y1 - y2
    r = np.sqrt(dx * dx + dy * dy)
    e0 = G * m1 * m2 / (r * r * r)
    del r
    e1 = dx * e0
    del dx
    e2 = dy * e0
    del dy, e0
    return -e1, -e2, 0.0, e1, e2, 0.0


def potential(*, x1, y1, x2, y2, G, m1, m2):
    """Potential energy V (J): run.energy adds it.

    V = -G m1 m2 / r,  r = |X1 - X2|
    Returns V.
    """
    dx = x1 - x2
    dy = y1 - y2
    r = np.sqrt(dx * dx + dy * dy)
    del dx, dy
    return -G * m1 * m2 / r
