"""Independent high-precision oracle for the contact gap d(t) and its derivatives.

Written from the geometric definitions in docs/conventions.md only; it shares no code (and no
formula for a derivative) with derive/ or generated/:

* every body follows the quadratic trajectory X_i(t) = X_i + V_i t + A_i t^2/2,
  th_i(t) = th_i + w_i t + al_i t^2/2 (an arbitrary motion, not contact preserving);
* world points are complex numbers, z = (x + i y) + exp(i th) (px + i py);
* the gap d(t) of each case is evaluated from its definition:

  ===============  ===================================================================
  vertex_edge      Re(conj(n) (p1 - e2)),       n = exp(i th2) (nx2 + i ny2)
  vertex_circle    sigma |p1 - c2| - r2,        sigma = sign(r2) (concave = negative)
  circle_edge      Re(conj(n) (c1 - e2)) - r1
  circle_circle    sigma |c1 - c2| - r1 - r2
  ===============  ===================================================================

* d'(0), d''(0) are obtained by numerical differentiation of d(t) with mpmath (``diffs``: a
  central difference with a step of ~2^-(prec+10) evaluated at several hundred bits, so the result
  is good to ~``DPS`` digits for the exact float inputs); the Jacobian row is dd/dq by
  differentiating d with respect to each pose coordinate; the bias is d''(0) with every
  acceleration set to zero.

The oracle works in its own mpmath context (``CTX``, ``DPS`` digits) and never touches the
global ``mpmath.mp``. Inputs are Python/NumPy floats (converted exactly) keyed by the kernel
argument names; a missing velocity or acceleration is zero. ``error_scales`` gives the
magnitude against which float64 kernel errors are judged (see its docstring).
"""

from __future__ import annotations

import cmath
import importlib
import math
from collections.abc import Mapping

import mpmath

DPS = 60
CTX = mpmath.MPContext()
CTX.dps = DPS

CASES = ("vertex_edge", "vertex_circle", "circle_edge", "circle_circle")
FUNCTIONS = ("gap", "gap_velocity", "gap_acceleration", "jacobian", "bias")

POSE = ("x1", "y1", "th1", "x2", "y2", "th2")
VELOCITY = ("vx1", "vy1", "w1", "vx2", "vy2", "w2")
ACCELERATION = ("ax1", "ay1", "al1", "ax2", "ay2", "al2")
GEOMETRY = {
    "vertex_edge": ("px1", "py1", "ex2", "ey2", "nx2", "ny2"),
    "vertex_circle": ("px1", "py1", "cx2", "cy2", "r2"),
    "circle_edge": ("cx1", "cy1", "r1", "ex2", "ey2", "nx2", "ny2"),
    "circle_circle": ("cx1", "cy1", "r1", "cx2", "cy2", "r2"),
}
BODY2_MOTION = ("vx2", "vy2", "w2", "ax2", "ay2", "al2")
ABS_ERROR = 1e-40
"""Bound on the oracle's own absolute error for the magnitudes used in the tests (<= 1e12): the
numerical derivatives are good to ~1e-70 relative to the terms of d(t)."""


def state_keys(case: str) -> tuple[str, ...]:
    """Every input name of a case (pose, velocity, acceleration, geometry)."""
    return POSE + VELOCITY + ACCELERATION + GEOMETRY[case]


def _check_case(case: str) -> None:
    if case not in GEOMETRY:
        raise ValueError(f"unknown case {case!r}; expected one of {CASES}")


def _mp_state(case: str, state: Mapping[str, float], static2: bool) -> dict[str, mpmath.mpf]:
    """Exact mpf copy of the state; missing motion terms are zero; static2 zeroes body 2's."""
    _check_case(case)
    out = {}
    for key in state_keys(case):
        if key in POSE or key in GEOMETRY[case]:
            if key not in state:
                raise KeyError(f"{case}: state lacks {key!r}")
            value = state[key]
        else:
            value = state.get(key, 0.0)
        if static2 and key in BODY2_MOTION:
            value = 0.0
        out[key] = CTX.mpf(float(value))  # float -> mpf is exact
    return out


def _pose_at(s: Mapping[str, mpmath.mpf], i: int, t, dq) -> tuple:
    """(world position as complex, angle) of body i at time t, pose shifted by dq[3(i-1):3i]."""
    k = 3 * (i - 1)
    x = s[f"x{i}"] + s[f"vx{i}"] * t + s[f"ax{i}"] * t * t / 2 + dq[k]
    y = s[f"y{i}"] + s[f"vy{i}"] * t + s[f"ay{i}"] * t * t / 2 + dq[k + 1]
    th = s[f"th{i}"] + s[f"w{i}"] * t + s[f"al{i}"] * t * t / 2 + dq[k + 2]
    return CTX.mpc(x, y), th


def _world_point(s, i: int, bx: str, by: str, t, dq):
    """World position of body i's body-frame point (s[bx], s[by]): X + exp(i th) p."""
    origin, th = _pose_at(s, i, t, dq)
    return origin + CTX.expj(th) * CTX.mpc(s[bx], s[by])


def _sign(r) -> int:
    return -1 if r < 0 else 1  # copysign(1, r): zero counts as convex


def _gap_mp(case: str, s: Mapping[str, mpmath.mpf], t, dq=(0, 0, 0, 0, 0, 0)):
    """The exact gap d at time t (pose offsets dq), from the geometric definition of the case."""
    if case in ("vertex_edge", "circle_edge"):
        q = (
            _world_point(s, 1, "px1", "py1", t, dq)
            if case == "vertex_edge"
            else _world_point(s, 1, "cx1", "cy1", t, dq)
        )
        e = _world_point(s, 2, "ex2", "ey2", t, dq)
        _, th2 = _pose_at(s, 2, t, dq)
        n = CTX.expj(th2) * CTX.mpc(s["nx2"], s["ny2"])
        d = CTX.re(CTX.conj(n) * (q - e))  # n . (q - e)
        return d - s["r1"] if case == "circle_edge" else d
    q = (
        _world_point(s, 1, "px1", "py1", t, dq)
        if case == "vertex_circle"
        else _world_point(s, 1, "cx1", "cy1", t, dq)
    )
    c = _world_point(s, 2, "cx2", "cy2", t, dq)
    d = _sign(s["r2"]) * abs(q - c) - s["r2"]
    return d - s["r1"] if case == "circle_circle" else d


def gap_at(case: str, state: Mapping[str, float], t: float, *, static2: bool = False):
    """d(t) along the quadratic trajectory (mpf)."""
    s = _mp_state(case, state, static2)
    return _gap_mp(case, s, CTX.mpf(t))


def oracle_gap_derivatives(case: str, state: Mapping[str, float], *, static2: bool = False):
    """(d, d', d'') at t = 0 as mpf, by mpmath differentiation of d(t)."""
    s = _mp_state(case, state, static2)
    d0, d1, d2 = CTX.diffs(lambda t: _gap_mp(case, s, t), 0, 2)
    return +d0, +d1, +d2


def oracle_jacobian(case: str, state: Mapping[str, float], *, static2: bool = False):
    """(dd/dx1, dd/dy1, dd/dth1, dd/dx2, dd/dy2, dd/dth2) at t = 0 (mpf), differentiating d in q."""
    s = _mp_state(case, state, static2)
    out = []
    for k in range(6):

        def shifted(h, k=k):
            dq = [0, 0, 0, 0, 0, 0]
            dq[k] = h
            return _gap_mp(case, s, 0, dq)

        out.append(+CTX.diff(shifted, 0))
    return tuple(out)


def oracle_bias(case: str, state: Mapping[str, float], *, static2: bool = False):
    """d''(0) with all accelerations zero (mpf)."""
    still = dict(state)
    for key in ACCELERATION:
        still[key] = 0.0
    return oracle_gap_derivatives(case, still, static2=static2)[2]


def oracle_values(case: str, state: Mapping[str, float], *, static2: bool = False) -> dict:
    """Oracle value of every kernel function, keyed like the kernels (jacobian: 6-tuple)."""
    d0, d1, d2 = oracle_gap_derivatives(case, state, static2=static2)
    return {
        "gap": d0,
        "gap_velocity": d1,
        "gap_acceleration": d2,
        "jacobian": oracle_jacobian(case, state, static2=static2),
        "bias": oracle_bias(case, state, static2=static2),
    }


def oracle_values_both(case: str, state: Mapping[str, float]) -> tuple[dict, dict]:
    """(oracle_values(full state), oracle_values(static2)); gap and Jacobian do not depend on
    the motion, so they are computed once."""
    full = oracle_values(case, state)
    _, d1, d2 = oracle_gap_derivatives(case, state, static2=True)
    fixed = dict(full, gap_velocity=d1, gap_acceleration=d2)
    fixed["bias"] = oracle_bias(case, state, static2=True)
    return full, fixed


# --------------------------------------------------------------------------------------------
# float64 error model
# --------------------------------------------------------------------------------------------


def _norm(state: Mapping[str, float], a: str, b: str) -> float:
    return math.hypot(float(state.get(a, 0.0)), float(state.get(b, 0.0)))


def _world_float(g: Mapping[str, float], i: int, bx: str, by: str) -> complex:
    return complex(g[f"x{i}"], g[f"y{i}"]) + cmath.exp(1j * g[f"th{i}"]) * complex(g[bx], g[by])


EPS = 2.0**-52


def error_scales(
    case: str, state: Mapping[str, float], *, static2: bool = False, absolute: bool = False
) -> dict:
    """Magnitude S_f of the terms of each kernel function f, such that float64 can honestly
    deliver |kernel - exact| <~ c * eps * S_f with c = O(10).

    First-order model of the rounding of the intermediates a formulation from world poses
    must form:

    * ``L`` = |X1 - X2| + |p1 or c1| + |e2 or c2|: the relative position of the features is a
      sum of these, so it carries absolute errors ~eps*L. The kernels subtract the poses first
      (x1 - x2 is exact for nearby bodies), so translating both bodies to 1e4 costs nothing; a
      formulation that forms world points first loses eps*|X| and would need ``absolute=True``
      (L = |X1| + |X2| + ...). ``absolute=True`` is also the right model when the inputs
      themselves were shifted by a large amount in float (translation-invariance test).
    * levers ``l1`` = |p1| or |c1|; ``l2`` = |c2| for a circle, |e2| + |q - e2| for a straight
      edge (the material point of body 2 under body 1's feature q).
    * ``rho`` = |q - c2| for a circle of body 2, infinite for a straight edge. The normal
      n = (q - c2)/rho is only known to an angle eps*L/rho and 1/rho to a relative eps*L/rho, so
      every term that depends on n is amplified by ``kappa = 1 + L/rho``. A 1e-6 circle whose
      centre lies ~1 from its body's centre of mass has kappa ~ 1e6: the float64 inputs only
      fix n, and so d', d'' and the Jacobian, to ~1e-10 relative there, whatever the kernel
      does (measured: up to 2e-8 relative in d'', within the model).
    * ``W`` = |V1| + |V2| + |w1| l1 + |w2| l2 (material-point velocities),
      ``A`` = |A1| + |A2| + (|al1| + w1^2) l1 + (|al2| + w2^2) l2, ``O`` = |w1| + |w2|.

    Scales: gap ``L + |r1| + |r2|``; d' ``kappa W + O L``;
    d'' ``kappa (A + O W + W^2/rho) + (|al1| + |al2| + O^2) L`` (W^2/rho: the curvature term of a
    circle; the L terms: levers formed from world points); bias: d'' with the accelerations zero;
    Jacobian ``kappa`` for the x, y entries and ``kappa l_i + L`` for the th entries.
    """
    _check_case(case)
    g = {k: float(state.get(k, 0.0)) for k in state_keys(case)}
    if static2:
        for k in BODY2_MOTION:
            g[k] = 0.0
    feat1 = ("px1", "py1") if case.startswith("vertex") else ("cx1", "cy1")
    feat2 = ("ex2", "ey2") if case.endswith("edge") else ("cx2", "cy2")
    l1, l2 = _norm(g, *feat1), _norm(g, *feat2)
    if absolute:
        length = _norm(g, "x1", "y1") + _norm(g, "x2", "y2") + l1 + l2
    else:
        length = math.hypot(g["x1"] - g["x2"], g["y1"] - g["y2"]) + l1 + l2
    radii = abs(g.get("r1", 0.0)) + abs(g.get("r2", 0.0))
    sep = abs(_world_float(g, 1, *feat1) - _world_float(g, 2, *feat2))
    if case.endswith("circle"):
        rho = max(sep, EPS * length)
        kappa, curv = 1.0 + length / rho, 1.0 / rho
    else:
        kappa, curv = 1.0, 0.0
        l2 += sep
    w1, w2 = abs(g["w1"]), abs(g["w2"])
    al = abs(g["al1"]) + abs(g["al2"])
    om = w1 + w2
    vel = _norm(g, "vx1", "vy1") + _norm(g, "vx2", "vy2") + w1 * l1 + w2 * l2
    centripetal = w1 * w1 * l1 + w2 * w2 * l2
    acc = (
        _norm(g, "ax1", "ay1")
        + _norm(g, "ax2", "ay2")
        + abs(g["al1"]) * l1
        + abs(g["al2"]) * l2
        + centripetal
    )
    velocity_terms = om * vel + vel * vel * curv
    return {
        "gap": length + radii,
        "gap_velocity": kappa * vel + om * length,
        "gap_acceleration": kappa * (acc + velocity_terms) + (al + om * om) * length,
        "jacobian": (kappa, kappa, kappa * l1 + length, kappa, kappa, kappa * l2 + length),
        "bias": kappa * (centripetal + velocity_terms) + om * om * length,
    }


# --------------------------------------------------------------------------------------------
# harness: call a generated kernel with a state dict (no code from generated/ is reused)
# --------------------------------------------------------------------------------------------


def kernel_module(case: str):
    """generated.<case> if it has been generated and imports, else None."""
    try:
        return importlib.import_module(f"generated.{case}")
    except ImportError:
        return None


def kernel_name(module, name: str, static2: bool) -> str:
    """name, or name_static2 for body 2 fixed (gap has no static2 variant: it takes no motion)."""
    if static2 and name + "_static2" in module.ARGUMENTS:
        return name + "_static2"
    if static2 and name != "gap":
        raise KeyError(f"{module.__name__} has no {name}_static2")
    return name


def call_kernel(module, name: str, state: Mapping[str, object]):
    """module.<name>(**{the arguments ARGUMENTS[name] lists, taken from state})."""
    args = module.ARGUMENTS[name]
    return getattr(module, name)(**{key: state[key] for key in args})


def full_state(case: str, state: Mapping[str, float]) -> dict[str, float]:
    """The state with every input of the case present (missing motion terms = 0.0)."""
    return {key: float(state.get(key, 0.0)) for key in state_keys(case)}
