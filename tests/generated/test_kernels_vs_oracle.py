"""The generated kernels against the independent mpmath oracle (tests/oracle.py).

1. The oracle itself, against motions whose d, d', d'' are known in closed form.
2. Every function of every case (and the ``*_static2`` variants) against the oracle on
   (a) 50 random states per case (fixed seed; random velocities and accelerations, gaps of both
   signs, not contact preserving) and (b) hard states: radii 1e-6 and 1e6 (body 2 also concave),
   |w| up to 1e3, both bodies translated to coordinates ~1e4, tiny relative gaps.
   Pass criterion: ``|kernel - oracle| <= C * eps * (|oracle| + S)`` where S is the magnitude of
   the terms from ``oracle.error_scales`` (its docstring derives what float64 can deliver: e.g. a
   1e-6 circle ~1 from its body's centre of mass fixes the normal only to ~eps*1e6, so S grows
   by L/rho ~ 1e6 there; the 1e4 translation costs nothing as the kernels subtract poses first).
3. Limits: a circle of radius +-1e8 becomes its tangent line; a circle of radius -> 0 becomes a
   vertex (with body roles swapped when body 2's circle shrinks).
4. The kernels against ``sympy.lambdify`` of derive's expressions (``derive.kernels.kernel_specs``
   with the intermediates inlined): the printing/CSE step changes nothing.

Kernel tests skip (with the reason) while generated/<case>.py does not exist; the oracle tests
always run.

``python tests/generated/test_kernels_vs_oracle.py`` prints the max error table.
"""

from __future__ import annotations

import functools
import inspect
import math
import sys
from pathlib import Path

import numpy as np
import pytest

if __name__ == "__main__":  # script mode: the helpers live in tests/, the packages in the root
    sys.path[:0] = [str(Path(__file__).resolve().parents[1]), str(Path(__file__).parents[2])]

import oracle as O  # noqa: E402

EPS = float(np.finfo(float).eps)
C_TOL = 16.0  # allowed error, in units of eps * (|oracle| + S); observed max < 1
KERNELS = {case: O.kernel_module(case) for case in O.CASES}


def _need(case: str):
    if KERNELS[case] is None:
        pytest.skip(f"generated/{case}.py does not exist yet (derive/ has not emitted it)")
    return KERNELS[case]


# ------------------------------------------------------------------------------------------
# state construction
# ------------------------------------------------------------------------------------------


def _rot(th: float, x: float, y: float) -> tuple[float, float]:
    c, s = math.cos(th), math.sin(th)
    return c * x - s * y, s * x + c * y


def _unit(rng: np.random.Generator) -> tuple[float, float]:
    phi = rng.uniform(-math.pi, math.pi)
    return math.cos(phi), math.sin(phi)


def make_state(
    rng: np.random.Generator,
    case: str,
    *,
    r1: float = 0.0,
    r2: float = 0.0,
    lever1: float = 1.0,
    lever2: float = 1.0,
    along: float = 1.0,
    gap: float = 0.0,
    rho_factor: float = 1.0,
    offset: float = 0.0,
    omega: float = 1.0,
    vel: float = 1.0,
    acc: float = 1.0,
) -> dict[str, float]:
    """A state with body 1's feature placed relative to body 2's: for a straight edge at signed
    distance ``gap`` (+ r1) from the line and ``along`` along it; for a circle of body 2 at distance
    ``rho = rho_factor * rho_contact`` from its centre (rho_contact = r1 + r2 convex,
    |r2| - r1 concave). Both bodies are translated by ~``offset`` in x and -y. Velocities,
    angular velocities and accelerations are random with magnitudes vel, omega, acc.
    """
    s: dict[str, float] = {}
    th1, th2 = rng.uniform(-math.pi, math.pi, 2)
    x2 = offset * rng.uniform(0.9, 1.1) + rng.normal()
    y2 = -offset * rng.uniform(0.9, 1.1) + rng.normal()
    s.update(x2=x2, y2=y2, th1=th1, th2=th2)
    ux, uy = _unit(rng)
    fx, fy = lever2 * ux, lever2 * uy  # body-frame feature of body 2
    wx, wy = _rot(th2, fx, fy)
    if case.endswith("edge"):
        nx, ny = _unit(rng)
        s.update(ex2=fx, ey2=fy, nx2=nx, ny2=ny)
        nwx, nwy = _rot(th2, nx, ny)
        h = gap + r1
        qx = x2 + wx + h * nwx - along * nwy
        qy = y2 + wy + h * nwy + along * nwx
    else:
        s.update(cx2=fx, cy2=fy, r2=r2)
        rho = rho_factor * (r1 + r2 if r2 > 0 else abs(r2) - r1)
        dx, dy = _unit(rng)
        qx, qy = x2 + wx + rho * dx, y2 + wy + rho * dy
    px, py = (lever1 * c for c in _unit(rng))
    if case.startswith("vertex"):
        s.update(px1=px, py1=py)
    else:
        s.update(cx1=px, cy1=py, r1=r1)
    rx, ry = _rot(th1, px, py)
    s.update(x1=qx - rx, y1=qy - ry)
    for i in (1, 2):
        s[f"vx{i}"], s[f"vy{i}"] = vel * rng.normal(size=2)
        s[f"ax{i}"], s[f"ay{i}"] = acc * rng.normal(size=2)
        s[f"w{i}"] = omega * rng.choice([-1.0, 1.0]) * rng.uniform(0.2, 1.0)
        s[f"al{i}"] = omega * rng.normal()
    return {k: float(v) for k, v in s.items()}


def random_states(case: str, n: int = 50) -> list[dict[str, float]]:
    """Moderate random states: radii 0.2..3 (body 2 of either sign), levers 0.1..3, gaps of
    both signs up to ~90% of the contact distance."""
    rng = np.random.default_rng([20240611, O.CASES.index(case)])
    out = []
    for _ in range(n):
        r2 = float(rng.choice([-1.0, 1.0]) * 10 ** rng.uniform(-0.7, 0.5))
        r1 = float(10 ** rng.uniform(-0.7, 0.5)) if case.startswith("circle") else 0.0
        if r2 < 0 and r1 >= 0.9 * abs(r2):
            r1 = abs(r2) * rng.uniform(0.1, 0.8)
        out.append(
            make_state(
                rng,
                case,
                r1=r1,
                r2=r2,
                lever1=10 ** rng.uniform(-1, 0.5),
                lever2=10 ** rng.uniform(-1, 0.5),
                along=rng.uniform(-2, 2),
                gap=max(r1, 1.0) * rng.uniform(-0.9, 0.9),
                rho_factor=rng.uniform(0.1, 1.9),
                omega=2.0,
            )
        )
    return out


def _radius_grid(case: str) -> list[tuple[float, float]]:
    big, small = 1e6, 1e-6
    if case == "vertex_edge":
        return [(0.0, 0.0)]
    if case == "vertex_circle":
        return [(0.0, r2) for r2 in (small, -small, big, -big)]
    if case == "circle_edge":
        return [(r1, 0.0) for r1 in (small, big)]
    grid = []
    for r1 in (small, big):
        for r2 in (small, big, -small, -big):
            grid.append((min(r1, abs(r2) / 2) if r2 < 0 else r1, r2))
    return grid


def hard_states(case: str, reps: int = 3) -> list[dict[str, float]]:
    """Radii 1e-6 / 1e6 (body 2 also concave; vertex_edge: edge offsets and vertex levers of
    1e-6 / 1e6), |w| ~ 1 or up to 1e3, coordinates 0 or ~1e4, relative gaps 1e-6..0.5 of
    either sign."""
    rng = np.random.default_rng([777, O.CASES.index(case)])
    out = []
    for r1, r2 in _radius_grid(case):
        for size in (1e-6, 1e6) if case == "vertex_edge" else (None,):
            for offset in (0.0, 1e4):
                for omega in (1.0, 1e3):
                    for _ in range(reps):
                        rel = rng.choice([-1.0, 1.0]) * 10 ** rng.uniform(-6, -0.3)
                        scale2 = size if size else max(abs(r2), 1.0)
                        scale1 = size if size else max(r1, 1.0)
                        out.append(
                            make_state(
                                rng,
                                case,
                                r1=r1,
                                r2=r2,
                                lever1=scale1 * rng.uniform(0.5, 1.5),
                                lever2=scale2 * rng.uniform(0.5, 1.5),
                                along=(size or max(r1, 1.0)) * rng.uniform(-1, 1),
                                gap=(size or max(r1, 1.0)) * rel,
                                rho_factor=1.0 + rel,
                                offset=offset,
                                omega=omega,
                            )
                        )
    return out


STATE_SETS = {"random": random_states, "hard": hard_states}


# ------------------------------------------------------------------------------------------
# comparison machinery
# ------------------------------------------------------------------------------------------


def normalized_errors(case: str, module, state, static2: bool) -> dict[str, float]:
    """|kernel - oracle| / (eps (|oracle| + S)) per function (max over Jacobian entries)."""
    ora = O.oracle_values(case, state, static2=static2)
    scales = O.error_scales(case, state, static2=static2)
    out = {}
    for name in O.FUNCTIONS:
        got = O.call_kernel(module, O.kernel_name(module, name, static2), state)
        if name == "jacobian":
            n = 3 if static2 else 6
            got = tuple(got)
            assert len(got) == n, f"{case}.{name} (static2={static2}) returned {len(got)} entries"
            pairs = zip(got, ora[name][:n], scales[name][:n], strict=True)
        else:
            pairs = [(got, ora[name], scales[name])]
        err = 0.0
        for g, o, sc in pairs:
            g = float(g)
            if not math.isfinite(g):
                err = math.inf
                continue
            diff = max(float(abs(O.CTX.mpf(g) - o)) - O.ABS_ERROR, 0.0)
            err = max(err, diff / (EPS * (abs(float(o)) + sc)) if diff else 0.0)
        out[name] = err
    return out


@functools.cache
def error_table(case: str, which: str, static2: bool) -> dict[str, tuple[float, int]]:
    """Max normalized error and the index of the worst state, per function."""
    module = _need(case)
    worst: dict[str, tuple[float, int]] = {name: (0.0, -1) for name in O.FUNCTIONS}
    for i, state in enumerate(STATE_SETS[which](case)):
        for name, err in normalized_errors(case, module, state, static2).items():
            if not err <= worst[name][0]:
                worst[name] = (err, i)
    return worst


# ------------------------------------------------------------------------------------------
# 1. the oracle against closed forms
# ------------------------------------------------------------------------------------------


def _zero_motion() -> dict[str, float]:
    return {k: 0.0 for k in O.VELOCITY + O.ACCELERATION}


def _close(value, expected, tol=1e-40) -> bool:
    return abs(value - expected) <= tol * (1 + abs(expected))


def test_oracle_vertex_sliding_along_fixed_edge():
    """A vertex (of a body at some angle) translating at constant velocity parallel to a fixed
    edge with a slanted normal keeps its height: d = h, d' = d'' = 0. (Normal (0.6, 0.8) and
    velocity (0.8, -0.6) are orthogonal exactly in the float values used.)"""
    h = 0.25
    s = _zero_motion()
    s.update(x2=1.0, y2=-2.0, th2=0.0, ex2=0.5, ey2=0.0, nx2=0.6, ny2=0.8, th1=1.1)
    s.update(px1=0.3, py1=-0.4, vx1=0.8, vy1=-0.6)
    rx, ry = _rot(1.1, 0.3, -0.4)
    s.update(x1=1.5 + h * 0.6 - rx + 1.6, y1=-2.0 + h * 0.8 - ry - 1.2)
    d0, d1, d2 = O.oracle_gap_derivatives("vertex_edge", s)
    assert abs(d0 - h) < 1e-15  # the float placement of x1, y1 rounds
    assert _close(d1, 0) and _close(d2, 0)


@pytest.mark.parametrize("radius", [1.7, -1.7, 1e-6, -1e6])
def test_oracle_tangential_motion_on_circle(radius):
    """A vertex at the contact point of a fixed circle (or bowl, r < 0) moving tangentially at
    speed v: d = d' = 0 and d'' = v^2/r (the centripetal term, negative in a bowl)."""
    v = 2.5
    s = _zero_motion()
    s.update(x2=0.0, y2=0.0, th2=0.0, cx2=0.0, cy2=0.0, r2=radius, th1=0.0, px1=0.0, py1=0.0)
    s.update(x1=abs(radius), y1=0.0, vy1=v)
    d0, d1, d2 = O.oracle_gap_derivatives("vertex_circle", s)
    assert _close(d0, 0) and _close(d1, 0)
    assert _close(d2, _ratio(v * v, radius))


def _ratio(a: float, b: float):
    """a / b exactly enough (oracle precision)."""
    return O.CTX.mpf(a) / O.CTX.mpf(b)


@pytest.mark.parametrize("case", ["vertex_circle", "circle_circle"])
def test_oracle_body2_rotating_about_bowl_centre(case):
    """Body 1's feature at rest inside a bowl (r2 < 0) whose body 2 spins about the bowl's
    centre (the centre is off body 2's centre of mass, so X2 must move to keep it fixed):
    d = |r2| - rho (- r1), d' = d'' = 0."""
    w, th2, c2 = 7.0, 0.0, (0.625, -1.25)  # dyadic: the compensating motion is exact
    cwx, cwy = _rot(th2, *c2)
    s = _zero_motion()
    s.update(x2=2.0, y2=1.0, th2=th2, cx2=c2[0], cy2=c2[1], r2=-3.0, w2=w)
    # centre C = X2 + R c2 fixed: V2 = -w J R c2, A2 = w^2 R c2 (al2 = 0)
    s.update(vx2=w * cwy, vy2=-w * cwx, ax2=w * w * cwx, ay2=w * w * cwy)
    feat = ("px1", "py1") if case == "vertex_circle" else ("cx1", "cy1")
    s.update({feat[0]: 0.2, feat[1]: 0.1, "th1": -0.7})
    if case == "circle_circle":
        s["r1"] = 0.5
    rx, ry = _rot(-0.7, 0.2, 0.1)
    s.update(x1=2.0 + cwx + 1.5 - rx, y1=1.0 + cwy - ry)  # 1.5 from the bowl centre
    d0, d1, d2 = O.oracle_gap_derivatives(case, s)
    assert abs(d0 - (3.0 - 1.5 - s.get("r1", 0.0))) < 1e-14
    assert _close(d1, 0) and _close(d2, 0)


def test_oracle_edge_rotating_about_its_point():
    """A fixed vertex on the line of an edge, at distance L along it from the pivot e2 about
    which body 2 rotates: d(t) = -L sin(th(t)) so d = 0, d' = -L w, d'' = -L al."""
    length, w, al = 1.5, 3.0, -4.0
    s = _zero_motion()
    s.update(x2=0.0, y2=0.0, th2=0.0, ex2=0.0, ey2=0.0, nx2=0.0, ny2=1.0, w2=w, al2=al)
    s.update(x1=length, y1=0.0, th1=0.0, px1=0.0, py1=0.0)
    d0, d1, d2 = O.oracle_gap_derivatives("vertex_edge", s)
    assert _close(d0, 0) and _close(d1, -length * w) and _close(d2, -length * al)


def test_oracle_wheel_rolling_on_line():
    """A wheel (circle_edge) whose circle centre is off its centre of mass, rolling at speed v
    on a fixed horizontal line (the centre moves straight, w1 = -v/r): d = d' = d'' = 0."""
    r, v, th1, c1 = 0.5, 2.0, 0.0, (0.25, 0.125)  # dyadic: the rolling motion is exact
    w = -v / r
    cx, cy = _rot(th1, *c1)
    s = _zero_motion()
    s.update(x2=0.0, y2=0.0, th2=0.0, ex2=0.0, ey2=0.0, nx2=0.0, ny2=1.0)
    s.update(cx1=c1[0], cy1=c1[1], r1=r, th1=th1, w1=w, x1=0.4 - cx, y1=r - cy)
    # centre velocity (v, 0): V1 = (v, 0) - w J R c1; centre acceleration 0: A1 = w^2 R c1
    s.update(vx1=v + w * cy, vy1=-w * cx, ax1=w * w * cx, ay1=w * w * cy)
    d0, d1, d2 = O.oracle_gap_derivatives("circle_edge", s)
    assert abs(d0) < 1e-15 and _close(d1, 0) and _close(d2, 0)


@pytest.mark.parametrize("r2", [0.7, -2.0])
def test_oracle_circle_centre_moving_tangentially(r2):
    """Body 1's circle centre passing body 2's fixed circle tangentially at speed v at the contact
    distance rho: d = 0, d' = 0, d'' = sigma v^2 / rho."""
    r1, v = 0.5, 1.5
    rho = r1 + r2 if r2 > 0 else abs(r2) - r1
    s = _zero_motion()
    s.update(x2=0.0, y2=0.0, th2=0.0, cx2=0.0, cy2=0.0, r2=r2, cx1=0.0, cy1=0.0, r1=r1)
    s.update(x1=0.0, y1=rho, th1=2.0, vx1=v, w1=5.0)
    d0, d1, d2 = O.oracle_gap_derivatives("circle_circle", s)
    assert _close(d0, 0) and _close(d1, 0)
    assert _close(d2, math.copysign(1, r2) * _ratio(v * v, rho))


def test_oracle_vertex_edge_jacobian_closed_form():
    """dd/dq of vertex_edge is (n, (R1 p1) x n, -n, -(q - X2) x n) with n = R(th2) n2."""
    rng = np.random.default_rng(5)
    s = make_state(rng, "vertex_edge", gap=0.3, along=0.7)
    jac = O.oracle_jacobian("vertex_edge", s)
    nx, ny = _rot(s["th2"], s["nx2"], s["ny2"])
    rx, ry = _rot(s["th1"], s["px1"], s["py1"])
    qx, qy = s["x1"] + rx - s["x2"], s["y1"] + ry - s["y2"]
    expected = (nx, ny, rx * ny - ry * nx, -nx, -ny, -(qx * ny - qy * nx))
    for got, want in zip(jac, expected, strict=True):
        assert abs(got - want) < 1e-14


@pytest.mark.parametrize("case", O.CASES)
def test_oracle_internal_consistency(case):
    """Two independent differentiation paths of the oracle agree: d' = J . v (d is first order
    in q = q0 + v t) and d'' = J . a + bias; and d' from mpmath matches a central difference of
    d(t) with step 1e-20 (error ~1e-40)."""
    for state in random_states(case, 5) + hard_states(case, 1)[::5]:
        d0, d1, d2 = O.oracle_gap_derivatives(case, state)
        jac = O.oracle_jacobian(case, state)
        vel = sum(j * state[k] for j, k in zip(jac, O.VELOCITY, strict=True))
        acc = sum(j * state[k] for j, k in zip(jac, O.ACCELERATION, strict=True))
        scales = O.error_scales(case, state)
        assert abs(d1 - vel) <= 1e-40 * (1 + scales["gap_velocity"])
        bias = O.oracle_bias(case, state)
        assert abs(d2 - acc - bias) <= 1e-40 * (1 + scales["gap_acceleration"])
        with O.CTX.workdps(O.DPS + 30):
            h = O.CTX.mpf("1e-25")
            fd = (O.gap_at(case, state, h) - O.gap_at(case, state, -h)) / (2 * h)
        assert abs(fd - d1) <= 1e-30 * (1 + scales["gap_velocity"] + abs(d2))


# ------------------------------------------------------------------------------------------
# 2. kernels against the oracle
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("case", O.CASES)
def test_arguments_contract(case):
    """ARGUMENTS lists each function's keyword-only arguments in signature order, and each
    function takes only what it needs (conventions.md): no velocities for gap/jacobian, no
    accelerations for gap_velocity/bias, no body-2 motion for the static2 variants."""
    module = _need(case)
    motion = set(O.VELOCITY + O.ACCELERATION)
    allowed = {
        "gap": set(),
        "gap_velocity": set(O.VELOCITY),
        "gap_acceleration": motion,
        "jacobian": set(),
        "bias": set(O.VELOCITY),
    }
    for name in O.FUNCTIONS:
        for suffix in ("", "_static2"):
            fname = name + suffix
            if fname == "gap_static2" and fname not in module.ARGUMENTS:
                continue  # the gap takes no motion: body 2 fixed changes nothing
            assert fname in module.ARGUMENTS, f"{case}: ARGUMENTS lacks {fname}"
            args = tuple(module.ARGUMENTS[fname])
            params = inspect.signature(getattr(module, fname)).parameters.values()
            assert all(p.kind is inspect.Parameter.KEYWORD_ONLY for p in params), fname
            assert tuple(p.name for p in params) == args, fname
            ok = set(O.POSE + O.GEOMETRY[case]) | allowed[name]
            if suffix:
                ok -= set(O.BODY2_MOTION)
            assert set(args) <= ok, f"{case}.{fname} takes {sorted(set(args) - ok)}"


@pytest.mark.parametrize("static2", [False, True], ids=["full", "static2"])
@pytest.mark.parametrize("which", ["random", "hard"])
@pytest.mark.parametrize("function", O.FUNCTIONS)
@pytest.mark.parametrize("case", O.CASES)
def test_kernel_matches_oracle(case, function, which, static2):
    """Max over the state set of |kernel - oracle| / (eps (|oracle| + S)) is <= C_TOL."""
    err, worst = error_table(case, which, static2)[function]
    states = STATE_SETS[which](case)
    assert err <= C_TOL, (
        f"{case}.{function}{'_static2' if static2 else ''} on {which} state #{worst}: "
        f"error {err:.3g} eps*(|o|+S) > {C_TOL}; state = {states[worst]!r}"
    )


# ------------------------------------------------------------------------------------------
# 3. limits
# ------------------------------------------------------------------------------------------


def _values(case: str, state, static2: bool = False) -> dict:
    module = _need(case)
    out = {
        name: O.call_kernel(module, O.kernel_name(module, name, static2), state)
        for name in O.FUNCTIONS
    }
    out["jacobian"] = tuple(float(v) for v in out["jacobian"])
    return {k: (v if k == "jacobian" else float(v)) for k, v in out.items()}


def _flat(values: dict) -> list[tuple[str, float]]:
    out = []
    for name in O.FUNCTIONS:
        if name == "jacobian":
            out += [(f"jacobian[{i}]", v) for i, v in enumerate(values[name])]
        else:
            out.append((name, values[name]))
    return out


def _tangent_line_pair(rng, radius: float, circle_case: str):
    """A body-2 circle of signed radius `radius` and the tangent line at its point e2, with body
    1's feature within O(1) of e2 and O(1) motion of both bodies. Returns (circle state, line
    state, line case)."""
    line_case = "vertex_edge" if circle_case == "vertex_circle" else "circle_edge"
    line = make_state(rng, line_case, r1=0.0 if line_case == "vertex_edge" else 0.4)
    circle = dict(line)
    for key in ("ex2", "ey2", "nx2", "ny2"):
        circle.pop(key)
    circle.update(
        cx2=line["ex2"] - radius * line["nx2"], cy2=line["ey2"] - radius * line["ny2"], r2=radius
    )
    return circle, line, line_case


@pytest.mark.parametrize("radius", [1e8, -1e8])
@pytest.mark.parametrize("circle_case", ["vertex_circle", "circle_circle"])
def test_limit_large_radius_is_tangent_line(circle_case, radius):
    """As r2 -> +-inf a circle (or bowl) through e2 with normal n2 there becomes the line
    (e2, n2): at r2 = 1e8 every output matches the straight-edge kernel. The exact difference is
    O(1/r2) ~ 1e-8 (the oracle shows it); the kernels may differ by that plus their own float
    error, ~eps * S of the circle state (S ~ w2^2 r2 because the far centre moves fast)."""
    rng = np.random.default_rng([11, int(radius > 0), O.CASES.index(circle_case)])
    for _ in range(10):
        circle, line, line_case = _tangent_line_pair(rng, radius, circle_case)
        got_c, got_l = _flat(_values(circle_case, circle)), _flat(_values(line_case, line))
        ora_c, ora_l = O.oracle_values(circle_case, circle), O.oracle_values(line_case, line)
        scales = _flat(O.error_scales(circle_case, circle))
        for (name, kc), (_, kl), (_, oc), (_, ol), (_, sc) in zip(
            got_c, got_l, _flat(ora_c), _flat(ora_l), scales, strict=True
        ):
            exact_gap = float(abs(oc - ol))
            assert exact_gap <= 1e-6 * (1 + abs(float(ol))), (name, exact_gap)
            tol = exact_gap + C_TOL * EPS * (abs(float(ol)) + sc)
            assert abs(kc - kl) <= tol, (circle_case, radius, name, kc, kl, tol)


@pytest.mark.parametrize("tiny", [1e-12, 1e-300])
def test_limit_circle_edge_small_radius_is_vertex_edge(tiny):
    """circle_edge with r1 -> 0 is vertex_edge with the vertex at c1: d = d_vertex - r1 and
    every derivative, the Jacobian and the bias are independent of r1 (to rounding)."""
    for state in random_states("circle_edge", 20):
        state = dict(state, r1=tiny)
        vertex = dict(state, px1=state["cx1"], py1=state["cy1"])
        got_c, got_v = _values("circle_edge", state), _values("vertex_edge", vertex)
        got_v["gap"] -= tiny
        scales = _flat(O.error_scales("vertex_edge", vertex))
        for (name, a), (_, b), (_, sc) in zip(_flat(got_c), _flat(got_v), scales, strict=True):
            assert abs(a - b) <= C_TOL * EPS * (abs(b) + sc), (name, a, b)


@pytest.mark.parametrize("tiny", [1e-12, 1e-300])
def test_limit_circle_circle_small_r1_is_vertex_circle(tiny):
    """circle_circle with r1 -> 0 is vertex_circle with the vertex at c1 (same bodies):
    d = d_vertex - r1, all else equal."""
    for state in random_states("circle_circle", 20):
        if state["r2"] < 0:
            state = dict(state, r2=state["r2"] - state["r1"])  # keep the disc's room in the bowl
        state = dict(state, r1=tiny)
        vertex = dict(state, px1=state["cx1"], py1=state["cy1"])
        got_c, got_v = _values("circle_circle", state), _values("vertex_circle", vertex)
        got_v["gap"] -= tiny
        scales = _flat(O.error_scales("vertex_circle", vertex))
        for (name, a), (_, b), (_, sc) in zip(_flat(got_c), _flat(got_v), scales, strict=True):
            assert abs(a - b) <= C_TOL * EPS * (abs(b) + sc), (name, a, b)


def _swap_bodies(state: dict[str, float]) -> dict[str, float]:
    """Body 1 <-> body 2 for pose, velocity and acceleration keys."""
    out = dict(state)
    for stem in ("x", "y", "th", "vx", "vy", "w", "ax", "ay", "al"):
        out[f"{stem}1"], out[f"{stem}2"] = state[f"{stem}2"], state[f"{stem}1"]
    return out


@pytest.mark.parametrize("tiny", [1e-12, 1e-300])
def test_limit_circle_circle_small_r2_is_vertex_circle_swapped(tiny):
    """circle_circle with r2 -> 0+ (body 2's circle shrinks to its centre c2) is the gap between
    body 2's point c2 and body 1's circle: vertex_circle with the roles swapped (body 1 := old
    body 2 with vertex p1 = c2, body 2 := old body 1 with the circle c1, r1). The gap function
    d(t) is the same, so d, d', d'' and the bias agree (d up to the r2 offset) while the two
    halves of the Jacobian row swap: J_cc = (J_vc[3:], J_vc[:3]). (The normal flips sign, but
    d does not depend on which body owns it.)"""
    for state in random_states("circle_circle", 20):
        state = dict(state, r2=tiny)
        swapped = _swap_bodies(state)
        swapped.update(px1=state["cx2"], py1=state["cy2"], cx2=state["cx1"], cy2=state["cy1"])
        swapped.update(r2=state["r1"])
        for key in ("cx1", "cy1", "r1"):
            swapped.pop(key)
        got_c, got_v = _values("circle_circle", state), _values("vertex_circle", swapped)
        got_v["gap"] -= tiny
        got_v["jacobian"] = got_v["jacobian"][3:] + got_v["jacobian"][:3]
        scales = _flat(O.error_scales("circle_circle", state))
        for (name, a), (_, b), (_, sc) in zip(_flat(got_c), _flat(got_v), scales, strict=True):
            assert abs(a - b) <= C_TOL * EPS * (abs(b) + sc), (name, a, b)


# ------------------------------------------------------------------------------------------
# 4. kernels against sympy.lambdify of derive's raw expressions
# ------------------------------------------------------------------------------------------


@functools.cache
def _derive_expressions(case: str) -> dict[str, tuple] | None:
    """{kernel name: (symbols, sympy outputs in state symbols)} from derive's kernel specs, or
    None if derive/ cannot be imported. The specs' outputs are written in named intermediates;
    they are inlined here (last to first, so each definition may use earlier ones), and derive's
    printing helpers Hypot and UnitSign become sqrt(a^2 + b^2) and sign(r) (r != 0 here)."""
    try:
        import sympy as sp

        from derive.cases import ALL_CASES
        from derive.derivation import Hypot, UnitSign, derive
        from derive.kernels import kernel_specs
    except ImportError:
        return None
    out = {}
    for spec in kernel_specs(derive(ALL_CASES[case]())):
        exprs = list(spec.outputs)
        for symbol, value in reversed(spec.intermediates):
            exprs = [e.subs(symbol, value) for e in exprs]
        exprs = [
            e.replace(Hypot, lambda a, b: sp.sqrt(a**2 + b**2)).replace(UnitSign, sp.sign)
            for e in exprs
        ]
        symbols = sorted(set().union(*(e.free_symbols for e in exprs)), key=str)
        out[spec.name] = (symbols, exprs)
    return out


@pytest.mark.parametrize("case", O.CASES)
def test_kernels_match_lambdified_derive_expressions(case):
    """The emitted code evaluates the expressions derive computed (no printing, CSE or argument
    order slip): sympy.lambdify of derive's kernel-spec outputs, intermediates inlined, agrees
    with every generated function on 20 random states, to C_TOL * eps * (|value| + S) with S from
    oracle.error_scales (the inlined form rounds differently, not worse than S), and takes no
    argument the generated function lacks."""
    import sympy as sp

    module = _need(case)
    exprs = _derive_expressions(case)
    if exprs is None:
        pytest.skip("derive/ is not importable: nothing to lambdify")
    assert set(exprs) == set(module.ARGUMENTS), "derive's specs and the generated module differ"
    states = random_states(case, 20)
    for name, (symbols, outputs) in exprs.items():
        assert {str(s) for s in symbols} <= set(module.ARGUMENTS[name]), name
        func = sp.lambdify(symbols, outputs, modules="numpy")
        base = name.removesuffix("_static2")
        static2 = name != base
        for state in states:
            full = O.full_state(case, state)
            if static2:
                full.update({k: 0.0 for k in O.BODY2_MOTION})
            want = [float(v) for v in func(*(full[str(s)] for s in symbols))]
            got = O.call_kernel(module, name, full)
            got = [float(v) for v in (got if isinstance(got, tuple) else (got,))]
            scale = O.error_scales(case, full)[base]
            scale = scale if isinstance(scale, tuple) else (scale,)
            for g, w, sc in zip(got, want, scale, strict=False):
                assert abs(g - w) <= C_TOL * EPS * (abs(w) + sc), (name, g, w, state)


# ------------------------------------------------------------------------------------------


def print_table() -> None:
    """The max error table: case x function x {random, hard} x {full, static2}."""
    print(f"max |kernel - oracle| / (eps (|oracle| + S)), eps = {EPS:.3g}; pass <= {C_TOL}")
    head = f"{'case':15s} {'function':17s}"
    print(head + "".join(f"{w + '/' + v:>17s}" for w in STATE_SETS for v in ("full", "static2")))
    for case in O.CASES:
        if KERNELS[case] is None:
            print(f"{case:15s} (not generated)")
            continue
        tables = [error_table(case, w, s) for w in STATE_SETS for s in (False, True)]
        for name in O.FUNCTIONS:
            cells = "".join(f"{t[name][0]:17.3g}" for t in tables)
            print(f"{case:15s} {name:17s}{cells}")


if __name__ == "__main__":
    print_table()
