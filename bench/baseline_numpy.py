"""Hand-written NumPy contact kernels: the benchmark's baseline (b).

Written straight from the note's formulas the way a person would, without SymPy and without any
common-subexpression tricks: cos/sin once per body, world vectors and their time derivatives, then
the formula. Keyword arguments with the generated kernels' names (docs/conventions.md); the
benchmark passes each function the arguments its signature asks for.

  straight edge (body 2):  d = n . v - r1,        d' = n' . v + n . v',
                           d'' = n'' . v + 2 n' . v' + n . v'',   v = q1 - e2 (world), n = R(th2) n2
  circular edge (body 2):  d = sigma |v| - r2 - r1,  n = sigma v/|v|,  d' = n . v',
                           d'' = n' . v' + n . v'',  v = q1 - c2 (world)

q1 is body 1's vertex p1 or circle centre c1 (r1 = 0 for a vertex). Jacobian row: body 1
(n, R1 x n), body 2 -(n, R2 x n), with R1 = R(th1) q1 and R2 the lever from body 2's centre of mass.
"""

from __future__ import annotations

import numpy as np

# --- kinematics of a body-fixed point ------------------------------------------------------------


def _rotate(c, s, px, py):
    """R(th) p, given c = cos(th), s = sin(th)."""
    return c * px - s * py, s * px + c * py


def _point_velocity(vx, vy, w, rx, ry):
    """Velocity of the body point at lever r: V + w perp(r)."""
    return vx - w * ry, vy + w * rx


def _point_acceleration(ax, ay, al, w, rx, ry):
    """Acceleration of the body point at lever r: A + al perp(r) - w^2 r."""
    return ax - al * ry - w * w * rx, ay + al * rx - w * w * ry


def _centripetal(w, rx, ry):
    """Acceleration of the body point at lever r when A = al = 0: -w^2 r."""
    return -w * w * rx, -w * w * ry


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


# --- straight edge of body 2 (vertex_edge, circle_edge) ------------------------------------------


def _line_geometry(x1, y1, th1, x2, y2, th2, qx1, qy1, ex2, ey2, nx2, ny2):
    """World normal n, levers R1 = R(th1) q1 and E2 = R(th2) e2, and v = q1 - e2 in world."""
    c1, s1 = np.cos(th1), np.sin(th1)
    c2, s2 = np.cos(th2), np.sin(th2)
    n = _rotate(c2, s2, nx2, ny2)
    r1 = _rotate(c1, s1, qx1, qy1)
    e2 = _rotate(c2, s2, ex2, ey2)
    v = (x1 + r1[0] - x2 - e2[0], y1 + r1[1] - y2 - e2[1])
    return n, r1, e2, v


def _line_gap(x1, y1, th1, x2, y2, th2, qx1, qy1, ex2, ey2, nx2, ny2, offset):
    n, _, _, v = _line_geometry(x1, y1, th1, x2, y2, th2, qx1, qy1, ex2, ey2, nx2, ny2)
    return n[0] * v[0] + n[1] * v[1] - offset


def _line_gap_velocity(
    x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, qx1, qy1, ex2, ey2, nx2, ny2
):
    n, r1, e2, v = _line_geometry(x1, y1, th1, x2, y2, th2, qx1, qy1, ex2, ey2, nx2, ny2)
    q1_t = _point_velocity(vx1, vy1, w1, *r1)
    e2_t = _point_velocity(vx2, vy2, w2, *e2)
    v_t = (q1_t[0] - e2_t[0], q1_t[1] - e2_t[1])
    n_t = (-w2 * n[1], w2 * n[0])
    return n_t[0] * v[0] + n_t[1] * v[1] + n[0] * v_t[0] + n[1] * v_t[1]


def _normal_rates(n, w2, al2):
    """n' = w2 perp(n) and n'' = al2 perp(n) - w2^2 n for n rotating with body 2."""
    n_t = (-w2 * n[1], w2 * n[0])
    n_tt = (-al2 * n[1] - w2 * w2 * n[0], al2 * n[0] - w2 * w2 * n[1])
    return n_t, n_tt


def _line_second_derivative(n, n_t, n_tt, v, v_t, v_tt):
    """d'' = n'' . v + 2 n' . v' + n . v''."""
    return (
        n_tt[0] * v[0]
        + n_tt[1] * v[1]
        + 2 * (n_t[0] * v_t[0] + n_t[1] * v_t[1])
        + n[0] * v_tt[0]
        + n[1] * v_tt[1]
    )


def _line_gap_acceleration(
    x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1, x2, y2, th2, vx2, vy2, w2, ax2, ay2, al2,
    qx1, qy1, ex2, ey2, nx2, ny2,
):  # fmt: skip
    n, r1, e2, v = _line_geometry(x1, y1, th1, x2, y2, th2, qx1, qy1, ex2, ey2, nx2, ny2)
    q1_t = _point_velocity(vx1, vy1, w1, *r1)
    e2_t = _point_velocity(vx2, vy2, w2, *e2)
    q1_tt = _point_acceleration(ax1, ay1, al1, w1, *r1)
    e2_tt = _point_acceleration(ax2, ay2, al2, w2, *e2)
    v_t = (q1_t[0] - e2_t[0], q1_t[1] - e2_t[1])
    v_tt = (q1_tt[0] - e2_tt[0], q1_tt[1] - e2_tt[1])
    n_t, n_tt = _normal_rates(n, w2, al2)
    return _line_second_derivative(n, n_t, n_tt, v, v_t, v_tt)


def _line_bias(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, qx1, qy1, ex2, ey2, nx2, ny2):
    n, r1, e2, v = _line_geometry(x1, y1, th1, x2, y2, th2, qx1, qy1, ex2, ey2, nx2, ny2)
    q1_t = _point_velocity(vx1, vy1, w1, *r1)
    e2_t = _point_velocity(vx2, vy2, w2, *e2)
    q1_tt = _centripetal(w1, *r1)
    e2_tt = _centripetal(w2, *e2)
    v_t = (q1_t[0] - e2_t[0], q1_t[1] - e2_t[1])
    v_tt = (q1_tt[0] - e2_tt[0], q1_tt[1] - e2_tt[1])
    n_t = (-w2 * n[1], w2 * n[0])
    n_tt = _centripetal(w2, *n)
    return _line_second_derivative(n, n_t, n_tt, v, v_t, v_tt)


def _line_jacobian(x1, y1, th1, x2, y2, th2, qx1, qy1, ex2, ey2, nx2, ny2):
    n, r1, e2, v = _line_geometry(x1, y1, th1, x2, y2, th2, qx1, qy1, ex2, ey2, nx2, ny2)
    r2 = (v[0] + e2[0], v[1] + e2[1])  # q1 - X2: lever of the contact from body 2's centre
    return n[0], n[1], _cross(*r1, *n), -n[0], -n[1], -_cross(*r2, *n)


def _line_jacobian_static2(th1, th2, qx1, qy1, nx2, ny2):
    n = _rotate(np.cos(th2), np.sin(th2), nx2, ny2)
    r1 = _rotate(np.cos(th1), np.sin(th1), qx1, qy1)
    return n[0], n[1], _cross(*r1, *n)


def _line_bias_static2(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, qx1, qy1, ex2, ey2, nx2, ny2):
    """Body 2 fixed: n' = n'' = 0 and e2'' = 0, so d'' = n . q1''."""
    n = _rotate(np.cos(th2), np.sin(th2), nx2, ny2)
    r1 = _rotate(np.cos(th1), np.sin(th1), qx1, qy1)
    q1_tt = _centripetal(w1, *r1)
    return n[0] * q1_tt[0] + n[1] * q1_tt[1]


# --- circular edge of body 2 (vertex_circle, circle_circle) --------------------------------------


def _circle_geometry(x1, y1, th1, x2, y2, th2, qx1, qy1, cx2, cy2):
    """Levers R1 = R(th1) q1 and U2 = R(th2) c2, and v = q1 - c2 in world."""
    r1 = _rotate(np.cos(th1), np.sin(th1), qx1, qy1)
    u2 = _rotate(np.cos(th2), np.sin(th2), cx2, cy2)
    v = (x1 + r1[0] - x2 - u2[0], y1 + r1[1] - y2 - u2[1])
    return r1, u2, v


def _circle_normal(v, r2):
    """n = sigma v/|v| and |v|."""
    length = np.hypot(v[0], v[1])
    sigma = np.sign(r2)
    return (sigma * v[0] / length, sigma * v[1] / length), length


def _circle_gap(x1, y1, th1, x2, y2, th2, qx1, qy1, cx2, cy2, r2, offset):
    _, _, v = _circle_geometry(x1, y1, th1, x2, y2, th2, qx1, qy1, cx2, cy2)
    return np.sign(r2) * np.hypot(v[0], v[1]) - r2 - offset


def _circle_gap_velocity(
    x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, qx1, qy1, cx2, cy2, r2
):
    r1, u2, v = _circle_geometry(x1, y1, th1, x2, y2, th2, qx1, qy1, cx2, cy2)
    n, _ = _circle_normal(v, r2)
    q1_t = _point_velocity(vx1, vy1, w1, *r1)
    c2_t = _point_velocity(vx2, vy2, w2, *u2)
    return n[0] * (q1_t[0] - c2_t[0]) + n[1] * (q1_t[1] - c2_t[1])


def _circle_second_derivative(v, v_t, v_tt, r2):
    """d'' = n' . v' + n . v'',  n' = sigma (v'/|v| - v (v . v')/|v|^3)."""
    n, length = _circle_normal(v, r2)
    sigma = np.sign(r2)
    v_dot_vt = v[0] * v_t[0] + v[1] * v_t[1]
    n_t = (
        sigma * (v_t[0] / length - v[0] * v_dot_vt / length**3),
        sigma * (v_t[1] / length - v[1] * v_dot_vt / length**3),
    )
    return n_t[0] * v_t[0] + n_t[1] * v_t[1] + n[0] * v_tt[0] + n[1] * v_tt[1]


def _circle_gap_acceleration(
    x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1, x2, y2, th2, vx2, vy2, w2, ax2, ay2, al2,
    qx1, qy1, cx2, cy2, r2,
):  # fmt: skip
    r1, u2, v = _circle_geometry(x1, y1, th1, x2, y2, th2, qx1, qy1, cx2, cy2)
    q1_t = _point_velocity(vx1, vy1, w1, *r1)
    c2_t = _point_velocity(vx2, vy2, w2, *u2)
    q1_tt = _point_acceleration(ax1, ay1, al1, w1, *r1)
    c2_tt = _point_acceleration(ax2, ay2, al2, w2, *u2)
    v_t = (q1_t[0] - c2_t[0], q1_t[1] - c2_t[1])
    v_tt = (q1_tt[0] - c2_tt[0], q1_tt[1] - c2_tt[1])
    return _circle_second_derivative(v, v_t, v_tt, r2)


def _circle_bias(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, qx1, qy1, cx2, cy2, r2):
    r1, u2, v = _circle_geometry(x1, y1, th1, x2, y2, th2, qx1, qy1, cx2, cy2)
    q1_t = _point_velocity(vx1, vy1, w1, *r1)
    c2_t = _point_velocity(vx2, vy2, w2, *u2)
    q1_tt = _centripetal(w1, *r1)
    c2_tt = _centripetal(w2, *u2)
    v_t = (q1_t[0] - c2_t[0], q1_t[1] - c2_t[1])
    v_tt = (q1_tt[0] - c2_tt[0], q1_tt[1] - c2_tt[1])
    return _circle_second_derivative(v, v_t, v_tt, r2)


def _circle_jacobian(x1, y1, th1, x2, y2, th2, qx1, qy1, cx2, cy2, r2):
    r1, u2, v = _circle_geometry(x1, y1, th1, x2, y2, th2, qx1, qy1, cx2, cy2)
    n, _ = _circle_normal(v, r2)
    return n[0], n[1], _cross(*r1, *n), -n[0], -n[1], -_cross(*u2, *n)


def _circle_jacobian_static2(x1, y1, th1, x2, y2, th2, qx1, qy1, cx2, cy2, r2):
    r1, _, v = _circle_geometry(x1, y1, th1, x2, y2, th2, qx1, qy1, cx2, cy2)
    n, _ = _circle_normal(v, r2)
    return n[0], n[1], _cross(*r1, *n)


def _circle_bias_static2(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, qx1, qy1, cx2, cy2, r2):
    """Body 2 fixed: v' = q1', v'' = q1''."""
    r1, _, v = _circle_geometry(x1, y1, th1, x2, y2, th2, qx1, qy1, cx2, cy2)
    v_t = _point_velocity(vx1, vy1, w1, *r1)
    v_tt = _centripetal(w1, *r1)
    return _circle_second_derivative(v, v_t, v_tt, r2)


# --- the four cases with the generated kernels' keyword arguments --------------------------------
# fmt: off


class vertex_edge:  # named like the generated module
    @staticmethod
    def gap(*, x1, y1, th1, x2, y2, th2, px1, py1, ex2, ey2, nx2, ny2):
        return _line_gap(x1, y1, th1, x2, y2, th2, px1, py1, ex2, ey2, nx2, ny2, 0.0)

    @staticmethod
    def gap_velocity(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2,
                     px1, py1, ex2, ey2, nx2, ny2):
        return _line_gap_velocity(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2,
                                  px1, py1, ex2, ey2, nx2, ny2)

    @staticmethod
    def gap_acceleration(*, x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1,
                         x2, y2, th2, vx2, vy2, w2, ax2, ay2, al2, px1, py1, ex2, ey2, nx2, ny2):
        return _line_gap_acceleration(x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1,
                                      x2, y2, th2, vx2, vy2, w2, ax2, ay2, al2,
                                      px1, py1, ex2, ey2, nx2, ny2)

    @staticmethod
    def jacobian(*, x1, y1, th1, x2, y2, th2, px1, py1, ex2, ey2, nx2, ny2):
        return _line_jacobian(x1, y1, th1, x2, y2, th2, px1, py1, ex2, ey2, nx2, ny2)

    @staticmethod
    def bias(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2,
             px1, py1, ex2, ey2, nx2, ny2):
        return _line_bias(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2,
                          px1, py1, ex2, ey2, nx2, ny2)

    @staticmethod
    def jacobian_static2(*, th1, th2, px1, py1, nx2, ny2):
        return _line_jacobian_static2(th1, th2, px1, py1, nx2, ny2)

    @staticmethod
    def bias_static2(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, px1, py1, ex2, ey2, nx2, ny2):
        return _line_bias_static2(x1, y1, th1, vx1, vy1, w1, x2, y2, th2,
                                  px1, py1, ex2, ey2, nx2, ny2)


class circle_edge:
    @staticmethod
    def gap(*, x1, y1, th1, x2, y2, th2, cx1, cy1, r1, ex2, ey2, nx2, ny2):
        return _line_gap(x1, y1, th1, x2, y2, th2, cx1, cy1, ex2, ey2, nx2, ny2, r1)

    @staticmethod
    def gap_velocity(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2,
                     cx1, cy1, ex2, ey2, nx2, ny2):
        return _line_gap_velocity(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2,
                                  cx1, cy1, ex2, ey2, nx2, ny2)

    @staticmethod
    def gap_acceleration(*, x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1,
                         x2, y2, th2, vx2, vy2, w2, ax2, ay2, al2, cx1, cy1, ex2, ey2, nx2, ny2):
        return _line_gap_acceleration(x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1,
                                      x2, y2, th2, vx2, vy2, w2, ax2, ay2, al2,
                                      cx1, cy1, ex2, ey2, nx2, ny2)

    @staticmethod
    def jacobian(*, x1, y1, th1, x2, y2, th2, cx1, cy1, ex2, ey2, nx2, ny2):
        return _line_jacobian(x1, y1, th1, x2, y2, th2, cx1, cy1, ex2, ey2, nx2, ny2)

    @staticmethod
    def bias(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2,
             cx1, cy1, ex2, ey2, nx2, ny2):
        return _line_bias(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2,
                          cx1, cy1, ex2, ey2, nx2, ny2)

    @staticmethod
    def jacobian_static2(*, th1, th2, cx1, cy1, nx2, ny2):
        return _line_jacobian_static2(th1, th2, cx1, cy1, nx2, ny2)

    @staticmethod
    def bias_static2(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, cx1, cy1, ex2, ey2, nx2, ny2):
        return _line_bias_static2(x1, y1, th1, vx1, vy1, w1, x2, y2, th2,
                                  cx1, cy1, ex2, ey2, nx2, ny2)


class vertex_circle:
    @staticmethod
    def gap(*, x1, y1, th1, x2, y2, th2, px1, py1, cx2, cy2, r2):
        return _circle_gap(x1, y1, th1, x2, y2, th2, px1, py1, cx2, cy2, r2, 0.0)

    @staticmethod
    def gap_velocity(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2,
                     px1, py1, cx2, cy2, r2):
        return _circle_gap_velocity(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2,
                                    px1, py1, cx2, cy2, r2)

    @staticmethod
    def gap_acceleration(*, x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1,
                         x2, y2, th2, vx2, vy2, w2, ax2, ay2, al2, px1, py1, cx2, cy2, r2):
        return _circle_gap_acceleration(x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1,
                                        x2, y2, th2, vx2, vy2, w2, ax2, ay2, al2,
                                        px1, py1, cx2, cy2, r2)

    @staticmethod
    def jacobian(*, x1, y1, th1, x2, y2, th2, px1, py1, cx2, cy2, r2):
        return _circle_jacobian(x1, y1, th1, x2, y2, th2, px1, py1, cx2, cy2, r2)

    @staticmethod
    def bias(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, px1, py1, cx2, cy2, r2):
        return _circle_bias(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2,
                            px1, py1, cx2, cy2, r2)

    @staticmethod
    def jacobian_static2(*, x1, y1, th1, x2, y2, th2, px1, py1, cx2, cy2, r2):
        return _circle_jacobian_static2(x1, y1, th1, x2, y2, th2, px1, py1, cx2, cy2, r2)

    @staticmethod
    def bias_static2(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, px1, py1, cx2, cy2, r2):
        return _circle_bias_static2(x1, y1, th1, vx1, vy1, w1, x2, y2, th2,
                                    px1, py1, cx2, cy2, r2)


class circle_circle:
    @staticmethod
    def gap(*, x1, y1, th1, x2, y2, th2, cx1, cy1, r1, cx2, cy2, r2):
        return _circle_gap(x1, y1, th1, x2, y2, th2, cx1, cy1, cx2, cy2, r2, r1)

    @staticmethod
    def gap_velocity(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2,
                     cx1, cy1, cx2, cy2, r2):
        return _circle_gap_velocity(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2,
                                    cx1, cy1, cx2, cy2, r2)

    @staticmethod
    def gap_acceleration(*, x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1,
                         x2, y2, th2, vx2, vy2, w2, ax2, ay2, al2, cx1, cy1, cx2, cy2, r2):
        return _circle_gap_acceleration(x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1,
                                        x2, y2, th2, vx2, vy2, w2, ax2, ay2, al2,
                                        cx1, cy1, cx2, cy2, r2)

    @staticmethod
    def jacobian(*, x1, y1, th1, x2, y2, th2, cx1, cy1, cx2, cy2, r2):
        return _circle_jacobian(x1, y1, th1, x2, y2, th2, cx1, cy1, cx2, cy2, r2)

    @staticmethod
    def bias(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2, cx1, cy1, cx2, cy2, r2):
        return _circle_bias(x1, y1, th1, vx1, vy1, w1, x2, y2, th2, vx2, vy2, w2,
                            cx1, cy1, cx2, cy2, r2)

    @staticmethod
    def jacobian_static2(*, x1, y1, th1, x2, y2, th2, cx1, cy1, cx2, cy2, r2):
        return _circle_jacobian_static2(x1, y1, th1, x2, y2, th2, cx1, cy1, cx2, cy2, r2)

    @staticmethod
    def bias_static2(*, x1, y1, th1, vx1, vy1, w1, x2, y2, th2, cx1, cy1, cx2, cy2, r2):
        return _circle_bias_static2(x1, y1, th1, vx1, vy1, w1, x2, y2, th2,
                                    cx1, cy1, cx2, cy2, r2)


# fmt: on
CASES = {c.__name__: c for c in (vertex_edge, vertex_circle, circle_edge, circle_circle)}
