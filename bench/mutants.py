"""The curated mutants of `make mutate` (bench/mutate.py): realistic bugs, one line each.

A mutant replaces one exact text in one file (`within`: the first occurrence after that anchor,
for lines that repeat) and names the tests that should catch it, run in that order. Tests that
only compare files (the stale check) are never named: a mutant must be caught by physics.
`regenerate=True` runs `python -m derive --no-pdf` first (a derive/ bug that reaches the kernels).

To add one, e.g. for the contact-force solver:

    Mutant("lcp:fast-path-sign", "runtime/solve/lcp.py", "-b / a", "b / a", LCP, "one contact: pulls"),
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Mutant:
    name: str
    path: str
    old: str
    new: str
    tests: str  # pytest targets, space-separated, run in this order with -x
    what: str  # the bug it models
    within: str = ""
    regenerate: bool = False


PROOFS = "tests/derive/test_proofs.py"
ORACLE = "tests/generated/test_bias_terms.py tests/generated/test_kernels_vs_oracle.py"
ARCS_FIRST = "tests/runtime/test_arcs.py " + ORACLE  # the engine scenes must catch it too
COMPILED = "tests/generated/test_compiled_kernels.py"
SHAPES = "tests/runtime/test_shapes.py tests/runtime/test_arcs.py"
STEPPING = "tests/runtime/test_arcs.py tests/runtime/test_physics.py"
LIFTS = "tests/runtime/test_lift_events.py"
INTEGRATORS = "tests/runtime/test_integrators.py " + STEPPING  # the general path's integrators
DERIVATION = "derive/derivation.py"
CC = "generated/circle_circle.py"
VC = "generated/vertex_circle.py"
CE = "generated/circle_edge.py"
VE = "generated/vertex_edge.py"
SHAPE = "runtime/model/shapes.py"
STEP = "runtime/step/integrators.py"
COMPILED_STEP = "runtime/step/compiled_stages.py"
LCP = "tests/runtime/test_lcp_pivoting.py tests/runtime/test_lcp_paths.py tests/runtime/test_lcp.py tests/runtime/test_lcp_property.py tests/runtime/test_lcp_reduced.py"
REDUCED = "runtime/solve/lcp_reduced.py"
DENSE = "runtime/solve/lcp_dense.py"
BARAFF = "runtime/solve/lcp_baraff.py"
ASSEMBLY = "runtime/solve/assembly.py"
IMPULSES = "runtime/solve/impulses.py"
LOADED = "runtime/solve/lcp_loaded.py"
LOADED_TESTS = "tests/runtime/test_lcp_loaded.py"
FRICTION_LCP = "runtime/solve/friction_lcp.py"
FRICTION_BASIS = "tests/runtime/test_friction_basis.py"
COMPILED_FRICTION = "runtime/step/compiled_friction.py"
COMPILED_FRICTION_TESTS = "tests/runtime/test_compiled_friction.py"
IMPACTS = "tests/runtime/test_collisions.py tests/runtime/test_moving_pairs.py"
CONTACTS = "tests/runtime/test_contacts.py tests/runtime/test_contact_properties.py"
EVENTS = "runtime/step/events.py"
GUESS = "tests/runtime/test_warm_guess.py tests/runtime/test_physics.py tests/runtime/test_collisions.py"
COMPOUND = "tests/runtime/test_compound.py tests/runtime/test_shapes.py tests/runtime/test_scene.py"
QUIET = "runtime/step/quiet.py"
QUIETS = "tests/runtime/test_quiet_step.py"
CLEARANCE = "runtime/step/clearance.py"
CLEARANCES = "tests/runtime/test_clearance.py tests/runtime/test_guards.py"
COAST = "runtime/step/coast.py"
COASTS = "tests/runtime/test_coast.py"

# fmt: off
JUNCTIONS = "tests/runtime/test_junctions.py"
TIME_STEPPING = "tests/runtime/test_time_stepping.py tests/runtime/test_island_impulses.py"
PRIMAL = "tests/runtime/test_lcp_primal.py"
TS = "runtime/step/time_stepping.py"
MUTANTS: list[Mutant] = [
    # derive/: the proofs must fail (issue #18: a wrong bias term used to pass them)
    Mutant("derive:centripetal-sign", DERIVATION, "/ V_LEN + V_TAN**2 / V_LEN)", "/ V_LEN - V_TAN**2 / V_LEN)", PROOFS, "circular edge: the centripetal v_tan^2/|v| term of d'' with the wrong sign"),
    Mutant("derive:centripetal-dropped", DERIVATION, "/ V_LEN + V_TAN**2 / V_LEN)", "/ V_LEN)", PROOFS, "circular edge: d'' without its centripetal term"),
    Mutant("derive:v_tan-cross", DERIVATION, "(V_TAN, (sx * sy_t - sy * sx_t) / V_LEN)", "(V_TAN, (sx * sy_t + sy * sx_t) / V_LEN)", PROOFS, "circular edge: v x v' written with a + (tangential speed wrong)", within="def _circle_case"),
    Mutant("derive:bias-keeps-body2-acceleration", DERIVATION, "{a: 0 for a in ACCELERATION})", "{a: 0 for a in ACCELERATION[:3]})", PROOFS, "the bias keeps body 2's acceleration terms"),
    Mutant("derive:static2-keeps-body2-velocity", DERIVATION, "{m: 0 for m in BODY2_MOTION})", "{m: 0 for m in BODY2_MOTION[3:]})", PROOFS, "body 2 fixed: only its accelerations zeroed, its velocity kept"),
    Mutant("derive:jacobian-no-chain-rule", DERIVATION, "total = sp.diff(expr, symbol) + sum(", "total = sp.diff(expr, symbol) + 0 * sum(", PROOFS, "J: the chain rule through the intermediates dropped"),
    Mutant("derive:line-offset-sign", DERIVATION, "d = nx * vx + ny * vy - case.offset", "d = nx * vx + ny * vy + case.offset", PROOFS, "straight edge: the circle's radius added to the gap"),
    Mutant("derive:dy-sign", DERIVATION, "(DY, y1 - y2)]", "(DY, y2 - y1)]", PROOFS, "the relative position's y taken the wrong way round"),
    Mutant("derive:rotation-transposed", "derive/kinematics.py", "sp.Matrix([c * vx - s * vy, s * vx + c * vy])", "sp.Matrix([c * vx + s * vy, -s * vx + c * vy])", PROOFS, "body points turned by R(-th): consistent, but not the bodies' motion"),
    Mutant("derive:circle-offset", "derive/cases.py", "offset=R1 + R2,", "offset=R1 - R2,", PROOFS, "circle on circle: r2 subtracted with the wrong sign"),
    Mutant("derive:centre-swapped", "derive/cases.py", "BODY2.point(CX2, CY2)", "BODY2.point(CY2, CX2)", PROOFS, "vertex on circle: the centre's coordinates swapped", within="def vertex_circle"),
    Mutant("derive:normal-on-body1", "derive/cases.py", "normal=BODY2.rotate(NX2, NY2),", "normal=BODY1.rotate(NX2, NY2),", PROOFS, "circle on edge: the edge's normal turned with body 1", within="def circle_edge"),
    Mutant("derive:jacobian-spec-bodies-swapped", "derive/kernels.py", "d.jacobian,\n            jac_names,", "d.jacobian[3:] + d.jacobian[:3],\n            jac_names,", ORACLE, "the emitted Jacobian row lists body 2 before body 1: a slip after the proofs", regenerate=True),
    # generated/: bias and Jacobian terms of every case, full and body 2 fixed
    Mutant("vertex_edge:bias-factor-2", VE, "+ 2 * n_x_t * v_x_t", "+ n_x_t * v_x_t", ORACLE, "eq. 4's factor 2 on n'.v' lost (x part)", within="def bias("),
    Mutant("vertex_edge:bias_static2-w1^2", VE, "v_x_tt = e2 * (-e3 * px1 + e4 * py1)", "v_x_tt = e2 * (-e3 * px1 - e4 * py1)", ORACLE, "body 2 fixed: the vertex's centripetal acceleration"),
    Mutant("vertex_edge:jacobian-j1th", VE, "-e11 * n_x + e8 * n_y,", "-e11 * n_x - e8 * n_y,", ORACLE, "body 1's lever R1 x n", within="def jacobian("),
    Mutant("vertex_edge:jacobian-j2th", VE, "- n_y * (-e4 + e5),", "+ n_y * (-e4 + e5),", ORACLE, "body 2's lever R2 x n", within="def jacobian("),
    Mutant("circle_edge:bias-n''", CE, "+ n_x_tt * v_x", "- n_x_tt * v_x", ORACLE, "eq. 11's -w2^2 r1 term (n''.v) with the wrong sign", within="def bias("),
    Mutant("circle_edge:bias-w1^2", CE, "e16 = w1 * w1", "e16 = -w1 * w1", ORACLE, "the off-centre circle's centripetal acceleration", within="def bias("),
    Mutant("circle_edge:jacobian_static2-j1th", CE, "return n_x, n_y, -n_x *", "return n_x, n_y, n_x *", ORACLE, "body 2 fixed: body 1's lever U1 x n", within="def jacobian_static2("),
    Mutant("vertex_circle:bias-centripetal", VC, "return sg2 * (e12 * v_tan * v_tan + e12", "return sg2 * (-e12 * v_tan * v_tan + e12", ORACLE, "eq. 8's curvature term sigma v_tan^2/|v| with the wrong sign", within="def bias("),
    Mutant("vertex_circle:bias-w2^2", VC, "e14 = w2 * w2", "e14 = -w2 * w2", ORACLE, "the moving circle's centripetal acceleration", within="def bias("),
    Mutant("vertex_circle:jacobian-j2th", VC, "e10 * (v_x * (e7 + e8) - v_y * (-e1 + e3)),", "e10 * (v_x * (e7 - e8) - v_y * (-e1 + e3)),", ORACLE, "body 2's lever U2 x n", within="def jacobian("),
    Mutant("circle_circle:bias-w1^2", CC, "e13 = w1 * w1", "e13 = -w1 * w1", ARCS_FIRST, "issue #18: the w1^2 term (zero for a disc) with the wrong sign", within="def bias("),
    Mutant("circle_circle:bias_static2-w1^2", CC, "e8 = w1 * w1", "e8 = -w1 * w1", ARCS_FIRST, "body 2 fixed (a bowl): the off-centre arc's w1^2 term", within="def bias_static2("),
    Mutant("circle_circle:bias-v_tan", CC, "v_tan = e12 * (v_x * v_y_t - v_x_t * v_y)", "v_tan = e12 * (v_x * v_y_t + v_x_t * v_y)", ARCS_FIRST, "the tangential relative speed", within="def bias("),
    Mutant("circle_circle:jacobian-j1th", CC, "e10 * (e6 * v_y - e9 * v_x),", "e10 * (e6 * v_y + e9 * v_x),", ARCS_FIRST, "body 1's lever U1 x n", within="def jacobian("),
    Mutant("compiled:circle_circle-bias-w1^2", "generated/compiled/circle_circle.py", "e13 = w1 * w1", "e13 = -w1 * w1", COMPILED, "the compiled variant's w1^2 term", within="def bias("),
    # runtime/model/shapes.py: mass properties (area, centroid, second moment)
    Mutant("shapes:arc-area", SHAPE, "+ h * R * s1 + k * R * c1)", "+ h * R * s1 - k * R * c1)", SHAPES, "an arc's area term (Green's theorem)"),
    Mutant("shapes:arc-first-moment", SHAPE, "(h * h * s1 + 2 * h * R * c2 + R * R * c3)", "(h * h * s1 + h * R * c2 + R * R * c3)", SHAPES, "an arc's first moment: the centroid of a half disc"),
    Mutant("shapes:arc-second-moment", SHAPE, "h**3 * s1 + 3 * h * h * R * c2", "h**3 * s1 + 2 * h * h * R * c2", SHAPES, "an arc's second moment"),
    Mutant("shapes:segment-second-moment", SHAPE, "* (y0 * y0 + y1 * y1)) / 12", "* (y0 * y0 + y1 * y1)) / 6", SHAPES, "a segment's second moment"),
    Mutant("shapes:segment-first-moment", SHAPE, "my = -dx * (y0 * y0 + y0 * y1 + y1 * y1) / 6", "my = -dx * (y0 * y0 + y0 * y1 + y1 * y1) / 3", SHAPES, "a segment's first moment"),
    Mutant("shapes:parallel-axis", SHAPE, "- area * (mx * mx + my * my)", "+ area * (mx * mx + my * my)", SHAPES, "the parallel-axis theorem the wrong way"),
    Mutant("shapes:ellipse-moment", SHAPE, "(edge.a**2 + edge.b**2) / 4", "(edge.a**2 + edge.b**2) / 2", SHAPES, "an ellipse's second moment"),
    Mutant("shapes:centroid-y", SHAPE, "cx, cy = ox + mx, oy + my", "cx, cy = ox + mx, oy - my", SHAPES, "the centroid's y from the wrong side"),
    Mutant("scene:inertia-no-area", "runtime/model/scene.py", "float(self.shape.second_moment) / float(self.shape.area)", "float(self.shape.second_moment)", SHAPES, "inertia = m J (J per unit density, not per unit mass)"),
    # runtime/step/integrators.py
    Mutant("integrators:rk4-a3", STEP, "a3 = rhs(q + half * v2, v3)", "a3 = rhs(q + half * v, v3)", INTEGRATORS, "RK4's third stage at the first stage's positions (still consistent, lower order)"),
    Mutant("integrators:rk4-a4", STEP, "a4 = rhs(q + h * v3, v4)", "a4 = rhs(q + h * v2, v4)", INTEGRATORS, "RK4's last stage from the second stage's velocity"),
    Mutant("integrators:rk4-weights", STEP, "v + sixth * (a1 + 2.0 * (a2 + a3) + a4)", "v + sixth * (a1 + 3.0 * a2 + a3 + a4)", INTEGRATORS, "RK4's weights (sum still 6)"),
    Mutant("integrators:midpoint-full-step", STEP, "qm, vm = q + half * v, v + half * a1", "qm, vm = q + h * v, v + h * a1", INTEGRATORS, "midpoint evaluated at the end of the step"),
    Mutant("integrators:euler-half", STEP, "return q + h * v, v + h * a1", "return q + h * v, v + 0.5 * h * a1", INTEGRATORS, "Euler's velocity with half the step"),
    Mutant("compiled:rk4-a3", COMPILED_STEP, "stage(q0, v0, v2, a2, half, q, v3)", "stage(q0, v0, v0, a2, half, q, v3)", STEPPING, "compiled RK4's third stage at the first stage's positions"),
    Mutant("compiled:rk4-weights", COMPILED_STEP, "v0[i, c] + sixth * (a0[i, c] + 2.0 * (a2[i, c] + a3[i, c]) + a4[i, c])", "v0[i, c] + sixth * (a0[i, c] + 3.0 * a2[i, c] + a3[i, c] + a4[i, c])", STEPPING, "compiled RK4's weights (sum still 6)"),
    Mutant("compiled:midpoint-position", COMPILED_STEP, "stage(q0, v0, v2, a2, h, q_out, v_out)", "stage(q0, v0, v0, a2, h, q_out, v_out)", STEPPING, "compiled midpoint: positions advanced with the start's velocity"),
    # runtime/solve: the contact-force solver (issue #18: the fast path and the polish step)
    Mutant("lcp:single-row-pulls", DENSE, "if joint[0] or b[0] < 0.0 else 0.0", "if joint[0] or b[0] != 0.0 else 0.0", LCP, "one contact (the fast path): -b/A returned for b > 0, a pulling force"),
    Mutant("lcp:polish-unchecked", DENSE, "if hit or is_solution(S, b, joint, f, tol, a, tol_a):", "if True:", LCP, "the polish (PGS) fallback accepted without its residual check"),
    Mutant("lcp:drive-wrong-rows", BARAFF, "state[i] != CLAMPED and a[i] < -tol_a[i] and -a[i] > worst:", "state[i] != CLAMPED and a[i] > tol_a[i] and -a[i] > worst:", LCP, "Baraff drives the separating contacts instead of the violated ones"),
    Mutant("lcp:max-step-sign", BARAFF, "elif state[i] == NOT_CLAMPED and da[i] < -noise_a:", "elif state[i] == NOT_CLAMPED and da[i] > noise_a:", LCP, "maxstep: a free contact limits the step when it separates, not when it closes"),
    Mutant("lcp:clamped-row-one-sided", BARAFF, "if not abs(a[i]) <= tol_a[i]:", "if not a[i] <= tol_a[i]:", LCP, "complementarity: a pushed row accepted with a < 0 (still penetrating)"),
    Mutant("lcp:least-norm-pulls", "runtime/solve/lcp_minnorm.py", "if jR[c] or u > 0.0:\n            fR[c]", "if jR[c] or u != 0.0:\n            fR[c]", LCP, "least norm: a redundant contact's force not clipped at 0"),
    Mutant("reduced:no-drop", REDUCED, "if dl[a] < 0.0 and -lam[a] / dl[a] < t_drop:", "if dl[a] < 0.0 and -lam[a] / dl[a] < t_drop and False:", LCP, "least norm (reduced QP): an active constraint whose multiplier turns negative is never dropped"),
    Mutant("reduced:redundant-weight-dropped", REDUCED, "H[a, a] += 1.0 / wR[a]", "H[a, a] += 0.0 / wR[a]", LCP, "least norm (reduced QP): the redundant rows' own forces left out of the norm"),
    Mutant("reduced:infeasible-too-soon", REDUCED, "if rate <= 1e-12 * curvature:", "if rate <= 0.5 * curvature:", LCP, "least norm (reduced QP): a constraint that a step can still meet taken as one it cannot (infeasible, the dual Newton method skipped)"),
    Mutant("reduced:rounding-enforced", REDUCED, "floor = max(floor, _MET * size)", "floor = 0.0", LCP, "least norm (reduced QP): a force >= 0 enforced on a row whose g is rounding of 0 (large opposed forces)"),
    Mutant("lcp:guess-single-row-pulls", ASSEMBLY, "if f[k] < 0.0:", "if f[k] < -np.inf:", GUESS, "the engine's guessed island with one clamped row keeps a pulling force (a body that should lift off)"),
    Mutant("lcp:guess-one-row-island-pulls", ASSEMBLY, "if f < 0.0:", "if f < -np.inf:", GUESS, "the engine's guessed one-row island keeps a pulling force (a body that should lift off)"),
    Mutant("assembly:reaction-sign", ASSEMBLY, "acc[j, c] += inv_mass[j, c] * jac[k, 3 + c] * f", "acc[j, c] -= inv_mass[j, c] * jac[k, 3 + c] * f", IMPACTS + " tests/runtime/test_physics.py", "body 2's reaction (force and impulse) with the wrong sign"),
    # runtime/solve/lcp_loaded.py: a large island's forces from its loaded set
    Mutant("loaded:multiplier-unchecked", LOADED, "if clamped[i] and not loaded[i] and g[i] > _TOL * largest:", "if False:", LOADED_TESTS, "a loaded set missing a contact that should carry force accepted: a solution, not the least-norm one"),
    Mutant("loaded:force-sign-unchecked", LOADED, "if rows[i] and not s > 0.0:", "if False:", LOADED_TESTS, "a loaded contact whose body-space force comes out negative accepted: a pulling force"),
    Mutant("loaded:lcp-check-dropped", LOADED, "if not env.valid(a_ptr, a_idx, s_data, bs, np.zeros(m, np.bool_), fs, _TOL, a, tol_a):", "if False:", LOADED_TESTS, "the body-space forces accepted without checking the LCP conditions"),
    Mutant("loaded:null-space-kept", LOADED, "            _remove_component(null, a, step)", "            pass", LOADED_TESTS, "K^+ without projecting off K's null space: a loaded set that leaves a body free solved as if it fixed it"),
    # runtime/solve/friction_lcp.py, friction.py: the remembered basis and the held fallback
    Mutant("friction:basis-unchecked", FRICTION_LCP, "if (abs(w[i]) if basic[i] else -w[i]) > _TOL * scale[i]:", "if False:", FRICTION_BASIS, "a remembered basis accepted without checking w = M z + q: the wrong forces of a stale basis"),
    Mutant("friction:lemke-unpolished", FRICTION_LCP, "if _warm(island, bias, tangent_bias, free_acc, rates, basic, polished):", "if False:", FRICTION_BASIS, "Lemke's forces taken from its tableau: sticking contacts 4e-9 N outside their cones"),
    Mutant("friction:held-fallback-dropped", "runtime/solve/friction.py", "            held = solve_held(", "            held = False and solve_held(", FRICTION_BASIS, "no held fallback when Lemke's method ends on a ray: a packed pile's first frame named a Painleve configuration"),
    Mutant("friction:moving-solution-kept", "runtime/solve/friction_lcp.py", "if hold_first and _moves(", "if False and _moves(", FRICTION_BASIS, "an island that can be held takes Lemke's solution that opens or slips its contacts (an island of the falling 30-disc pile with mu = 1 slips at ~2 m/s^2)"),
    Mutant("friction:held-first-dropped", "runtime/solve/friction_lcp.py", "if hold_first and z.size >= _HELD_FIRST and _sticks(slide, k):", "if False:", FRICTION_BASIS, "a large island that sticks everywhere runs Lemke's paths before its held forces: a packed 100-disc pile's first step 6.8 s, not 0.3 s"),
    Mutant("friction:unloaded-basis-refused", "runtime/solve/friction_lcp.py", "np.where(basic, z + largest, 0.0)", "np.where(basic, z, 0.0)", FRICTION_BASIS, "a basis refused for rounding in the rows of a contact without force: Lemke's method at every solve of a resting pile (16 ms a step, not 1)"),
    Mutant("friction:frame-failure-not-final", "runtime/solve/friction.py", "                    final = True\n", "                    raise\n", "tests/runtime/test_friction_jams.py", "a frame whose island sticks everywhere and fails the first covering vectors ends the run (the falling 20-disc pile with mu = 0.5 at t = 0.645 s)"),
    Mutant("friction:no-jam", "runtime/solve/friction.py", "                if not sliding:", "                if True:", "tests/runtime/test_friction_jams.py", "a jammed island's sliding contacts do not stick: the Painleve error stands"),
    Mutant("friction:chatter-unchecked", "runtime/step/stepper.py", "if transitions == settings.CHATTER:", "if False:", "tests/runtime/test_friction_jams.py", "chattering slips keep their stick speed until MAX_EVENTS"),
    Mutant("stepper:trial-not-cut", "runtime/step/stepper.py", "            except self.refused:\n                if cuts == settings.TRIAL_CUTS:", "            except ZeroDivisionError:\n                if cuts == settings.TRIAL_CUTS:", "tests/runtime/test_friction_jams.py", "a trial whose friction modes no forces obey half a step on ends the run (the falling 20-disc pile with mu = 0.5 at t = 0.672 s)"),
    Mutant("stepper:search-refusal-not-cut", "runtime/step/stepper.py", "            except self.refused:\n                # the search integrated", "            except ZeroDivisionError:\n                # the search integrated", "tests/runtime/test_friction_inconsistent.py", "the event search met a state whose friction modes no forces obey: the run ends instead of a trial half as long"),
    Mutant("stepper:trial-cut-ends-the-step", "runtime/step/stepper.py", "            if not firsts and cut:", "            if False:", "tests/runtime/test_friction_jams.py", "a cut trial without events is taken as the whole step: the bodies lag the clock"),
    Mutant("stepper:trial-cut-quiet-ends-the-step", "runtime/step/stepper.py", "                if cut:\n                    (q, v), elapsed, events = end, elapsed + span, events + 1\n                    continue\n                report.quiet", "                report.quiet", "tests/runtime/test_friction_jams.py", "a quiet cut trial is taken as the whole step: the bodies lag the clock"),
    Mutant("stepper:substep-all-from-own", "runtime/step/stepper.py", "q[members], v[members] = q_own[members], v_own[members]", "q, v = q_own, v_own", "tests/runtime/test_island_substep.py", "a sub-step of every island takes every body from the event island's own trajectory: the other islands fall free of their resting contacts"),
    Mutant("friction-events:wrong-way-slip-located", "runtime/step/friction_events.py", "stopping = (starts > 0) & (ends <= 0)", "stopping = ends <= 0", "tests/runtime/test_friction_jams.py", "a contact sliding against its residual v_t is located as stopping at t = 0, at every restart (MAX_EVENTS)"),
    Mutant("friction-events:later-stops-unchecked", "runtime/step/friction_events.py", "if earliest is not None and speed(earliest)[0] > tol:", "if earliest is not None:", "tests/runtime/test_friction_jams.py", "only the stop guessed first is located: a slip that stops earlier is stepped across"),
    Mutant("friction-events:inconsistent-bisected-wrong", "runtime/step/friction_events.py", "                state(mid)\n                lo = mid", "                state(mid)\n                hi = mid", "tests/runtime/test_friction_inconsistent.py", "where the frame's friction modes stop being obeyed inside a trial, the bisection keeps the wrong half: the sub-step ends at the trial's start"),
    Mutant("held-lp:presolve", "runtime/solve/friction_lcp.py", '        options={"presolve": False},\n', "", "tests/runtime/test_friction_held_lp.py", "the held island's LP runs HiGHS's presolve, which corrupts the heap on one 20-variable LP and aborts the process"),
    Mutant("lemke:no-other-covers", "runtime/solve/lemke.py", "for attempt in range(1, covers + 1):", "for attempt in range(1, 1):", "tests/runtime/test_friction_jams.py", "a ray with Lemke's covering vector of ones ends the run although another vector solves the island (rows of 20 dropped with mu = 1)"),
    Mutant("lemke:cut-off-path-final", "runtime/solve/lemke.py", "        first = INACCURATE\n    size", "        first = INACCURATE\n    if first == ITERATIONS:\n        return first\n    size", "tests/runtime/test_friction_jams.py", "a path cut off after LEMKE_PIVOTS is final: no retry, no other covering vector"),
    Mutant("lemke:first-end-unchecked", "runtime/solve/lemke.py", "        if complementary(M, q, z):\n            return SOLVED\n        first = INACCURATE", "        return SOLVED", "tests/runtime/test_friction_jams.py", "the end of Lemke's first path is taken unchecked: a 35-contact island's w = -18.9 beside z = 120, the dropped rows sink 6.5e-8 m"),
    Mutant("lemke:retry-ends-unchecked", "runtime/solve/lemke.py", "if lemke(M, moved, z, basic) == SOLVED and complementary(M, q, z):", "if lemke(M, moved, z, basic) == SOLVED:", "tests/runtime/test_friction_jams.py", "the ends of the perturbed retries are taken unchecked (one leaves w = -1.7e-5 on that island)"),
    Mutant("lemke:cycles-unchecked", "runtime/solve/lemke.py", "        if key in visited:", "        if False:", "tests/runtime/test_friction_jams.py", "a path that meets a basis again runs on to LEMKE_PIVOTS x (n + 1) pivots: a packed 60-disc pile's first frame took 89 s"),
    # runtime/step/lift_events.py: lift-offs located inside a step
    Mutant("lifts:not-located", "runtime/step/stepper.py", "            self.lifts = LiftEvents(self)", "            self.lifts = None", LIFTS, "a pressing contact's lift-off is stepped across, not located (the disc over the cylinder's flight 1.8e-3 m off at dt = 0.05 s)"),
    Mutant("lifts:quiet-blind", "runtime/step/stepper.py", "if not (self.compiled or self.compiled_friction) or lifting:", "if not (self.compiled or self.compiled_friction):", LIFTS, "World.step's quiet check takes a trial across a lift-off"),
    Mutant("lifts:coast-blind", "runtime/step/coast.py", "if np.any(pressing & ~staged) and lifted(", "if False and lifted(", LIFTS, "a coasted stretch steps across a lift-off"),
    Mutant("events:sinking-touch-unlocated", "runtime/step/events.py", "return Bracket(k, t0, t0 + span, t0 + 0.5 * span, SINK, c, t0, span)", "return None", IMPACTS, "a lifting or separating contact that closes from the start of a trial is not located: it sinks (a falling 30-disc pile with mu = 1: 1.7e-7 m)"),
    Mutant("lifts:later-lifts-unchecked", "runtime/step/lift_events.py", "if earliest is not None and g(earliest) > 0.0:", "if earliest is not None:", LIFTS, "only the first lifting contact is located: an earlier lift-off of another is stepped across"),
    Mutant("lifts:pressed-side", "runtime/step/lift_events.py", "    return hi\n", "    return lo\n", LIFTS, "a lift-off located on the side where the contact still presses"),
    Mutant("lifts:any-force-presses", "runtime/step/lift_events.py", "pressing = forces > settings.LCP_TOL * forces[members].max()", "pressing = forces > 0.0", "tests/runtime/test_hard_cases.py::test_mixed_bodies_falling_into_a_v_do_not_sink_into_each_other", "a contact restarted just past its lift-off, found pressing with 1e-9 of its island's largest force (one solution of a redundant set), is located lifting again at once, until MAX_EVENTS (the mixed pile at t = 0.433 s)"),
    # runtime/step/compiled_friction.py: friction on the compiled path
    Mutant("compiled-friction:quiet-ignores-slide", COMPILED_FRICTION, "if slide[k] != 0.0 and not slide[k] * v_t[k] > 0.0:", "if False:", COMPILED_FRICTION_TESTS, "a trial whose sliding contact's slip crossed 0 (slip -> stick) called quiet: the transition not located"),
    Mutant("compiled-friction:no-restitution-phase", COMPILED_FRICTION, "if phase == 1 and not np.any(e_w > 0.0):", "if phase == 1:", COMPILED_FRICTION_TESTS, "impacts with friction lose their restitution phase (plastic whatever e)"),
    Mutant("compiled-friction:hold-keeps-slip", COMPILED_FRICTION, "target[r] = -v_t[stick[r]]", "target[r] = 0.0", COMPILED_FRICTION_TESTS, "the hold of sticking contacts leaves their residual slip"),
    # runtime/solve/impulses.py
    Mutant("impulses:restitution-factor", IMPULSES, "(1.0 + restitution[wave]) * rate[wave]", "restitution[wave] * rate[wave]", IMPACTS, "Newton's law with e instead of (1 + e)"),
    Mutant("impulses:wave-not-propagated", IMPULSES, "rate += A[:, wave] @ p", "rate[wave] += A[wave][:, wave] @ p", IMPACTS, "a wave's impulses not passed to the touching contacts (Newton's cradle)"),
    # runtime/collide: contact finding
    Mutant("collide:circle-edge-radius-sign", "runtime/collide/curves.py", "gap = nx * (cx - ax) + ny * (cy - ay) - r", "gap = nx * (cx - ax) + ny * (cy - ay) + r", CONTACTS, "circle on an edge: the screening gap with the radius added"),
    Mutant("collide:concave-normal", "runtime/collide/curves.py", "nx, ny = sig * vx / dist, sig * vy / dist", "nx, ny = vx / dist, vy / dist", CONTACTS, "circle in a bowl: the normal not turned for a concave arc"),
    Mutant("collide:corner-cone-normal", "runtime/collide/corners.py", "_corner_ok(rows, world, c, -nx, -ny, True)", "_corner_ok(rows, world, c, nx, ny, True)", CONTACTS, "corner on an edge: its cone tested with the edge's normal, not the opposite"),
    Mutant("collide:sweep-stops-early", "runtime/collide/broadphase.py", "if a[q] - r[q] > a[p] + r[p]:", "if a[q] - r[q] > a[p]:", CONTACTS, "the broad phase's sweep ends at a circle's centre: pairs dropped"),
    Mutant("collide:keeps-deepest", "runtime/collide/selection.py", "if admitted[m] and same and gap[m] > gap[k]:", "if admitted[m] and same and gap[m] < gap[k]:", CONTACTS, "a penetrating corner keeps its deepest way out, not its shallowest"),
    # runtime/step/events.py: the impact time
    Mutant("events:locate-accepts-penetration", EVENTS, "if abs(d) <= gap_tol:", "if d <= gap_tol:", IMPACTS, "locate stops at any penetrating iterate (abs dropped): the impact late"),
    Mutant("events:locate-one-step-early", EVENTS, "gap_tol=settings.TOUCH_LOCATE * self.touch", "gap_tol=self.touch", IMPACTS, "the impact accepted at the touch gap, not a thousandth of it: about one Newton step early", within="bracket.guess,"),
    Mutant("events:cubic-bisection-side", EVENTS, "if (fm < 0.0) == (f0 < 0.0):", "if (fm < 0.0) != (f0 < 0.0):", IMPACTS, "the compiled cubic roots: bisection keeps the half without the root"),
    Mutant("events:dip-bracket-side", EVENTS, "if v < 0:\n            t0, g0, v0 = t, g, v", "if v > 0:\n            t0, g0, v0 = t, g, v", IMPACTS, "a near graze: the dip search narrows to the wrong side"),
    Mutant("watch:rate-is-gap", "runtime/solve/rows.py", "return float(gap[k]), float(rate[k])", "return float(gap[k]), float(gap[k])", "tests/runtime/test_kernel_rows.py " + IMPACTS, "the event search's one-contact watcher returns d as d' (Newton on the wrong slope)"),
    Mutant("watch:open-at-best-inverted", EVENTS, "return at_best[g][1][k] > 0", "return at_best[g][1][k] <= 0", IMPACTS, "a contact already penetrating at its island's earliest impact skipped (and open ones located): an earlier impact missed"),
    # mass properties of compound bodies and of a given centre of mass; the bodies' inverse masses
    Mutant("shapes:compound-no-parallel-axis", SHAPE, "jc = math.fsum(p.second_moment_about((cx, cy)) for p in parts)", "jc = math.fsum(p.second_moment for p in parts)", COMPOUND, "a compound's moment: the parts' own moments summed, without the parallel-axis terms"),
    Mutant("shapes:moment-about-point-sign", SHAPE, "return self.second_moment + self.area * (dx * dx + dy * dy)", "return self.second_moment - self.area * (dx * dx + dy * dy)", COMPOUND, "the second moment about a point: the parallel-axis term subtracted"),
    Mutant("scene:inertia-about-centroid", "runtime/model/scene.py", "inertia = float(mass) * shape.second_moment_about(offset) / float(shape.area)", "inertia = float(mass) * shape.second_moment / float(shape.area)", COMPOUND, "a given centre of mass: the inertia about the centroid, not about that point"),
    Mutant("scene:inverse-masses-rows", "runtime/model/scene.py", "(b.inverse_mass, b.inverse_mass, b.inverse_inertia)", "(b.inverse_mass, b.inverse_inertia, b.inverse_mass)", STEPPING + " " + IMPACTS, "W = diag(1/m, 1/I, 1/m): the inverse inertia on y, the inverse mass on the rotation"),
    # the impulses' final inelastic pass and the effective-mass matrix of several contacts
    Mutant("impulses:final-pass-not-applied", IMPULSES, "    total += p\n    rate += A @ p\n", "    rate += A @ p\n", IMPACTS, "the final inelastic pass's impulses counted in d' but never applied to the bodies"),
    # runtime/step/quiet.py: a step that ends without the event search must have had no event
    Mutant("quiet:crossing-not-seen", QUIET, "if g1 <= floor:", "if g1 <= floor and g0 <= floor:", QUIETS, "only contacts touching at the start are checked for a crossing: an open one that closed within the step counts as quiet, its impact never located"),
    Mutant("quiet:dip-not-seen", QUIET, "r0 < 0.0 and v1k > -creep", "r0 < 0.0 and v1k > 1.0", QUIETS, "an open contact approaching at the start and receding at the end counts as quiet: a dip below d = 0 between the ends missed"),
    Mutant("quiet:margin-not-checked", QUIET, "far <= margin[i]", "far <= 1e300", QUIETS, "a body that outran its margin counts as quiet: contacts beyond the swept ones never watched"),
    Mutant("quiet:dip-screen-dropped", QUIET, "return (1.0 + screen) * low - screen * max(g0, g1) > room", "return low > room", QUIETS, "an open contact whose Hermite cubic stays above 0 counts as quiet, though the search checks the real gap of one within settings.DIP_SCREEN of its variation: a graze the cubic misses goes through"),
    Mutant("quiet:flight-rests-ignored", QUIET, "            rests[i]\n            or rests[j]\n            or not least_gap", "            not least_gap", QUIETS, "a body with a resting contact taken to fly free: a disc sliding round a bowl is checked along the straight path of its start acceleration, and a peg its arc runs into counts as passed"),
    Mutant("quiet:flight-vertex-dropped", QUIET, "if half > 0.0 and 0.0 < -rate / (2.0 * half) < h:", "if False:", QUIETS, "a free body's gap to a fixed edge taken at the step's ends only: a ball that dips to the floor and rises again within the step counts as quiet"),
    Mutant("quiet:moving-apart-slide-unchecked", "runtime/step/quiet.py", "if modes[k] != OPEN and may_slide_off(", "if modes[k] == RESTING and may_slide_off(", "tests/runtime/test_quiet_step.py", "a contact moving apart past its arc's end is quiet: the side beyond is unwatched (a box's corner lifting off a rounded box's arc went 1.3e-6 m into its side)"),
    # runtime/step/clearance.py: a fast pair skipped by the search must have had nothing to find
    Mutant("clearance:depth-dropped", CLEARANCE, "room = (reach + max(depth, touch))", "room = (reach + touch)", CLEARANCES, "the deepest contact the finder admits left out: a pair clear by less than a penetrating contact's depth counts as clear"),
    Mutant("clearance:segment-far-end", CLEARANCE, "return max(near - outer, inner - far)", "return far - outer", CLEARANCES, "a feature's distance from a segment taken at the segment's far end: a corner over the middle of an edge counts as far from it"),
    Mutant("clearance:travel-not-counted", CLEARANCE, "reach += max(margin[j], 2.0 * moved(q0, q1, radii, j))", "reach = 0.0", CLEARANCES, "how far the bodies move left out: any pair whose features are apart at the start counts as clear"),
    Mutant("coast:set-not-compared", COAST, "elif m != keys.size or not np.all(found == keys):", "elif m != keys.size:", COASTS, "a stretch goes on when a contact gave way to another: the held flags and warm-start guesses of the old set used for the new one"),
    Mutant("coast:lifting-coasted", COAST, "if not ok or np.any(modes == LIFTING):", "if not ok:", COASTS, "a step with a lifting contact coasts: its record misses the lifting contact's force, which World.step solves for it"),
    Mutant("coast:memory-not-written", COAST, "memory.update(keys[touched], guesses[touched])", "memory.update(keys[:0], guesses[:0])", COASTS, "the warm-start guesses of a stretch are not written back: the steps after it start from older ones"),
    Mutant("bound:writability-not-keyed", "runtime/compiled.py", "a.flags.c_contiguous, a.flags.writeable)", "a.flags.c_contiguous)", "tests/runtime/test_bound.py", "a read-only array shares the entry of a writable one (numba types them apart)"),
    Mutant("assembly:island-matrix-half", ASSEMBLY, "if a != b or side_a != side_b:", "if side_a != side_b:", "tests/runtime/test_warm_guess.py " + IMPACTS, "A of several contacts on one body: a pair on the same side of it filled on one side of the diagonal"),
    Mutant("selection:boundary-corner-deep", "runtime/collide/selection.py", "if not plausible[k] and out >= -rounding:", "if False:", "tests/runtime/test_contacts.py", "a corner on a box's side, 1e-13 outside, is a contact 0.01 deep under the box's top (it locked a mixed pile at t = 0.773 s)"),
    Mutant("clearance:arc-span-unchecked", "runtime/step/clearance.py", "if t != SEGMENTS and t != ARCS:\n        return math.inf", "if t != SEGMENTS:\n        return math.inf", "tests/runtime/test_quiet_step.py tests/runtime/test_hard_cases.py", "a resting contact on an arc never slides off it: the disc off a rounded apex goes 9.6e-8 m into the side"),
    Mutant("clearance:concave-not-flipped", "runtime/step/clearance.py", "flip = -1.0 if t == ARCS and rows[r, A_R] < 0.0 else 1.0", "flip = 1.0", "tests/runtime/test_coast.py", "a rounded box's corner sliding in a bowl is taken as past its arc (the wrong side of it): never quiet, never coasted"),
    Mutant("clearance:cone-unchecked", "runtime/step/clearance.py", "return _signed(angle, rows[r, C_WIDTH] + 2.0 * LEAVE)", "return math.inf", "tests/runtime/test_quiet_step.py", "a resting corner turned out of its normal cone stays quiet: a side next to it meets a curve unwatched"),
    Mutant("clearance:end-unchecked", "runtime/step/clearance.py", "return _end_room(rows, r, pose, other_r, other_pose)", "return math.inf", "tests/runtime/test_quiet_step.py", "a smooth end turned back onto its arc (a rounded box tipping from its flat side onto its corner) never slides off it: the end stays held where the arc takes the contact"),
    Mutant("events:left-unlocated", "runtime/step/events.py", "left = self._left(frame, mine[sliding], start, trajectory(g), until)", "left = None", "tests/runtime/test_hard_cases.py tests/runtime/test_friction_edge.py", "the instant a resting contact leaves its feature is not located: a disc rolling off a flat face onto a corner arc is held up on the face's line past its end, flies and lands (1.3e-4 J)"),
    Mutant("events:slid-off-unasked", EVENTS, "            if not sliding.any():\n                continue", "            continue", "tests/runtime/test_hard_cases.py", "the event search does not ask about an island whose resting contact slid off its feature: an ellipse 4.6e-6 m into a rounded box's side"),
    Mutant("clearance:corner-arc-cone-unchecked", "runtime/step/clearance.py", "if rows[r, C_ARC_BEFORE] == 0.0 and rows[r, C_ARC_AFTER] == 0.0:", "if True:", JUNCTIONS, "a corner resting on a straight edge turned out of its cone onto its arc stays held: the arc goes 7e-7 m into the wall, unlocated"),
    # runtime/collide/junctions.py: reflex joins of straight edges
    Mutant("junctions:free-space-unheld", "runtime/collide/junctions.py", "return min(1.0 / sin, JOIN_REACH) * depth", "return 0.0", JUNCTIONS, "an edge does not hold a corner beyond its end over the free space up to the other edge: a box sliding into a V's vertex is found past it, 1.7e-9 m into the other wall"),
    Mutant("junctions:material-unheld", "runtime/collide/junctions.py", "reach = sin / -cos if cos < 0.0 else JOIN_REACH", "reach = 0.0", JUNCTIONS, "a corner pressed into a V's vertex, behind both lines, is held by neither wall"),
    Mutant("junctions:depth-unbounded", "runtime/collide/junctions.py", "if angle <= 0.0 or not abs(gap) <= limit:", "if angle <= 0.0:", JUNCTIONS, "an edge holds a corner beyond its end however deep: a box's corner 1 cm below a V's vertex touches both walls"),
    Mutant("junctions:walls-unjoined", "runtime/collide/finder.py", "            self._join_fixed(p)\n", "            pass\n", JUNCTIONS, "two fixed walls meeting at a point are not joined: the box tipping over the V's vertex stops 8.9 mm into a wall"),
    Mutant("junctions:end-vertices-kept", "runtime/collide/junctions.py", "            rows[r, C_WIDTH] = HIDDEN", "            pass", JUNCTIONS, "the walls' end vertices at a V's vertex are kept: a corner there touches four features and the force solve fails (infeasible)"),
    Mutant("time-stepping:no-speculation", TS, "b = rate + np.maximum(gap, 0.0) / h", "b = rate", TIME_STEPPING, "a contact open by d is held shut at once (no speculative row): a falling disc stops in the air, a step short of the floor"),
    Mutant("time-stepping:plastic-bounce", TS, "b[bounce] = (1.0 + e[bounce]) * rate[bounce]", "b[bounce] = rate[bounce]", TIME_STEPPING, "restitution ignored: every impact plastic"),
    Mutant("time-stepping:unprojected", TS, "if gap.min() >= -self.tolerance:", "if True:", TIME_STEPPING, "the overlaps a step leaves are never projected out (the velocity LCP holds only the linearised gaps)"),
    Mutant("time-stepping:explicit-euler", TS, "moved = q + h * after", "moved = q + h * v", TIME_STEPPING, "positions advanced with the velocities before the step (explicit Euler): falls by the wrong recurrence, and contacts close by the old velocity"),
    Mutant("island-impulses:unregularised", "runtime/settings.py", "IMPULSE_REGULARISATION = 1e-9 ", "IMPULSE_REGULARISATION = 0.0 ", TIME_STEPPING, "the impulse LCP unregularised: a pile's dependent rows with b out of A's range end \"infeasible\" (the landing 50-disc pile, seed 7, step 630)"),
    Mutant("lcp-primal:full-step", "runtime/solve/lcp_primal.py", "        if count > 0:  # y leaves f >= 0", "        if False:  # y leaves f >= 0", PRIMAL, "the primal active-set method takes the minimiser over the free rows even where it has negative forces"),
    Mutant("lcp-primal:search-curvature", "runtime/solve/lcp_primal.py", "p[j] * s_jj - 2.0 * Sp[j]", "p[j] * s_jj + 2.0 * Sp[j]", PRIMAL, "the projected search updates q's curvature along its path with the wrong sign where a row stops"),
    Mutant("lcp-primal:forward-late", "runtime/solve/lcp_primal.py", "env.forward(first[:n], offset[: n + 1], L, x, z, w0)", "env.forward(first[:n], offset[: n + 1], L, x, z, w0 + 1)", PRIMAL, "the forward substitution is redone from the row after the first one whose membership changed"),
    Mutant("time-stepping:margins-trusted", TS, "if self.collision.finder.has_ovals or sweep.outran(q, moved, self.radii, margin):", "if self.collision.finder.has_ovals:", TIME_STEPPING, "the overlap check trusts the step's contacts even where an impulse sent a body beyond its margin: a disc knocked into a wall it was not near stays in it"),
    Mutant("time-stepping:clear-unchecked", TS, "return not len(contacts) or self.evaluator.gaps(contacts, moved).min() >= -self.tolerance", "return True", TIME_STEPPING, "no overlap check when no body outran its margin: the overlaps a step leaves stay"),
    Mutant("lcp-primal:packed-envelope-short", "runtime/solve/lcp_envelope.py", "lo = min(lo, pos[j])", "lo = min(lo, pos[j] + 1)", PRIMAL, "the packed factor's rows start a column late: each drops its first member column"),
    Mutant("lcp-primal:update-rotation-half", "runtime/solve/lcp_envelope.py", "x = cos * x - sin * l_ij", "x = cos * x", PRIMAL, "a row taken out of the factor by an update: the rotations leave the update vector's part from the factor out"),
    Mutant("lcp-primal:update-scales-stale", "runtime/solve/lcp_envelope.py", "scales[i, 0], scales[i, 1] = 1.0 / r, scales[i, 1] * (d * d) / (r * r)", "pass", PRIMAL, "an updated row keeps its old 1 / L_jj: the rows factored after it use the old pivot"),
    Mutant("lcp-primal:refactor-late", "runtime/solve/lcp_envelope.py", "    for i in range(start, member.size):", "    for i in range(start + 1, member.size):", PRIMAL, "the envelope factor is redone from the row after the first one whose membership changed"),
]
# fmt: on

# Why a mutant survives, when it is expected to (printed with it and in bench/README.md).
SURVIVOR_NOTES: dict[str, str] = {}

# What the list leaves out on purpose, and what earlier runs found (printed in bench/README.md).
NOTES = (
    "Earlier runs. The first (2026-12-01, 42 mutants) killed 38: Euler with half the step and"
    " the midpoint rule evaluated at the end of the step survived (now tests/runtime/test_arcs.py"
    " checks each method's order of convergence), a mutant dropping the inner chain rule of"
    " `Derivatives.total_derivative` was equivalent (replaced by dropping the outer one), and a"
    " kernel-spec mutant crashed `regenerate-equations` (replaced by one that regenerates). The"
    " solver, impulse, contact-finding and impact-time mutants were first run group by group"
    " (--only): `events:dip-bracket-side` survived (tests/runtime/test_moving_pairs.py now checks"
    " shallow asymmetric dips against their exact entry time) and `events:locate-one-step-early`"
    " could not fail at 1 ms steps (the spinning oval now also runs with 0.05 s steps). The run"
    " of 2026-12-02 01:12 (66 mutants, stopped after 52 to rerun with its fixes) found three"
    " kinds of survivor. The five `integrators:` mutants: the engine's scenes now step through"
    " the compiled stages, so runtime/step/integrators.py runs only for friction, joints, ovals"
    " and stabilisation; tests/runtime/test_integrators.py checks each method's order on"
    " harmonic oscillators (closed form), and test_arcs.py the rocking arc's on the general path"
    " too. `lcp:max-step-sign`: the fallbacks (a fresh start, projected Gauss-Seidel) repaired"
    " the broken pivoting, exact forces after about 8 times the pivots in 4 of 300 random"
    " problems; tests/runtime/test_lcp_pivoting.py checks that pivoting alone solves strictly"
    " convex problems. `lcp:guess-single-row-pulls`, and `lcp:guess-one-row-island-pulls`, which"
    " had ended 'timeout 900 s': no endless loop, its tests passed after a cold compile that"
    " outlasted the timeout at load 4-6, while the disc over the cylinder stayed glued about 20"
    " steps past its lift-off angle, pulled by up to 49 N; tests/runtime/test_warm_guess.py"
    " checks the warm-started island solve against a brute-force oracle, and test_physics.py"
    " that the cylinder only pushes. Left out on purpose: equivalent mutants, and mutants that"
    " crash regenerate-equations, which any run shows."
)
