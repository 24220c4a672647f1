"""Every velocity term of every bias kernel, one test each, against the mpmath oracle.

The bias b (d'' at zero accelerations) is a quadratic form in the six velocities
(vx1, vy1, w1, vx2, vy2, w2): b = sum over i <= j of Q_ij u_i u_j. Each coefficient is measured
from the kernel by polarization (Q_ii = b(e_i), Q_ij = (b(e_i + e_j) - b(e_i) - b(e_j))/2) and
compared with the same from ``oracle.oracle_bias``, on states where every feature is off its
body's centre of mass (so the w1^2 term of an off-centre arc, zero for a disc, is non-zero).
A failing test names the term, e.g. ``test_bias_term[circle_circle-full-w1^2]``; terms that are
exactly zero (for a straight edge: everything without w2) must stay zero.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import oracle as O
import pytest

EPS = float(np.finfo(float).eps)
C_TOL = 64.0  # polarization combines three kernel calls: 3x the C_TOL of the direct tests
PAIRS = list(itertools.combinations_with_replacement(range(6), 2))
TERMS = [
    (case, variant, i, j)
    for case in O.CASES
    for variant in ("full", "static2")
    for i, j in PAIRS
    if variant == "full" or j < 3  # body 2 fixed: no body-2 velocity
]


def _term_name(i: int, j: int) -> str:
    a, b = O.VELOCITY[i], O.VELOCITY[j]
    return f"{a}^2" if i == j else f"{a}*{b}"


def _states(case: str) -> list[dict[str, float]]:
    """Two states (body 2's circle convex and concave) with features ~1 from their centres of
    mass, body 1's feature close to contact, generic angles, zero motion."""
    rng = np.random.default_rng([31, O.CASES.index(case)])
    out = []
    for r2 in (0.7, -2.5):
        th1, th2 = rng.uniform(-math.pi, math.pi, 2)
        f1 = rng.uniform(0.5, 1.0) * np.array([math.cos(a := rng.uniform(0, 6.3)), math.sin(a)])
        f2 = rng.uniform(0.5, 1.0) * np.array([math.cos(a := rng.uniform(0, 6.3)), math.sin(a)])
        s = {k: 0.0 for k in O.VELOCITY + O.ACCELERATION}
        s.update(x2=0.3, y2=-0.2, th1=th1, th2=th2)
        w2 = np.array([0.3, -0.2]) + _rot(th2, f2)
        r1 = 0.4
        if case.endswith("edge"):
            phi = rng.uniform(0, 6.3)
            s.update(ex2=f2[0], ey2=f2[1], nx2=math.cos(phi), ny2=math.sin(phi))
            normal = _rot(th2, np.array([math.cos(phi), math.sin(phi)]))
            feature = w2 + (r1 + 0.01) * normal + 0.8 * np.array([-normal[1], normal[0]])
        else:
            s["cx2"], s["cy2"], s["r2"] = f2[0], f2[1], r2
            rho = r1 + r2 if r2 > 0 else abs(r2) - r1
            phi = rng.uniform(0, 6.3)
            feature = w2 + 1.01 * rho * np.array([math.cos(phi), math.sin(phi)])
        if case.startswith("vertex"):
            s.update(px1=f1[0], py1=f1[1])
        else:
            s.update(cx1=f1[0], cy1=f1[1], r1=r1)
        x1 = feature - _rot(th1, f1)
        s.update(x1=float(x1[0]), y1=float(x1[1]))
        out.append({k: float(v) for k, v in s.items()})
    return out if case.endswith("circle") else out[:1]


def _rot(th: float, p: np.ndarray) -> np.ndarray:
    c, s = math.cos(th), math.sin(th)
    return np.array([c * p[0] - s * p[1], s * p[0] + c * p[1]])


def _with(state: dict, keys: tuple[str, ...]) -> dict:
    out = dict(state)
    for k in keys:
        out[k] = out[k] + 1.0
    return out


def _polarized(b, state: dict, i: int, j: int):
    ei, ej = O.VELOCITY[i], O.VELOCITY[j]
    if i == j:
        return b(_with(state, (ei,)))
    return (b(_with(state, (ei, ej))) - b(_with(state, (ei,))) - b(_with(state, (ej,)))) / 2


@pytest.mark.parametrize(
    ("case", "variant", "i", "j"),
    TERMS,
    ids=[f"{c}-{v}-{_term_name(i, j)}" for c, v, i, j in TERMS],
)
def test_bias_term(case, variant, i, j):
    module = O.kernel_module(case)
    if module is None:
        pytest.skip(f"generated/{case}.py does not exist yet")
    static2 = variant == "static2"
    name = "bias_static2" if static2 else "bias"

    def kernel(s):
        return float(O.call_kernel(module, name, O.full_state(case, s)))

    def oracle(s):
        return O.oracle_bias(case, s, static2=static2)

    for state in _states(case):
        got, want = _polarized(kernel, state, i, j), _polarized(oracle, state, i, j)
        both = _with(state, (O.VELOCITY[i], O.VELOCITY[j]))
        scale = O.error_scales(case, both, static2=static2)["bias"]
        tol = C_TOL * EPS * (abs(float(want)) + scale) + 4 * O.ABS_ERROR
        assert abs(got - float(want)) <= tol, (
            f"{case}.{name}: the {_term_name(i, j)} coefficient is {got!r}, the oracle's "
            f"{float(want)!r} (r2 = {state.get('r2')})"
        )
