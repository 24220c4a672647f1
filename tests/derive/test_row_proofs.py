"""The friction and joint proofs hold, and each fails on the bug it claims to exclude.

As tests/derive/test_proofs.py does for the normal rows: the proofs of derive/friction_proofs.py
and derive/joint_proofs.py are run on deliberately wrong derivations (a friction lever with the
wrong sign of the radius, a wrong torque lever in a row, a bias that keeps an acceleration, a
distance joint's d'' without its centripetal term) and must name what is wrong.
"""

import dataclasses
import functools

import sympy as sp

from derive.cases import ALL_CASES, R1
from derive.derivation import ACCELERATION
from derive.friction import tangential
from derive.friction_proofs import friction_proofs
from derive.joint_proofs import joint_proofs
from derive.joints import ALL_JOINTS, S_TAN, derive_joint

RATES = "v_t and d/dt v_t equal"
T_BIAS = "the tangential bias"
T_JACOBIAN = "the tangential Jacobian row J_t"
T_LEVERS = "J_t = (t, R1 x t"
ROLLING = "rolling condition"
FRICTION_KINDS = (RATES, T_BIAS, T_JACOBIAN, T_LEVERS, ROLLING)

ROWS = "d, d' and the whole d''"
J_BIAS = "the bias equals"
J_JACOBIAN = "each Jacobian row"
J_LEVERS = "J = (e, R1 x e"
JOINT_KINDS = (ROWS, J_BIAS, J_JACOBIAN, J_LEVERS)


@functools.cache
def _friction(case: str):
    return tangential(ALL_CASES[case]())


@functools.cache
def _joint(name: str):
    return derive_joint(ALL_JOINTS[name]())


def _failing(found, kinds) -> set[str]:
    failed = [p.statement for p in found if not p.holds]
    return {kind for kind in kinds if any(kind in s for s in failed)}


def _friction_failing(case: str, f) -> set[str]:
    return _failing(friction_proofs(ALL_CASES[case](), f), FRICTION_KINDS)


def _joint_failing(name: str, j) -> set[str]:
    return _failing(joint_proofs(ALL_JOINTS[name](), j), JOINT_KINDS)


def test_friction_proofs_hold_and_cover_every_claim():
    found = friction_proofs(ALL_CASES["circle_edge"](), _friction("circle_edge"))
    assert {k for k in FRICTION_KINDS for p in found if k in p.statement} == set(FRICTION_KINDS)
    assert all(p.holds for p in found), [p.statement for p in found if not p.holds]


def test_friction_lever_with_the_wrong_radius_sign_is_caught():
    """v_t of a rolling circle with w1 (L1.n + r1) in place of w1 (L1.n - r1): the lever of the
    circle's centre, not of its contact point. The exact-rate, rolling and variant proofs (the
    *_static2 v_t comes from the same expression) fail."""
    f = _friction("circle_edge")
    vt = f.values["tangent_velocity"][0]
    w1 = sp.Symbol("w1", real=True)
    wrong_vt = sp.expand(vt + 2 * w1 * R1)
    assert wrong_vt != sp.expand(vt)
    wrong = dataclasses.replace(f, values={**f.values, "tangent_velocity": (wrong_vt,)})
    assert _friction_failing("circle_edge", wrong) == {RATES, T_BIAS, ROLLING}


def test_friction_row_with_a_wrong_lever_is_caught(case="circle_circle"):
    """J_t with body 2's torque lever negated: the Jacobian and lever proofs fail."""
    f = _friction(case)
    wrong = dataclasses.replace(f)
    row = f.jacobian[0]
    wrong.__dict__["jacobian"] = ((*row[:5], -row[5]),)
    assert _friction_failing(case, wrong) == {T_JACOBIAN, T_LEVERS}


def test_friction_bias_that_keeps_an_acceleration_is_caught():
    """A tangential bias with only body 1's accelerations zeroed: only the bias proof fails."""
    f = _friction("vertex_edge")
    wrong = dataclasses.replace(f)
    wrong.__dict__["bias"] = f.with_state({a: 0 for a in ACCELERATION[:3]})
    assert _friction_failing("vertex_edge", wrong) == {T_BIAS}


def test_joint_proofs_hold_and_cover_every_claim():
    for name in ALL_JOINTS:
        found = joint_proofs(ALL_JOINTS[name](), _joint(name))
        assert {k for k in JOINT_KINDS for p in found if k in p.statement} == set(JOINT_KINDS)
        assert all(p.holds for p in found), [p.statement for p in found if not p.holds]


def test_distance_joint_without_its_centripetal_term_is_caught():
    """d'' = s.s''/|s| (the s_tan^2/|s| term dropped): the d'' and bias proofs fail."""
    j = _joint("distance_joint")
    (d2,) = j.values["gap_acceleration"]
    dropped = d2.subs(S_TAN, 0)
    assert dropped != d2
    wrong = dataclasses.replace(j, values={**j.values, "gap_acceleration": (dropped,)})
    assert _joint_failing("distance_joint", wrong) == {ROWS, J_BIAS}


def test_pin_row_with_a_wrong_lever_is_caught():
    """The pin's y row with body 1's torque lever negated: the Jacobian and lever proofs fail."""
    j = _joint("pin_joint")
    wrong = dataclasses.replace(j)
    x_row, y_row = j.jacobian
    wrong.__dict__["jacobian"] = (x_row, (*y_row[:2], -y_row[2], *y_row[3:]))
    assert _joint_failing("pin_joint", wrong) == {J_JACOBIAN, J_LEVERS}
