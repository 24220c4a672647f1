"""Oval edges: d'' for a vertex touching an ellipse equals the osculating-circle value.

The note says the circular restriction "can be relaxed by finding the radius of curvature". This
checks it to high precision with mpmath: the true gap (distance from a moving vertex to a moving
ellipse, found by root finding on the ellipse parameter) is differentiated numerically along a
trajectory that starts at contact, and compared with the circular formula (note eq. 8) evaluated with
the osculating circle's centre and radius at the contact point. The gap's value, slope and curvature
in time all agree, because a curve and its osculating circle share the point, the normal and the
curvature — exactly what d, d', d'' depend on.
"""

from __future__ import annotations

from dataclasses import dataclass

import mpmath as mp

DIGITS = 40


@dataclass(frozen=True)
class OsculatingCheck:
    true: tuple[float, float, float]  # d, d', d'' of the exact ellipse gap
    circle: tuple[float, float, float]  # the same from the osculating circle (note eq. 6-8)

    @property
    def max_difference(self) -> float:
        return max(abs(a - b) for a, b in zip(self.true, self.circle, strict=True))


def _rot(th, x, y):
    return mp.cos(th) * x - mp.sin(th) * y, mp.sin(th) * x + mp.cos(th) * y


def _ellipse_gap(a, b, q):
    """Signed distance from point q (ellipse frame) to the ellipse x^2/a^2 + y^2/b^2 = 1."""
    qx, qy = q
    phi0 = mp.atan2(a * qy, b * qx)

    def foot(phi):  # the foot of the normal through q: (q - e(phi)) . e'(phi) = 0
        ex, ey = a * mp.cos(phi), b * mp.sin(phi)
        return (qx - ex) * (-a * mp.sin(phi)) + (qy - ey) * (b * mp.cos(phi))

    phi = mp.findroot(foot, phi0)
    ex, ey = a * mp.cos(phi), b * mp.sin(phi)
    dist = mp.sqrt((qx - ex) ** 2 + (qy - ey) ** 2)
    outside = (qx / a) ** 2 + (qy / b) ** 2 > 1
    return dist if outside else -dist


def check(
    a=2.0, b=1.0, phi=0.7, seed_motion=(0.3, -0.2, 1.1, 0.5, 0.4, -0.8), radius_scale=1.0
) -> OsculatingCheck:
    """Vertex of body 1 touching the ellipse of body 2 (semi-axes a, b) at parameter phi.

    `radius_scale` != 1 uses a wrong circle (same contact point and normal), to show the check
    can fail.
    """
    with mp.workdps(DIGITS):
        a, b, phi = mp.mpf(a), mp.mpf(b), mp.mpf(phi)
        vx1, vy1, w1, vx2, vy2, w2 = (mp.mpf(s) for s in seed_motion)
        ax1, ay1, al1, ax2, ay2, al2 = mp.mpf("0.2"), mp.mpf("-1"), mp.mpf("0.3"), 0, 0, mp.mpf(2)
        th1, th2 = mp.mpf("0.4"), mp.mpf("-0.3")
        x2, y2 = mp.mpf("1.5"), mp.mpf("-0.5")
        # Contact point and osculating circle of the ellipse, in body-2 coordinates.
        px, py = a * mp.cos(phi), b * mp.sin(phi)
        dpx, dpy = -a * mp.sin(phi), b * mp.cos(phi)
        ddpx, ddpy = -px, -py
        speed = mp.sqrt(dpx**2 + dpy**2)
        kappa = (dpx * ddpy - dpy * ddpx) / speed**3
        nx, ny = dpy / speed, -dpx / speed  # outward normal
        radius = mp.mpf(radius_scale) / kappa
        cx, cy = px - radius * nx, py - radius * ny
        # Body 1 carries a vertex at (0.3, 0.2) placed on the contact point at t = 0.
        vertex = (mp.mpf("0.3"), mp.mpf("0.2"))
        wx, wy = _rot(th2, px, py)
        rx, ry = _rot(th1, *vertex)
        x1, y1 = x2 + wx - rx, y2 + wy - ry

        def pose(t, x, y, th, vx, vy, w, ax, ay, al):
            return (
                x + vx * t + ax * t**2 / 2,
                y + vy * t + ay * t**2 / 2,
                th + w * t + al * t**2 / 2,
            )

        def vertex_in_body2(t):
            X1, Y1, T1 = pose(t, x1, y1, th1, vx1, vy1, w1, ax1, ay1, al1)
            X2, Y2, T2 = pose(t, x2, y2, th2, vx2, vy2, w2, ax2, ay2, al2)
            ox, oy = _rot(T1, *vertex)
            return _rot(-T2, X1 + ox - X2, Y1 + oy - Y2)

        def true_gap(t):
            return _ellipse_gap(a, b, vertex_in_body2(t))

        def circle_gap(t):
            qx, qy = vertex_in_body2(t)
            return mp.sqrt((qx - cx) ** 2 + (qy - cy) ** 2) - radius

        true = tuple(float(mp.diff(true_gap, 0, k)) for k in range(3))
        circle = tuple(float(mp.diff(circle_gap, 0, k)) for k in range(3))
    return OsculatingCheck(true, circle)
