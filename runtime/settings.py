"""Every tolerance and threshold of the engine, with its unit and the reason for its size.

Why one module: a threshold typed where it is used hides how the engine decides (when a contact
touches, when a force is zero, when a step gives up), and two places that should agree drift
apart. Like Box2D's constants.h or Rapier's IntegrationParameters, nothing else in runtime/
types a threshold: modules import them from here. Sections follow the step's stages.

Units: m (lengths), s, m/s, rad; "relative" means a pure number scaled by the quantity named.
"""

from __future__ import annotations

# -- geometry and the narrow phase -------------------------------------------------------------

SPAN_EPS = 1e-9  # rad, and relative length: arc spans and segment ends are closed by this much,
# so a flat side lying on a floor keeps both end contacts under rounding
CONE_SLACK = 0.1  # rad: how far a corner's normal cone may miss a straight edge's normal (the
# lifted end of a box tilting on a floor still touches at its corner)
WAY_OUT_MARGIN = 0.05  # relative to the depth limit: how much deeper than its shallowest way out
# a penetrating vertex may be and still be a plausible contact
TURN_EPS = 1e-9  # rad: joins that turn less than this are smooth (no corner)
DUPLICATE_EPS = 1e-9  # relative to the pair's size: one constraint reported from both bodies

# -- contact forces (the LCP) ------------------------------------------------------------------
# The solver works on the scaled problem S = D A D, D = diag(A)^-1/2 (unit diagonal: A in 1/kg,
# b and a in m/s^2 and f in N all become numbers of one size), so these are pure numbers.

LCP_TOL = 1e-9  # relative, row by row: f solves the LCP if every |a_i| at a clamped row (and
# -a_i elsewhere) is at most LCP_TOL * (sum_j |A_ij f_j| + |b_i|), the size of the terms a_i is
# the sum of -- a componentwise backward error: f is exact for an A and b changed by 1e-9 of
# themselves. Rounding of forming a_i is <= 2.2e-13 of that sum for 1000-row islands (and ~1e-16
# typically), far below; a pile resting on such forces creeps by < 1e-9 of its weight's
# acceleration.
LCP_SHARP = 1e-12  # relative, like LCP_TOL: what the solver aims for -- pivoting drives every
# row violated beyond it and a warm start must meet it to count as a hit; LCP_TOL decides
# acceptance and which rows are held (a = 0) for the least-norm forces. Pivoting to LCP_TOL
# would leave a row 1e-9 off in a near-redundant pair (Schur complement 1e-9), and with it a
# force off by 100 %, unnoticed
LCP_FLOOR = 1e-12  # relative to the largest scaled |b_i| or |f_i| (one unit for every row of
# the scaled problem): added to every row's tolerance, for rows whose own terms are ~0 while b
# carries rounding of terms that cancelled (a b_i of 1e-17 where 0 was meant) or forces on
# an ill-conditioned clamped set do (cond 1e8: residuals ~3e-13 of the largest force seen)
LCP_DEPENDENT = 1e-12  # relative to A_jj: a row whose Schur complement against the clamped rows
# (its squared distance from their span in the metric of A) is below this depends on them
# (a redundant contact); rounding leaves ~k * 1e-16 for a truly dependent row among k, while
# a wedge as tight as the 2 x 2 case (1 - 3e-11 coupling) still has 6e-11.
LCP_REDUNDANT = 1e-6  # relative to A_jj: for the least-norm forces, a row this close to the
# span of the others (1e-3 rad) counts as redundant if the forces still meet LCP_TOL -- a
# near-redundant pair can otherwise carry huge opposed forces (39 N / 45 N where 3 N do) that
# change a by less than the tolerance; if they miss it, only LCP_DEPENDENT rows count
LCP_PIVOT_ROUNDING = 3.6e-15  # 16 eps: a pivot's rounding, times S_jj + sum_i row_i^2 S_ii /
# L_ii^2 (runtime.solve.lcp_factor.trial); a pivot below it is indistinguishable from 0
LCP_NOISE = 1e-12  # relative to max |Delta f|: entries of a pivoting direction (Delta f, and
# Delta a of the unit-diagonal S) this small are rounding, not motion, and never limit a step
LCP_SYMMETRY = 1e-8  # relative to sqrt(A_ii A_jj): input whose A_ij and A_ji differ by more
# (or |A_ij| exceeds sqrt(A_ii A_jj), impossible for a PSD A) is refused; A = J M^-1 J^T
# assembled in float64 is symmetric to ~1e-16
LCP_ZERO_ROW = 1e-24  # relative to the largest A_ii: a row below it is one no force can move
# (a contact between two fixed bodies); 1e-24 resolves any mass ratio up to 1e24
LCP_LEAST_NORM_DONE = 1e-12  # relative to the size of its terms: the least-norm stage's
# equations E f = g hold this well when its Newton method has converged (rounding: ~1e-15)
LCP_LEAST_NORM_ENOUGH = 1e-9  # relative, as above: good enough when rounding stalls the Newton
# method (ill-conditioned T); the forces still pass the LCP_TOL check or are not used
LCP_LEAST_NORM_REGULAR = 1e-14  # relative to a row's curvature: the proximal term of the
# least-norm dual (runtime.solve.lcp_minnorm) -- keeps it bounded when rounding makes the
# equations infeasible by ~1e-16, and biases the forces by ~1e-14 of themselves
LCP_PGS_SWEEPS = 200  # projected Gauss-Seidel sweeps of the last fallback, from the best point
# found, before its clamped set is solved exactly (it only has to find the set)
LCP_DENSE_MAX = 64  # rows: islands up to this size use the compiled dense solver, larger ones
# with a sparse A the sparse path: measured on resting piles, the sparse path's ~50 us of set-up
# (ordering, scaling) beats the dense solver's O(m^3) from ~35 rows cold and ~60 rows warm
LCP_SPARSE_DENSITY = 0.2  # fraction of non-zeros above which a large island is solved dense

# -- contacts: touching, resting, impacts ------------------------------------------------------

# -- events and integration -------------------------------------------------------------------

# -- guards ------------------------------------------------------------------------------------
