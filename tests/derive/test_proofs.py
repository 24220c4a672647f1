"""The proofs hold for the derivation, and each fails on the bug it claims to exclude.

The reference (derive/reference.py) is independent of the derivation; here the proofs are run on
deliberately wrong derivations (the sign of a centripetal term, a dropped velocity term, a bias
that keeps an acceleration, a wrong lever, a transposed rotation in the kinematics) and must
name what is wrong. The zero test behind every proof is checked on its own as well.
"""

import dataclasses
import functools

import pytest
import sympy as sp

from derive import kinematics, proofs
from derive.cases import ALL_CASES, SIGMA2
from derive.derivation import ACCELERATION, V_TAN, derive
from derive.reference import sym

WHOLE = "the whole d''"
BIAS = "the bias (b term)"
JACOBIAN = "the Jacobian row J"
LEVERS = "J = (n, R1 x n"
NOTE = "(note eq."
KINDS = (WHOLE, BIAS, JACOBIAN, LEVERS, NOTE)


@functools.cache
def _derive(case: str):
    return derive(ALL_CASES[case]())


@pytest.fixture(params=sorted(ALL_CASES))
def derived(request):
    return _derive(request.param)


def _failing(d) -> set[str]:
    """Which kinds of proof fail (by the words of their statements above)."""
    failed = [p.statement for p in proofs.proofs_for(d) if not p.holds]
    return {kind for kind in KINDS if any(kind in s for s in failed)}


def test_every_proof_holds(derived):
    found = proofs.proofs_for(derived)
    assert {kind for kind in KINDS for p in found if kind in p.statement} == set(KINDS)
    failing = [p.statement for p in found if not p.holds]
    assert not failing, failing


def _flip(expr: sp.Expr, term: sp.Expr) -> sp.Expr:
    """expr with the sign of `term` flipped (term must appear as a product factor)."""
    return expr.subs(term, -term)


@pytest.mark.parametrize("case", ["vertex_circle", "circle_circle"])
def test_centripetal_sign_flip_is_caught(case):
    """The v_tan^2/|v| term of a circular edge (the centripetal part of d'', sigma w^2 r at a
    rolling contact) with the wrong sign: the whole-d'', bias and note proofs fail."""
    d = _derive(case)
    wrong = dataclasses.replace(d, gap_acceleration=_flip(d.gap_acceleration, V_TAN**2))
    assert wrong.gap_acceleration != d.gap_acceleration
    assert _failing(wrong) == {WHOLE, BIAS, NOTE}


@pytest.mark.parametrize("case", ["vertex_edge", "circle_edge"])
def test_dropped_velocity_term_is_caught(case):
    """d'' of a straight edge without its 2 n'.v' term (the note's factor 2 lost): caught."""
    d = _derive(case)
    nx_t, ny_t, vx_t, vy_t = map(sym, ("n_x_t", "n_y_t", "v_x_t", "v_y_t"))
    dropped = sp.expand(d.gap_acceleration - (nx_t * vx_t + ny_t * vy_t))
    assert sp.expand(d.gap_acceleration - dropped - (nx_t * vx_t + ny_t * vy_t)) == 0
    wrong = dataclasses.replace(d, gap_acceleration=dropped)
    assert _failing(wrong) == {WHOLE, BIAS, NOTE}


@pytest.mark.parametrize("case", ["vertex_edge", "circle_circle"])
def test_bias_that_keeps_an_acceleration_is_caught(case):
    """A bias formed with only body 1's accelerations zeroed: only the bias proof fails."""
    d = _derive(case)
    wrong = dataclasses.replace(d)
    wrong.__dict__["bias"] = d.with_state({a: 0 for a in ACCELERATION[:3]})
    assert _failing(wrong) == {BIAS}


@pytest.mark.parametrize("case", ["circle_edge", "vertex_circle"])
def test_jacobian_with_a_wrong_lever_is_caught(case):
    """J with body 2's torque lever negated: the Jacobian and lever proofs fail."""
    d = _derive(case)
    wrong = dataclasses.replace(d)
    wrong.__dict__["jacobian"] = (*d.jacobian[:5], -d.jacobian[5])
    assert _failing(wrong) == {JACOBIAN, LEVERS}


def test_transposed_rotation_in_the_kinematics_is_caught(monkeypatch):
    """A derivation whose body points turn by R(-th): consistent with itself (the Jacobian is
    still its own gradient), but not with the reference's motion, so every proof against the
    reference fails."""

    def transposed(self, vx, vy):
        c, s = sp.cos(self.th), sp.sin(self.th)
        return sp.Matrix([c * vx + s * vy, -s * vx + c * vy])

    monkeypatch.setattr(kinematics.PlanarBody, "rotate", transposed)
    wrong = derive(ALL_CASES["circle_circle"]())
    assert _failing(wrong) >= {WHOLE, BIAS, JACOBIAN, LEVERS}


def test_zero_test_on_known_identities():
    """Identities over angles and square roots reduce to zero; near misses do not."""
    th1, x1, x2, r2 = sym("th1"), sym("x1"), sym("x2"), sym("r2")
    c, s = sp.cos(th1), sp.sin(th1)
    radicand = (x1 - x2 + c) ** 2 + s**2
    assert proofs.is_zero(c**4 + 2 * c**2 * s**2 + s**4 - 1)
    assert proofs.is_zero(sp.sqrt(4 * sp.expand(radicand)) - 2 * sp.sqrt(radicand))
    assert proofs.is_zero(sp.sqrt(radicand) ** 3 / radicand - sp.sqrt(radicand))
    assert proofs.is_zero(sp.sign(r2) ** 3 - SIGMA2)
    assert not proofs.is_zero(c**4 + s**4 - 1)
    assert not proofs.is_zero(sp.sqrt(radicand) - sp.sqrt(radicand + s**2))
    assert not proofs.is_zero(sp.sqrt(radicand) - (x1 - x2 + c))
