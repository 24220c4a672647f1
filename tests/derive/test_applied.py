"""The applied forces (derive/applied.py, generated/spring.py, mutual_gravity.py, body_damping.py):
their proofs hold and catch the bugs they claim to exclude, and the emitted kernels -- the code
the runtime runs, which the symbolic proofs do not see -- agree with an oracle written here:

* the textbook forms typed again in NumPy (Hooke's force along the unit vector with torques
  r x F about each centre, Newton's G m1 m2 / r^2, -k m v and -k I w);
* minus the central-difference gradient of the emitted potential (so run.energy is the energy
  the forces conserve);
* a spring whose anchors coincide: a finite zero force, no warning.
"""

import dataclasses
import functools
import warnings

import numpy as np
import pytest

import generated.body_damping as damping_kernels
import generated.mutual_gravity as gravity_kernels
import generated.spring as spring_kernels
from derive.applied import ALL_APPLIED, derive_applied
from derive.applied_proofs import applied_proofs, textbook

TEXTBOOK = "equal the textbook form"
GRADIENT = "minus its gradient"
POWER = "the power of the forces"
KINDS = (TEXTBOOK, GRADIENT, POWER)


@functools.cache
def _derived(name: str):
    return derive_applied(ALL_APPLIED[name]())


def _failing(a) -> set[str]:
    failed = [p.statement for p in applied_proofs(a) if not p.holds]
    return {kind for kind in KINDS if any(kind in s for s in failed)}


@pytest.mark.parametrize("name", ["mutual_gravity", "body_damping", "spring"])
def test_applied_proofs_hold_and_cover_every_claim(name):
    found = applied_proofs(_derived(name))
    assert all(p.holds for p in found), [p.statement for p in found if not p.holds]
    assert {k for k in KINDS for p in found if k in p.statement} == set(KINDS)


def test_a_wrong_torque_lever_is_caught():
    """Body 2's spring torque about body 1's centre (its lever l1 for l2): Hooke's form fails."""
    a = _derived("spring")
    tau2 = a.forces[5].xreplace({sym: other for sym, other in _lever_swap(a).items()})
    wrong = dataclasses.replace(a, forces=(*a.forces[:5], tau2))
    assert not textbook(wrong).holds


def _lever_swap(a):
    names = {str(s): s for s, _ in a.intermediates}
    return {names["l2_x"]: names["l1_x"], names["l2_y"]: names["l1_y"]}


def test_a_potential_off_by_a_factor_is_caught():
    a = _derived("mutual_gravity")
    assert _failing(dataclasses.replace(a, potential=2 * a.potential)) == {GRADIENT, POWER}


def test_a_damping_force_without_the_mass_is_caught():
    """-k v where -k m v is meant (the acceleration typed as the force)."""
    a = _derived("body_damping")
    m1 = next(s for s in a.forces[0].free_symbols if str(s) == "m1")
    wrong = dataclasses.replace(a, forces=tuple(f.xreplace({m1: 1}) for f in a.forces))
    assert _failing(wrong) == {TEXTBOOK, POWER}


# ------------------------------------------------------------------------------------------
# the emitted kernels against a NumPy oracle
# ------------------------------------------------------------------------------------------

RNG = np.random.default_rng(16)
N = 200


def _states(n: int = N) -> dict[str, np.ndarray]:
    names = ("x1", "y1", "th1", "vx1", "vy1", "w1", "x2", "y2", "th2", "vx2", "vy2", "w2")
    state = {k: RNG.uniform(-2.0, 2.0, n) for k in names}
    state.update({k: RNG.uniform(-0.5, 0.5, n) for k in ("px1", "py1", "px2", "py2")})
    state.update(rest_length=RNG.uniform(0.1, 1.0, n), stiffness=RNG.uniform(1.0, 100.0, n))
    state.update(damping=RNG.uniform(0.0, 5.0, n), G=RNG.uniform(0.1, 2.0, n))
    state.update(m1=RNG.uniform(0.5, 3.0, n), m2=RNG.uniform(0.5, 3.0, n))
    state.update(
        i1=RNG.uniform(0.01, 1.0, n), k_lin=RNG.uniform(0, 2, n), k_ang=RNG.uniform(0, 2, n)
    )
    return state


def _call(module, function: str, values: dict) -> np.ndarray:
    out = getattr(module, function)(**{a: values[a] for a in module.ARGUMENTS[function]})
    return np.array(np.broadcast_arrays(*out) if isinstance(out, tuple) else out)


def _rotate(th, px, py):
    return np.array([np.cos(th) * px - np.sin(th) * py, np.sin(th) * px + np.cos(th) * py])


def _hooke(st) -> np.ndarray:
    """Force and torque on each body of a spring with a dashpot, by the textbook."""
    r1, r2 = _rotate(st["th1"], st["px1"], st["py1"]), _rotate(st["th2"], st["px2"], st["py2"])
    s = np.array([st["x1"], st["y1"]]) + r1 - np.array([st["x2"], st["y2"]]) - r2
    u1 = np.array([st["vx1"], st["vy1"]]) + st["w1"] * np.array([-r1[1], r1[0]])
    u2 = np.array([st["vx2"], st["vy2"]]) + st["w2"] * np.array([-r2[1], r2[0]])
    length = np.hypot(*s)
    n = s / length
    tension = st["stiffness"] * (length - st["rest_length"]) + st["damping"] * np.sum(
        n * (u1 - u2), axis=0
    )
    f = -tension * n
    return np.array([f[0], f[1], r1[0] * f[1] - r1[1] * f[0],
                     -f[0], -f[1], -(r2[0] * f[1] - r2[1] * f[0])])  # fmt: skip


def test_spring_kernels_are_hookes_force_with_torques_about_each_centre():
    st = _states()
    expected = _hooke(st)
    assert np.allclose(_call(spring_kernels, "force", st), expected, rtol=1e-12, atol=1e-12)
    still = {**st, "vx2": 0.0 * st["vx2"], "vy2": 0.0 * st["vy2"], "w2": 0.0 * st["w2"]}
    got = _call(spring_kernels, "force_static2", still)
    assert np.allclose(got, _hooke(still)[:3], rtol=1e-12, atol=1e-12)


def test_mutual_gravity_kernel_is_newtons_attraction():
    st = _states()
    apart = np.array([st["x2"] - st["x1"], st["y2"] - st["y1"]])
    r = np.hypot(*apart)
    pull = st["G"] * st["m1"] * st["m2"] / r**2 * apart / r
    zero = np.zeros(N)
    expected = np.array([pull[0], pull[1], zero, -pull[0], -pull[1], zero])
    assert np.allclose(_call(gravity_kernels, "force", st), expected, rtol=1e-12, atol=0)


def test_body_damping_kernel_is_minus_k_m_v():
    st = _states()
    expected = np.array([-st["k_lin"] * st["m1"] * st["vx1"], -st["k_lin"] * st["m1"] * st["vy1"],
                         -st["k_ang"] * st["i1"] * st["w1"]])  # fmt: skip
    assert np.allclose(_call(damping_kernels, "force", st), expected, rtol=1e-14, atol=0)


@pytest.mark.parametrize("module", [spring_kernels, gravity_kernels], ids=["spring", "gravity"])
def test_forces_at_rest_are_minus_the_gradient_of_the_emitted_potential(module):
    st = _states()
    st.update({k: 0.0 * st[k] for k in ("vx1", "vy1", "w1", "vx2", "vy2", "w2")})
    force = _call(module, "force", st)
    h = 1e-6
    for k, q in enumerate(("x1", "y1", "th1", "x2", "y2", "th2")):
        if q not in module.ARGUMENTS["potential"]:
            assert np.all(force[k] == 0.0)
            continue
        up, down = {**st, q: st[q] + h}, {**st, q: st[q] - h}
        slope = (_call(module, "potential", up) - _call(module, "potential", down)) / (2 * h)
        scale = np.abs(force[k]) + np.abs(force).max(axis=0)
        assert np.all(np.abs(force[k] + slope) < 1e-7 * scale), (
            q,
            np.max(np.abs(force[k] + slope)),
        )


def test_spring_with_coincident_anchors_pulls_with_no_force_and_no_warning():
    st = {k: v[:3] for k, v in _states().items()}
    st.update(x1=st["x2"].copy(), y1=st["y2"].copy(), th1=st["th2"].copy())
    st.update(px1=st["px2"].copy(), py1=st["py2"].copy())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        force = _call(spring_kernels, "force", st)
        energy = _call(spring_kernels, "potential", st)
    assert np.array_equal(force, np.zeros_like(force))
    assert np.allclose(energy, 0.5 * st["stiffness"] * st["rest_length"] ** 2, rtol=1e-15)
