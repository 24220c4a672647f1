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
DUPLICATE_EPS = 1e-9  # relative to the pair's size (sum of bounding radii): one constraint
# reported from both bodies (two corners meeting) has the same mid-point and gap within this
PARALLEL_EPS = 1e-9  # of |n1 . n2|: normals this close to (anti)parallel are the same constraint
JOIN_EPS = 1e-9  # relative to the body's bounding radius: a vertex this close to a join of two
# edges takes that join's normal cone (rounding of the edges' end points)
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

# -- contact forces (the LCP) ------------------------------------------------------------------

# -- contacts: touching, resting, impacts ------------------------------------------------------

# -- events and integration -------------------------------------------------------------------

# -- guards ------------------------------------------------------------------------------------
