"""Every tolerance and threshold of the engine, with its unit and the reason for its size.

Why one module: a threshold typed where it is used hides how the engine decides (when a contact
touches, when a force is zero, when a step gives up), and two places that should agree drift
apart. Like Box2D's constants.h or Rapier's IntegrationParameters, nothing else in runtime/
types a threshold: modules import them from here. Sections follow the step's stages.

Units: m (lengths), s, m/s, rad; "relative" means a pure number scaled by the quantity named.
Lengths that must scale with a scene (the contact tolerance) live in the scene (Scene.
contact_tolerance, default 1e-4 m); the numbers here are either relative or are speeds that the
user can change per run (simulate(resting_speed=...)).
"""

from __future__ import annotations

# -- scene input (runtime/io, and the shape constructors of runtime/model) --------------------

LARGEST = 1e50  # m, m/s, rad, s: the largest magnitude of a number read from a scene (but masses,
# densities and inertias, whose products are checked instead): beyond it squares and fourth powers
# (areas, second moments, kinetic energies, squared distances) overflow float64
SMALLEST = 1e-50  # same units: the smallest positive one (its fourth power, 1e-200, still a normal
# double); below it those powers underflow and shape checks report nonsense
TOLERANCE_FRACTION = 0.5  # relative to the half-width of the thinnest moving body: the largest
# contact or overlap tolerance, so a resting contact is never held visibly open
MAX_AXIS_RATIO = 1e6  # relative: the most slender ellipse, long / short semi-axis. The radius of
# curvature at the ends of the long axis is short^2 / long = long / ratio^2: at 1e6 it is 1e-12 of
# the long axis, still ~4500 spacings of the doubles that place those points (2.2e-16 x long);
# near 6.7e7 it is below one spacing and contact geometry there is rounding noise
MAX_ANGLE = 2.0**49  # rad (5.6e14): the largest body angle read. From 2^49 on, doubles are
# 0.125 rad (7 degrees) apart, so the angle written is not the angle read; below it, the loader
# reduces the angle to (-pi, pi] exactly (atan2 of its sin and cos)
BACK_FACE_REACH = 1.0  # relative to a moving body's bounding diameter: a body whose bounding
# circle is closer than this behind a fixed wall's, bowl's or box's back face, level with it, is
# refused at load (a wall drawn the wrong way round); farther behind, it may be meant to be there
SCENE_FILE_MAX_BYTES = 10 * 2**20  # bytes (10 MiB): the largest scene file read. A scene of
# 10,000 bodies is ~1.5 MB; the cap stops /dev/zero-like inputs or a results file given by mistake
# from filling memory (tomllib holds the text and the parsed tables at once)

# -- geometry and the narrow phase -------------------------------------------------------------

SPAN_EPS = 1e-9  # rad, and relative length: arc spans and segment ends are closed by this much,
# so a flat side lying on a floor keeps both end contacts under rounding
CONE_SLACK = 0.1  # rad: how far a corner's normal cone may miss a straight edge's normal (the
# lifted end of a box tilting on a floor still touches at its corner)
WAY_OUT_MARGIN = 0.05  # relative to the depth limit: how much deeper than its shallowest way out
# a penetrating vertex may be and still be a plausible contact
TURN_EPS = 1e-9  # rad: joins that turn less than this are smooth (no corner)
DUPLICATE_EPS = 1e-9  # relative to the pair's size (sum of bounding radii): one constraint
# reported from both bodies (two corners meeting) has the same mid-point and gap within this
PARALLEL_EPS = 1e-9  # of |n1 . n2|: normals this close to (anti)parallel are the same constraint
JOIN_EPS = 1e-9  # relative to the body's bounding radius: a vertex this close to a join of two
# edges takes that join's normal cone (rounding of the edges' end points)
JOIN_REACH = 10.0  # per unit of the contact tolerance or of a corner's depth: how far at most a
# straight edge holds a corner beyond its end at a reflex join (runtime.collide.junctions), whose
# free space there reaches 1 / sin of the join's angle beyond and the material behind both lines
# |tan|: a cap keeps a nearly flat or nearly square join's reach near the join
INSIDE_EPS = 1e-9  # relative to body 2's half width: a "penetrating" vertex whose way out of a
# closed body 2 is positive by more than this lies outside it (the candidate is spurious)
SCREEN_SLACK = 1e-9  # relative to the pair's size: the candidate stage screens with geometric
# distances widened by this, so the generated kernel's gap (equal up to rounding) decides
ROOT_XTOL = 1e-15  # rad: the ellipse maximiser's root of the derivative, absolute part
ROOT_RTOL = 1e-15  # relative part (as scipy's brentq; >= 4 machine epsilons)
ROOT_GRID = 64  # points over a turn where the maximiser picks the best before its root search
# (the global maximum's neighbourhood; as the previous narrow phase)
WIDTH_DIRECTIONS = 180  # directions over a half turn for a shape's smallest width (exact
# support per direction; the width is the depth limit of a plausible penetration)
THICKNESS_RAYS = 16  # rays from a concave arc (a cup) into its material: the thinnest gives the
# cup's depth limit (its hull's width would be the cup's depth); exact for a cup of uniform
# thickness, whose every ray has the same length

OVERLAP_DIRECTIONS = 720  # directions over a turn where runtime.model.regions.overlap_depth
# (the depth of two convex parts' overlap, a centre of mass's distance outside a hull) picks the
# best before its bounded 1-D search; the exact candidates (edge normals, lines between
# corners and centres) are added to them
CONVEX_EPS = 1e-9  # relative (to the part's size; rad for turns): a compound's part is convex
# if its edges meet within this and no join turns back by more (rounding of end points)

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
LCP_LEAST_NORM_GROWTH = 1e-6  # relative: a proximal-point pass of the least-norm stage (which
# removes the regularization's bias, runtime.solve.lcp_minnorm.dual_newton) may raise the
# objective sum f^2/w by this much -- the bias had let the equations be missed, so the exact
# forces may cost more -- but no more: growth beyond it is a runaway along a direction the
# equations cannot meet with f >= 0
LCP_PGS_SWEEPS = 200  # projected Gauss-Seidel sweeps of the last fallback, from the best point
# found, before its clamped set is solved exactly (it only has to find the set)
LCP_DENSE_MAX = 64  # rows: islands up to this size use the compiled dense solver, larger ones
# with a sparse A the sparse path: measured on resting piles, the sparse path's ~50 us of set-up
# (ordering, scaling) beats the dense solver's O(m^3) from ~35 rows cold and ~60 rows warm
LCP_SPARSE_DENSITY = 0.2  # fraction of non-zeros above which a large island is solved dense

COMPILED = True  # use the compiled frame and integrator stages where they apply (small islands,
# fixed-step methods); False runs every stage the general way (the same results to rounding)
COAST_BATCH = 256  # steps: `simulate` coasts quiet stretches (runtime.step.coast) in calls of
# at most this many steps (a Ctrl-C waits for the call: ~5 ms for a small scene)
COAST_RECORD_BYTES = 4_000_000  # and of at most about this much of records (poses, velocities)
COAST_PATIENCE = 64  # quiet steps: after an attempt that did no step, the next 1, 2, 4, ... up to
# this many quiet steps go one by one (a pile whose contacts change at every step would pay its
# frame twice at each)
LOADED_NULLITY = 12  # body-space directions: a loaded set that leaves more of an island's
# moving directions free (a landing pile, bodies on one contact each) is not solved in body space
# (runtime.solve.lcp_loaded): its rows are then independent, and the contact-space Cholesky of
# the warm start is the cheaper solve; projecting off a null space of q vectors costs q solves
LOADED_DEPENDENT = 1e-9  # relative to K_jj: a body-space column whose pivot is below this
# depends on the columns before it (a direction the loaded contacts leave free)
LOADED_TRIES = 2  # solves: a loaded set whose body-space forces are <= 0 on some rows is solved
# again without them, at most this often in all (each try is one sparse factorization)
LOADED_ISLAND = 24  # contacts: islands from this size whose guessed rows are dependent try
# their loaded set before the dense solver, and keep it as their guess
# (runtime.solve.assembly.solve_small_islands); smaller ones leave it to the dense solver
DENSE_ISLAND = 128  # contacts: islands up to this size are assembled and solved dense in one
# compiled call (an A_CC Cholesky of 48 rows costs ~20 us); larger ones go sparse

# -- friction (runtime/solve/friction*.py, runtime/step/friction_events.py) ----------------------

LEMKE_PIVOT = 1e-12  # relative to the largest |M_ij| (at least 1): a tableau entry below it is
# rounding and cannot limit the entering variable (runtime.solve.lemke); the friction problem's
# entries are O(1/mass) and O(mu), its eliminations lose a few digits at most
LEMKE_TIE = 1e-12  # relative to the minimum ratio: rows within this of it tie (and the
# lexicographic rule decides); two equal tangential rows (a box's corners) tie exactly
LEMKE_PIVOTS = 50  # times (n + 1): pivots of one Lemke solve before giving up (it needs about n;
# a path that meets a basis again, a cycle of rounding, ends there: runtime.solve.lemke)
LEMKE_BASIS_PIVOT = 1e-12  # relative to the largest |entry| left in its column: an LU pivot
# of a remembered friction basis (runtime.solve.friction_lcp) below this is singular, and Lemke's
# method solves instead
LEMKE_RETRIES = 3  # solves again with a perturbed q after a ray (runtime.solve.lemke)
LEMKE_PERTURB = 1e-13  # relative to max |q| (at least 1): the perturbation of such a retry; the
# solution is then exact for a q changed by this much, far below LCP_TOL
LEMKE_COVERS = 24  # other covering vectors tried after those retries (runtime.solve.lemke) where
# a failure has an answer: the friction modes are being decided (a jam sticks its slides); the
# compiled paths try none (runtime.step.compiled_friction: a failure declines to the general path)
LEMKE_COVERS_LAST = 400  # where a failure ends the run (an integrator stage's forces, an
# impact's frictional impulses): one problem of a 30-disc pile with mu = 1 (151 unknowns, ~4 ms
# a path) was solved by 20 of the first 399 vectors, the first at the 28th
HELD_FIRST = 256  # unknowns: an island that sticks everywhere, this large, with no remembered
# basis that solves it, is tried held (runtime.solve.friction_lcp.solve_held, a linear program)
# before Lemke's method, whose path costs O(n^3): the first frames of packed piles with
# mu = 0.5, LP against one path: 208 unknowns 3.5 / 1.5 ms, 320: 5.2 / 28 ms, 432: 7.1 / 119 ms,
# 660: 12 / 560 ms (and that path failed). Held, they would be held with Lemke's forces too
LEMKE_CHECK = 1e-9  # relative to the largest z and |q|: how closely such a solution must solve
# the LCP (w >= 0, z_i or w_i at 0)
STICK_SPEED = 1e-9  # m/s: a frictional contact whose tangential speed |v_t| is at most this
# sticks if the forces allow it (the friction LCP decides); faster, it slides against v_t. As
# TOUCH for gaps: a located slip -> stick leaves |v_t| a thousandth of it (STICK_LOCATE)
STICK_LOCATE = 1e-3  # relative to STICK_SPEED: the |v_t| a located slip -> stick must reach
STICK_DRIFT = 1e-5  # relative to the free-fall speed g dt of one step: how fast the integrator
# may let a sticking contact creep in a step (RK4 leaves 2-3e-8 m/s at dt = 0.05 s on a disc
# rolling in a bowl) and have it still stick at the next frame, its creep removed by
# runtime.step.friction_hold, instead of sliding for the ~1e-8 s friction takes to stop it -- a
# located slip -> stick and a second trial in every step. Sliding that slowly would stop within
# (STICK_DRIFT g dt)^2 / (2 mu g) of where it is: 2.5e-12 m at dt = 0.05 s and mu = 0.5
SLIP_ONSET = 1e-9  # relative to the problem's scale (largest |b|, or g): a sticking contact
# whose slack lambda (the tangential acceleration it would take) exceeds this starts to slide;
# rounding of the Lemke tableau leaves ~1e-15 of it
IMPACT_ENERGY_SLACK = 1e-12  # relative to the kinetic energy before: a frictional impact whose
# restitution phase leaves more than this (rounding is ~1e-15) is redone plastic
# (runtime.solve.friction_impulses: Poisson's restitution with friction can add energy)
CHATTER = 50  # friction transitions located within one step (per island) after which the rest
# of the step lets every slip slower than the resting speed stick (runtime.step.stepper): coupled
# contacts of a pile with mu = 1 stopped and restarted in turn, ~1e-9 s apart, slips of 1e-7 to
# 1e-5 m/s against tangential accelerations of 10-400 m/s^2, until MAX_EVENTS; the slip this
# removes is at most the resting speed, as a plastic impact's approach is
SLIP_TIME = 1e-9  # relative to the step: how closely a stick -> slip transition is bisected in
# time (a predicate, not a smooth function: runtime.step.friction_events); the state differs
# from the exact one's by ~ (this x dt)^2 x the change of acceleration, far below the step's error

LIFT_TIME = 1e-9  # relative to the step: how closely a lift-off (a pressing contact's force
# falling to 0 as it moves apart) is located in time (runtime.step.lift_events); as SLIP_TIME, the
# restart state then differs from the exact one's by ~ (this x dt)^2 x the change of acceleration

# -- contacts: touching, resting, impacts ------------------------------------------------------

TOUCH = 1e-9  # m, at most the scene's contact tolerance: the largest gap that counts as
# touching; a located impact leaves |d| below a thousandth of it (TOUCH_LOCATE)
TOUCH_LOCATE = 1e-3  # relative to TOUCH: the gap an impact location must reach
RESTING_SPEED = 1e-3  # m/s: an approach slower than this is plastic (restitution 0) and the
# contact rests; this is what ends a bouncing ball in finite time (no Zeno sequence of bounces)
CREEP = 1e-9  # relative to the resting speed: the rounding level of d' (nothing is done below)
HOLD = 100.0  # relative to TOUCH: a resting contact that drifted open this far is still held
DRIFT = 1e-3  # relative to the free-fall distance g dt^2 / 2 of one step: how far the integrator
# may carry a resting contact off a curved surface in a step and still hold it
MAX_WAVES = 200  # restitution waves of simultaneous impulses before the final plastic pass
PRESS_RANK = 1e-10  # relative to the largest singular value of an island's B = J M^-1/2: a
# press (runtime.step.resting.project_island) leaves the directions below it alone -- d' has no
# part there beyond rounding (d' = B M^1/2 v), and resolving them would divide rounding by them
SETTLE_ROUNDS = 8  # press/lift rounds of runtime.step.resting before a step goes on

# -- events and integration -------------------------------------------------------------------

RTOL, ATOL = 1e-9, 1e-12  # the adaptive methods' (rk45, dop853) error tolerances per step
MAX_EVENTS = 1000  # located impacts allowed inside one step of one island before giving up
TRIAL_CUTS = 30  # halvings of a trial whose friction modes no forces obey before its end
# (runtime.step.stepper.Stepper._trial): down to 1e-9 of the step, where the frame's own forces
# were found; the sub-step then ends at a new frame, which decides the modes again
LOCATE_ITERATIONS = 60  # Newton/bisection steps to locate one impact in time
TIME_EPS = 4.0  # relative to the float spacing of the step length: two times this close are equal
GRAZE = 1e-6  # relative to TOUCH: a zero of d with d' = 0 that dips less than this is a graze
FAST_PAIR = 0.25  # relative to the smaller body's half width: a pair that moves more than this
# against each other within a step is watched by conservative advancement, not by a cubic fit of
# its gap between the step's ends (a fit misses two discs passing through each other)
DIP_SCREEN = 1.0  # relative to the Hermite cubic's variation over an interval (its larger end
# value less its minimum): a contact open at both ends whose cubic's minimum is closer to 0 than
# this is checked against the real gap (runtime.step.events.find_dip). The cubic's error is a
# fraction (~(travel / size)^2) of that variation, so a minimum farther up cannot be a dip
DIP_LEVELS = 8  # real-gap checks of one such interval, each narrowing it toward the real minimum
ANGLE_WRAP = 1e3  # rad: angles beyond this are wrapped to (-pi, pi] between steps, so the
# integrator keeps 1e-13 rad of resolution however long a body spins


# -- time stepping (runtime/step/time_stepping.py: method "time-stepping") ---------------------

IMPULSE_REGULARISATION = 1e-9  # relative to A_ii: added to the diagonal of a time step's impulse
# LCP (runtime.solve.island_impulses), making A positive definite: a pile's dependent rows with
# a b out of A's range left the dense solver "infeasible" on solvable problems. It is a
# compliance: a held contact moves by h x 1e-9 x A_ii x p a step (1e-13 m for a 1 kg disc under
# a 5 kg column at 1 ms), and a dependent set shares its impulse as the least-norm solution does
SPARSE_WARM = 24  # contacts: a time step's islands from this size are solved by the primal
# active-set method from their guessed clamped set with the envelope factor in a fill-reducing
# order (runtime.solve.island_impulses), smaller ones from the guess with the dense factor; a miss
# goes to the dense solver either way
PRIMAL_FACTORIZATIONS = 3000  # the primal active-set method's limit (runtime.solve.lcp_primal)
# before the dense solver takes over (measured: the 657 islands of 129-551 rows of the falling
# 200-disc pile took 46 factorizations each on average, the most 306)
PRIMAL_UPDATES = 16  # rows: a round of the primal method that only frees rows, up to this many,
# takes them out of the factor by rank-one updates (O(envelope) each) instead of refactoring
# (O(envelope x bandwidth)); measured on the falling 200-disc pile's islands (replayed): 2, 4,
# 16 or no limit alike (0.74-0.75 of the time refactoring took); the limit keeps a round that
# frees many rows from paying an update each.
PROJECTION_TOL = 0.1  # relative to the touch gap (TOUCH, 1e-9 m, or the scene's contact
# tolerance if smaller): a time step ends with no overlap deeper than this (1e-10 m; issue #12 asks
# <= 1e-9 m); deeper ones are projected out (Newton on the gaps, each round an LCP) over the
# contacts within the scene's contact tolerance (so that pushing one overlap out does not push a
# neighbour in)
PROJECTION_ROUNDS = 8  # Newton rounds of the projection before the step gives up; each squares
# the overlap's relative error (measured over 1 s at 1 ms: the falling 50- and 200-disc piles
# needed one round in 6 and 27 steps, the mixed pile of every shape two at most)

# -- joints, springs, damping, mutual gravity (issue #16) ---------------------------------------

JOINT_ASSEMBLY = 1e-9  # relative to the anchors' distance from the origin (at least 1 m): a pin
# joint's anchors must coincide at t = 0 within this (a pin holds their separation as it is, so a
# larger one is a mistake in the scene, not a joint), a distance joint's must be farther apart
JOINT_RANK = 1e-10  # relative to the largest eigenvalue of a joint block J W J^T: smaller ones
# are dependent joint rows (a pin and a distance joint on the same anchors, a closed loop), whose
# impulses the pseudo-inverse leaves at least-norm instead of dividing by rounding

# -- guards ------------------------------------------------------------------------------------

PENETRATION_LIMIT = 1e-2  # relative to the smaller body's bounding radius: an overlap deeper
# than this is a missed impact (a located impact leaves ~1e-12 m)
ENERGY_GROWTH_LIMIT = 0.5  # relative to the scene's energy scale: frictionless contacts do no
# work and restitution <= 1, so a rise of the energy by half the scale is an integrator blow-up

# -- the application (simulate command) ---------------------------------------------------------

PROBE_FROM = 2e5  # steps x bodies: a run this large is probed (a few timed steps) before it
# starts, to warn of its time and memory; below, a run takes about a minute at most
PROBE_STEPS = 20  # steps of the probe: enough for a median step time past the first step's set-up
PROBE_SECONDS = 2.0  # s of wall time the probe may take at most (a slow scene stops it earlier)
WARN_SECONDS = 600.0  # s: expected wall time above which the run is announced with a warning
WARN_BYTES = 2e9  # bytes: expected memory for the recorded steps above which it warns (or half
# the machine's memory if that is less)
SWEEP_MAX_RUNS = 10**7  # runs: the largest grid a sweep accepts (its table alone is then ~1 GB)
SWEEP_CHUNKS = 16  # chunks a sweep's grid is cut into by default: enough to keep a few workers
# busy and to resume an interrupted sweep without redoing much, few enough that each chunk is a
# sizeable ensemble (runtime.step.ensemble: the per-step cost is shared by its copies)
SWEEP_MAX_CHUNK = (
    256  # runs per chunk at most by default (a chunk's trajectories are held in memory)
)
