"""The derivation agrees with the note (eq. 4, 8, 11, 12), J gives the physical levers, and the
zero test behind the proofs does reject a wrong formula (so a proof can fail)."""

import pytest
import sympy as sp

from derive.cases import ALL_CASES, NX2, NY2, PX1, PY1
from derive.derivation import derive
from derive.kinematics import BODY1, BODY2, dot, t, to_state
from derive.proofs import _is_zero, _unit_normal, _vertex_at, proofs_for


@pytest.fixture(scope="module", params=sorted(ALL_CASES))
def derived(request):
    return derive(ALL_CASES[request.param]())


def test_every_proof_holds(derived):
    proofs = proofs_for(derived)
    assert len(proofs) >= 3
    failing = [p.statement for p in proofs if not p.holds]
    assert not failing, failing


def test_jacobian_is_gradient_of_gap(derived):
    """J from d'' (acceleration coefficients) equals dd/dq from the gap itself."""
    gap = derived.in_state_symbols(derived.gap)
    poses = BODY1.pose_symbols() + BODY2.pose_symbols()
    for j, q in zip(derived.jacobian, poses, strict=True):
        assert _is_zero(derived.in_state_symbols(j) - sp.diff(gap, q))


def test_zero_test_rejects_note_formula_with_wrong_factor():
    """Eq. 4 with factor 1 instead of 2 on the velocity term must NOT be proved."""
    d = derive(ALL_CASES["vertex_edge"]())
    q = sp.Matrix([sp.Symbol("qx", real=True), sp.Symbol("qy", real=True)])
    p2 = BODY2.point(q[0], q[1])
    p1 = BODY1.point(PX1, PY1)
    n = BODY2.rotate(NX2, NY2)
    wrong = dot(sp.diff(n, t), sp.diff(p1 - p2, t)) + dot(n, sp.diff(p1 - p2, t, 2))
    subs = {k: to_state(v) for k, v in _vertex_at(p2, PX1, PY1).items()}
    full = d.in_state_symbols(d.gap_acceleration).subs(_unit_normal()).subs(subs)
    assert not _is_zero(full - to_state(wrong.subs(_unit_normal())).subs(subs))


def test_static_variant_drops_body2_motion():
    d = derive(ALL_CASES["circle_circle"]())
    body2_motion = set(BODY2.velocity_symbols() + BODY2.acceleration_symbols())
    for _, value in d.static2.intermediates:
        assert not (value.free_symbols & body2_motion)
