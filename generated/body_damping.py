"""Linear and angular damping of a body (`body_damping`): generated NumPy applied-force kernels. DO NOT EDIT.

Written by `regenerate-equations` from derive/applied.py through
templates/applied_module.py.j2; `regenerate-equations --check` fails when this file is stale.
Derivation: docs/derivations.pdf, section "Applied forces".

V = 0,  R = (k_lin m1 (vx1^2 + vy1^2) + k_ang i1 w1^2)/2:
the generalized forces Q = -dV/dq - dR/dq' on (x1, y1, th1), by SymPy: the force and
torque on each body (body coordinates: origin at the centre of mass), which the runtime adds to
the free accelerations as Q / m and Q / I at every stage; `potential` (if there is one) is what
run.energy adds. One body (k_lin, k_ang in 1/s): v(t) = v0 exp(-k_lin t) when nothing else acts.
Every function takes keyword arguments only and broadcasts over NumPy arrays (or plain floats);
ARGUMENTS lists each function's arguments in order.
"""

ARGUMENTS = {
    "force": ("vx1", "vy1", "w1", "m1", "i1", "k_lin", "k_ang"),
}


def force(*, vx1, vy1, w1, m1, i1, k_lin, k_ang):
    """Generalized forces Q = -dV/dq - dR/dq': force and torque on each body (N, N m).

    V = 0,  R = (k_lin m1 (vx1^2 + vy1^2) + k_ang i1 w1^2)/2
    Returns fx1, fy1, tau1.
    """
    e0 = k_lin * m1
    return -e0 * vx1, -e0 * vy1, -i1 * k_ang * w1
