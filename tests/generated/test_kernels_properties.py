"""Hypothesis property tests of the generated kernels (generated/<case>.py).

States are drawn with every magnitude spread over six orders (lengths, radii, velocities,
accelerations from 1e-3 to 1e3, either sign, zeros included); body 1's feature is placed at a
distance 1e-3..1e3 from body 2's circle centre or edge point, so the state is always valid
(never exactly at a circle centre). Errors are judged against the float64 error model of
``oracle.error_scales``: ``|error| <= C_TOL * eps * (|value| + S)``.
"""

from __future__ import annotations

import math

import numpy as np
import oracle as O
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

EPS = float(np.finfo(float).eps)
C_TOL = 16.0
KERNELS = {case: O.kernel_module(case) for case in O.CASES}
SETTINGS = settings(derandomize=True, max_examples=200, deadline=None, database=None)


def _need(case: str):
    if KERNELS[case] is None:
        pytest.skip(f"generated/{case}.py does not exist yet (derive/ has not emitted it)")
    return KERNELS[case]


# ------------------------------------------------------------------------------------------
# strategies
# ------------------------------------------------------------------------------------------


N_SIGNED = 18  # 12 motion terms, X2, body 2's feature point, body 1's feature point
N_MAGNITUDES = 3  # distance of the features, r1, |r2|
EXPONENT = st.floats(-3.0, 3.0)  # magnitudes 1e-3 .. 1e3: six orders
ANGLE = st.floats(-math.pi, math.pi)


def _rot(th: float, x: float, y: float) -> tuple[float, float]:
    c, s = math.cos(th), math.sin(th)
    return c * x - s * y, s * x + c * y


def _state_from_draws(case: str, draws) -> dict[str, float]:
    """Build a valid state from flat draws (few primitive draws keep Hypothesis fast):
    signed values sign * 10**e (sign 0 gives an exact zero), positive magnitudes 10**e, angles.
    Body 1's feature is put at distance 10**e from body 2's circle centre or edge point."""
    signs, exps, mags, angles, r2_sign = draws
    signed = iter(sg * 10.0**e for sg, e in zip(signs, exps, strict=True))
    rho, r1, r2 = (10.0**e for e in mags)
    th1, th2, phi_n, phi_q = angles
    s = {k: next(signed) for k in O.VELOCITY + O.ACCELERATION}
    s.update(th1=th1, th2=th2, x2=next(signed), y2=next(signed))
    fx, fy = next(signed), next(signed)
    wx, wy = _rot(th2, fx, fy)
    if case.endswith("edge"):
        s.update(ex2=fx, ey2=fy, nx2=math.cos(phi_n), ny2=math.sin(phi_n))
    else:
        s.update(cx2=fx, cy2=fy, r2=r2_sign * r2)
    qx, qy = s["x2"] + wx + rho * math.cos(phi_q), s["y2"] + wy + rho * math.sin(phi_q)
    px, py = next(signed), next(signed)
    if case.startswith("vertex"):
        s.update(px1=px, py1=py)
    else:
        s.update(cx1=px, cy1=py, r1=r1)
    rx, ry = _rot(th1, px, py)
    s.update(x1=qx - rx, y1=qy - ry)
    return s


def states(case: str) -> st.SearchStrategy[dict[str, float]]:
    """Valid random states of `case` with every input present, magnitudes over six orders."""
    return st.tuples(
        st.lists(st.integers(-1, 1), min_size=N_SIGNED, max_size=N_SIGNED),
        st.lists(EXPONENT, min_size=N_SIGNED, max_size=N_SIGNED),
        st.lists(EXPONENT, min_size=N_MAGNITUDES, max_size=N_MAGNITUDES),
        st.lists(ANGLE, min_size=4, max_size=4),
        st.sampled_from([-1.0, 1.0]),
    ).map(lambda draws: _state_from_draws(case, draws))


def _outputs(module, state, static2: bool = False) -> dict[str, tuple[float, ...]]:
    """Every function's result as a tuple of floats (the Jacobian has 6 or 3 entries)."""
    out = {}
    for name in O.FUNCTIONS:
        got = O.call_kernel(module, O.kernel_name(module, name, static2), state)
        out[name] = tuple(float(v) for v in (got if isinstance(got, tuple) else (got,)))
    return out


def _scales(case, state, static2=False, absolute=False) -> dict[str, tuple[float, ...]]:
    sc = O.error_scales(case, state, static2=static2, absolute=absolute)
    return {k: v if isinstance(v, tuple) else (v,) for k, v in sc.items()}


CASES = pytest.mark.parametrize("case", O.CASES)
MODES = (False, True)  # full state, body 2 fixed (*_static2)


def _mode_state(state: dict[str, float], static2: bool) -> dict[str, float]:
    return dict(state, **{k: 0.0 for k in O.BODY2_MOTION}) if static2 else state


# ------------------------------------------------------------------------------------------
# properties (each checks the full-state functions and the *_static2 variants)
# ------------------------------------------------------------------------------------------


@CASES
def test_kernels_agree_with_oracle(case):
    """Every function agrees with the mpmath oracle within the float64 error model, over
    magnitudes spanning six orders (the fixed-state tests in test_kernels_vs_oracle.py cover the
    extreme 1e-6/1e6 values; this explores the combinations in between)."""
    module = _need(case)

    @SETTINGS
    @given(states(case))
    def check(state):
        for static2, ora in zip(MODES, O.oracle_values_both(case, state), strict=True):
            scales = _scales(case, state, static2)
            for name, got in _outputs(module, state, static2).items():
                want = ora[name] if isinstance(ora[name], tuple) else (ora[name],)
                for g, w, sc in zip(got, want, scales[name], strict=False):
                    err = abs(O.CTX.mpf(g) - w)
                    tol = C_TOL * EPS * (abs(float(w)) + sc) + O.ABS_ERROR
                    assert err <= tol, (name, static2, g, float(w), sc)

    check()


@CASES
def test_acceleration_is_jacobian_dot_acceleration_plus_bias(case):
    """d'' = J . (ax1, ay1, al1, ax2, ay2, al2) + bias, to rounding: the split the contact solver
    relies on (A from J, b from bias) must reproduce the kernels' own full d''."""
    module = _need(case)

    @SETTINGS
    @given(states(case))
    def check(state):
        for static2 in MODES:
            state = _mode_state(state, static2)
            accel = O.ACCELERATION[:3] if static2 else O.ACCELERATION
            out = _outputs(module, state, static2)
            (d2,), (bias,) = out["gap_acceleration"], out["bias"]
            terms = [j * state[a] for j, a in zip(out["jacobian"], accel, strict=True)]
            split = math.fsum(terms)
            scale = _scales(case, state, static2)["gap_acceleration"][0]
            tol = C_TOL * EPS * (abs(d2) + scale)
            assert abs(d2 - split - bias) <= tol, (static2, d2, split, bias)

    check()


@CASES
def test_translation_invariance(case):
    """Adding 1e3 to x1 and x2 (and -1e3 to y1, y2) moves both bodies rigidly: every output is
    unchanged up to the rounding of the shifted coordinates (eps * 1e3 in the positions, hence
    the error model with absolute coordinates)."""
    module = _need(case)

    @SETTINGS
    @given(states(case))
    def check(state):
        moved = dict(state, x1=state["x1"] + 1e3, x2=state["x2"] + 1e3)
        moved.update(y1=state["y1"] - 1e3, y2=state["y2"] - 1e3)
        for static2 in MODES:
            scales = _scales(case, moved, static2, absolute=True)
            base, shifted = _outputs(module, state, static2), _outputs(module, moved, static2)
            for name in O.FUNCTIONS:
                for a, b, sc in zip(base[name], shifted[name], scales[name], strict=False):
                    assert abs(a - b) <= C_TOL * EPS * (abs(a) + sc), (name, static2, a, b, sc)

    check()


@CASES
def test_vectorised_equals_scalar_calls(case):
    """Calling with arrays of N states gives, bitwise, the N scalar results with shape (N,);
    geometry passed as scalars broadcasts against array poses and motion the same way. (The
    runtime evaluates all contacts in one call; a contact must not change value with the batch.)"""
    module = _need(case)

    @SETTINGS
    @given(st.lists(states(case), min_size=1, max_size=6))
    def check(batch):
        shared = [dict(s, **{k: batch[0][k] for k in O.GEOMETRY[case]}) for s in batch]
        for group, scalar_geometry in ((batch, False), (shared, True)):
            arrays = {k: np.array([s[k] for s in group]) for k in O.state_keys(case)}
            if scalar_geometry:
                arrays.update({k: group[0][k] for k in O.GEOMETRY[case]})
            for static2 in MODES:
                for name in O.FUNCTIONS:
                    kname = O.kernel_name(module, name, static2)
                    vec = O.call_kernel(module, kname, arrays)
                    vec = vec if isinstance(vec, tuple) else (vec,)
                    for entry in vec:
                        assert np.shape(entry) == (len(group),), (kname, np.shape(entry))
                    for i, s in enumerate(group):
                        one = O.call_kernel(module, kname, s)
                        one = one if isinstance(one, tuple) else (one,)
                        for k, (v, o) in enumerate(zip(vec, one, strict=True)):
                            assert v[i] == o, (kname, k, i, float(v[i]), float(o), s)

    check()


@CASES
def test_no_nan_or_inf_for_valid_states(case):
    """Every output is finite for every valid state (body 1's feature not at a circle centre),
    including zero velocities, zero accelerations and zero levers."""
    module = _need(case)

    @SETTINGS
    @given(states(case))
    def check(state):
        for static2 in MODES:
            for name, got in _outputs(module, state, static2).items():
                assert all(math.isfinite(v) for v in got), (name, static2, got)

    check()


@CASES
def test_vectorised_equals_scalar_calls_large_batch(case):
    """The same bitwise property on one batch of 300 states drawn with NumPy (fixed seed) over
    the same six-order ranges: Hypothesis favours simple values (0, +-1, powers of ten) on which
    rounding differences between the array and scalar code paths of NumPy rarely show."""
    module = _need(case)
    rng = np.random.default_rng([99, O.CASES.index(case)])
    batch = [
        _state_from_draws(
            case,
            (
                rng.integers(-1, 2, N_SIGNED),
                rng.uniform(-3, 3, N_SIGNED),
                rng.uniform(-3, 3, N_MAGNITUDES),
                rng.uniform(-math.pi, math.pi, 4),
                rng.choice([-1.0, 1.0]),
            ),
        )
        for _ in range(300)
    ]
    arrays = {k: np.array([s[k] for s in batch]) for k in O.state_keys(case)}
    mismatches = []
    for static2 in MODES:
        for name in O.FUNCTIONS:
            kname = O.kernel_name(module, name, static2)
            vec = O.call_kernel(module, kname, arrays)
            vec = vec if isinstance(vec, tuple) else (vec,)
            for i, s in enumerate(batch):
                one = O.call_kernel(module, kname, s)
                one = one if isinstance(one, tuple) else (one,)
                for k, (v, o) in enumerate(zip(vec, one, strict=True)):
                    if v[i] != o:
                        mismatches.append((kname, k, i, float(v[i]), float(o)))
    assert not mismatches, f"{len(mismatches)} array/scalar mismatches, e.g. {mismatches[:3]}"
