"""Every tolerance and threshold of the engine, with its unit and the reason for its size.

Why one module: a threshold typed where it is used hides how the engine decides (when a contact
touches, when a force is zero, when a step gives up), and two places that should agree drift
apart. Like Box2D's constants.h or Rapier's IntegrationParameters, nothing else in runtime/
types a threshold: modules import them from here. Sections follow the step's stages.

Units: m (lengths), s, m/s, rad; "relative" means a pure number scaled by the quantity named.
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
DUPLICATE_EPS = 1e-9  # relative to the pair's size: one constraint reported from both bodies

# -- contact forces (the LCP) ------------------------------------------------------------------

# -- contacts: touching, resting, impacts ------------------------------------------------------

# -- events and integration -------------------------------------------------------------------

# -- guards ------------------------------------------------------------------------------------
