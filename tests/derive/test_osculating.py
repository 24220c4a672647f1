"""An oval edge uses the circular kernels: d, d', d'' of a vertex against an ellipse equal those of
the osculating circle (mpmath, 40 digits), and a circle of another radius does not."""

import pytest

from derive import osculating


@pytest.mark.parametrize(("a", "b", "phi"), [(2.0, 1.0, 0.7), (3.0, 0.5, 2.0), (1.0, 0.2, -1.3)])
def test_osculating_circle_matches_ellipse(a, b, phi):
    result = osculating.check(a=a, b=b, phi=phi)
    assert abs(result.true[2]) > 1e-3  # a non-trivial curvature term
    assert result.max_difference < 1e-25


def test_other_radius_gives_other_second_derivative():
    """Sensitivity: a circle 1 % too large shares d and d' (same point and normal) but not d''."""
    result = osculating.check(radius_scale=1.01)
    assert abs(result.true[0] - result.circle[0]) < 1e-25
    assert abs(result.true[1] - result.circle[1]) < 1e-25
    assert abs(result.true[2] - result.circle[2]) > 1e-4
