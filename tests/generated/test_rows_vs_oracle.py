"""The generated friction and joint kernels against the independent mpmath oracle
(tests/oracle_rows.py).

1. The oracle itself, against motions whose v_t, d, d', d'' are known in closed form (a wheel
   rolling on a floor, a disc sliding without spin, two spinning discs, a pendulum on a rod, a
   body turning about its pin).
2. Every function (and the ``*_static2`` variants) against the oracle on random states (fixed
   seed; not contact preserving: gaps of both signs) and hard states (radii 1e-6 / 1e6, body 2
   concave, |w| up to 1e3, coordinates ~1e4; joints: anchors 1e-6 / 1e6 from the centres of
   mass, nearly coincident anchors of a distance joint). Pass criterion as for the normal rows:
   ``|kernel - oracle| <= C * eps * (|oracle| + S)`` with S the magnitude of the terms
   (oracle_rows.friction_scales, joint_scales).
"""

from __future__ import annotations

import functools
import importlib
import math

import numpy as np
import oracle as O
import oracle_rows as R
import pytest
from test_kernels_vs_oracle import hard_states, random_states

EPS = float(np.finfo(float).eps)
C_TOL = 16.0


def _zero_motion() -> dict[str, float]:
    return {k: 0.0 for k in O.VELOCITY + O.ACCELERATION}


def _close(value, expected, tol=1e-40) -> bool:
    return abs(value - expected) <= tol * (1 + abs(expected))


# ------------------------------------------------------------------------------------------
# 1. the oracle against closed forms
# ------------------------------------------------------------------------------------------


def test_oracle_wheel_rolling_and_sliding_on_a_floor():
    """A wheel of radius r on the fixed floor y = 0 (n = +y, t = -x), its centre moving at v:
    rolling (w = -v/r) has v_t = 0 and d/dt v_t = 0; without spin it slides with v_t = -v;
    spinning in place at w its lowest point moves at w r along +x, so v_t = -w r. The row is
    (t, R1 x t, -t, -R2 x t) = (-1, 0, -r, 1, 0, 0) (body 2's contact point (0.75, 0) is on
    the line of t through its centre)."""
    r, v = 0.5, 2.0
    s = _zero_motion()
    s.update(x2=0.0, y2=0.0, th2=0.0, ex2=0.0, ey2=0.0, nx2=0.0, ny2=1.0)
    s.update(cx1=0.0, cy1=0.0, r1=r, th1=0.3, x1=0.75, y1=r, vx1=v, w1=-v / r)
    rolling = R.friction_values("circle_edge", s)
    assert _close(rolling["tangent_velocity"], 0) and _close(rolling["tangent_acceleration"], 0)
    row = rolling["tangent_jacobian"]
    assert all(_close(a, b) for a, b in zip(row, (-1, 0, -r, 1, 0, 0), strict=True))
    s.update(w1=0.0)
    assert _close(R.friction_values("circle_edge", s)["tangent_velocity"], -v)
    s.update(vx1=0.0, w1=3.0)
    assert _close(R.friction_values("circle_edge", s)["tangent_velocity"], -3.0 * r)


def test_oracle_two_spinning_discs():
    """Discs of radii r1, r2 touching, centres at rest, spinning at w1, w2: v_t = -w1 r1 - w2 r2
    (zero for gears turning together, w1 r1 = -w2 r2); a disc spinning in place at the bottom
    of a fixed bowl (r2 < 0): v_t = -w1 r1."""
    s = _zero_motion()
    s.update(x1=0.0, y1=0.0, th1=0.2, cx1=0.0, cy1=0.0, r1=0.5, w1=3.0)
    s.update(x2=-1.25, y2=0.0, th2=-0.4, cx2=0.0, cy2=0.0, r2=0.75, w2=-1.0)
    values = R.friction_values("circle_circle", s)
    assert _close(values["tangent_velocity"], -3.0 * 0.5 + 1.0 * 0.75)
    s.update(x2=0.0, y2=1.5, r2=-2.0, w2=0.0)  # body 1 at the bottom of a bowl of radius 2
    assert _close(R.friction_values("circle_circle", s)["tangent_velocity"], -3.0 * 0.5)


def test_oracle_vertex_sliding_along_an_edge():
    """A vertex moving at u along a fixed edge with normal n = (0.6, 0.8): v_t = u.t with
    t = (-0.8, 0.6), whatever the vertex's lever, and d/dt v_t = a.t for an acceleration a."""
    s = _zero_motion()
    s.update(x2=0.0, y2=0.0, th2=0.0, ex2=0.0, ey2=0.0, nx2=0.6, ny2=0.8)
    s.update(x1=1.0, y1=0.5, th1=0.7, px1=0.25, py1=-0.5, vx1=-1.6, vy1=1.2, ax1=0.5, ay1=2.0)
    values = R.friction_values("vertex_edge", s)
    mp = O.CTX.mpf  # the float inputs exactly: 0.6 and 0.8 are not dyadic
    assert _close(values["tangent_velocity"], -mp(0.8) * mp(-1.6) + mp(0.6) * mp(1.2))
    assert _close(values["tangent_acceleration"], -mp(0.8) * mp(0.5) + mp(0.6) * mp(2.0))


def test_oracle_pendulum_on_a_rod():
    """Body 1 (anchor at its centre of mass) circling the world anchor at distance L with speed
    v and centripetal acceleration v^2/L: d = d' = d'' = 0, and the bias (d'' without the
    acceleration) is v^2/L; the Jacobian row is (n, 0, -n, R2 x -n) with n = s/|s|."""
    length, v = 2.0, 3.0  # v^2/L = 4.5 exactly
    s = _zero_motion()
    s.update(x1=length, y1=0.0, th1=0.4, px1=0.0, py1=0.0, vy1=v, ax1=-v * v / length)
    s.update(x2=0.0, y2=0.0, th2=0.0, px2=0.0, py2=0.0, length=length)
    values = R.joint_values("distance_joint", s)
    for name in ("gap", "gap_velocity", "gap_acceleration"):
        assert _close(values[name][0], 0), name
    assert _close(values["bias"][0], O.CTX.mpf(v * v) / length)
    assert all(
        _close(a, b) for a, b in zip(values["jacobian"][0], (1, 0, 0, -1, 0, 0), strict=True)
    )


def test_oracle_body_turning_about_its_pin():
    """Body 1 pinned to the world at its anchor a1 = (0.5, 0) and turning at w about it (so its
    centre moves): both pin rows stay 0 with d' = d'' = 0; at rest but off by (0.1, -0.2) the rows
    are that separation; the Jacobian rows are (1, 0, -R1_y, -1, 0, R2_y), (0, 1, R1_x, 0, -1,
    -R2_x)."""
    w, th = 3.0, 0.0
    s = _zero_motion()
    s.update(px1=0.5, py1=0.0, px2=1.0, py2=2.0, th1=th, w1=w)
    s.update(x1=1.0 - 0.5, y1=2.0, x2=0.0, y2=0.0, th2=0.0)
    # the anchor X1 + R(th) a1 fixed: V1 = -w k x R a1 = (0, -w 0.5), A1 = w^2 R a1 = (w^2 0.5, 0)
    s.update(vy1=-w * 0.5, ax1=w * w * 0.5)
    values = R.joint_values("pin_joint", s)
    for name in ("gap", "gap_velocity", "gap_acceleration"):
        assert all(_close(x, 0) for x in values[name]), name
    assert all(
        _close(a, b) for a, b in zip(values["jacobian"][0], (1, 0, 0, -1, 0, 2.0), strict=True)
    )
    assert all(
        _close(a, b) for a, b in zip(values["jacobian"][1], (0, 1, 0.5, 0, -1, -1.0), strict=True)
    )
    s.update(x1=0.6, y1=1.8)
    assert [float(x) for x in R.joint_values("pin_joint", s)["gap"]] == pytest.approx([0.1, -0.2])


# ------------------------------------------------------------------------------------------
# 2. the kernels against the oracle
# ------------------------------------------------------------------------------------------


def _module(name: str):
    return importlib.import_module(f"generated.{name}")


def _error(got, want, scale) -> float:
    g = float(got)
    if not math.isfinite(g):
        return math.inf
    diff = max(float(abs(O.CTX.mpf(g) - want)) - O.ABS_ERROR, 0.0)
    return diff / (EPS * (abs(float(want)) + scale)) if diff else 0.0


def _friction_errors(case: str, state, static2: bool) -> dict[str, float]:
    module = _module(f"{case}_friction")
    want = R.friction_values(case, state, static2=static2)
    scales = R.friction_scales(case, state, static2=static2)
    out = {}
    for name in R.FRICTION_FUNCTIONS:
        got = O.call_kernel(module, name + ("_static2" if static2 else ""), state)
        if name == "tangent_jacobian":
            n = 3 if static2 else 6
            assert len(got) == n
            out[name] = max(map(_error, got, want[name][:n], scales[name][:n]))
        else:
            out[name] = _error(got, want[name], scales[name])
    return out


@functools.cache
def _friction_table(case: str, which: str, static2: bool) -> dict[str, float]:
    states = {"random": random_states(case, 25), "hard": hard_states(case, reps=1)}[which]
    worst = dict.fromkeys(R.FRICTION_FUNCTIONS, 0.0)
    for state in states:
        for name, err in _friction_errors(case, state, static2).items():
            worst[name] = max(worst[name], err)
    return worst


@pytest.mark.parametrize("static2", [False, True], ids=["moving", "static2"])
@pytest.mark.parametrize("which", ["random", "hard"])
@pytest.mark.parametrize("case", O.CASES)
def test_friction_kernels_match_the_oracle(case, which, static2):
    table = _friction_table(case, which, static2)
    bad = {k: v for k, v in table.items() if not v <= C_TOL}
    assert not bad, f"{case}_friction {which}: errors / (eps (|v| + S)) {bad}"


def _joint_states(joint: str, which: str) -> list[dict[str, float]]:
    rng = np.random.default_rng([4242, R.JOINTS.index(joint), ["random", "hard"].index(which)])
    out = []
    for k in range(24):
        lever = 10 ** rng.uniform(-1, 0.5) if which == "random" else [1e-6, 1e6][k % 2]
        offset = 0.0 if which == "random" else [0.0, 1e4][(k // 2) % 2]
        omega = 2.0 if which == "random" else [1.0, 1e3][(k // 4) % 2]
        s = {"th1": rng.uniform(-np.pi, np.pi), "th2": rng.uniform(-np.pi, np.pi)}
        for key in ("px1", "py1", "px2", "py2"):
            s[key] = lever * rng.normal()
        s["x2"], s["y2"] = offset + rng.normal(size=2)
        s["x1"], s["y1"] = s["x2"] + rng.normal(size=2) * (
            1e-6 if which == "hard" and k > 16 else 1
        )
        for i in (1, 2):
            s[f"vx{i}"], s[f"vy{i}"] = rng.normal(size=2)
            s[f"ax{i}"], s[f"ay{i}"] = rng.normal(size=2)
            s[f"w{i}"], s[f"al{i}"] = omega * rng.normal(size=2)
        s["length"] = rng.uniform(0.1, 3.0)
        out.append({k: float(v) for k, v in s.items()})
    return out


@pytest.mark.parametrize("static2", [False, True], ids=["moving", "static2"])
@pytest.mark.parametrize("which", ["random", "hard"])
@pytest.mark.parametrize("joint", R.JOINTS)
def test_joint_kernels_match_the_oracle(joint, which, static2):
    module = _module(joint)
    worst = dict.fromkeys(R.JOINT_FUNCTIONS, 0.0)
    for state in _joint_states(joint, which):
        want = R.joint_values(joint, state, static2=static2)
        scales = R.joint_scales(joint, state, static2=static2)
        for name in R.JOINT_FUNCTIONS:
            got = O.call_kernel(module, O.kernel_name(module, name, static2), state)
            rows = len(want[name])
            if name == "jacobian":
                n = 3 if static2 else 6
                assert len(got) == rows * n
                errs = [
                    _error(got[r * n + c], want[name][r][c], scales[name][c])
                    for r in range(rows)
                    for c in range(n)
                ]
            else:
                got = got if rows > 1 else (got,)
                errs = [_error(g, w, scales[name]) for g, w in zip(got, want[name], strict=True)]
            worst[name] = max(worst[name], *errs)
    bad = {k: v for k, v in worst.items() if not v <= C_TOL}
    assert not bad, f"{joint} {which}: errors / (eps (|d| + S)) {bad}"
