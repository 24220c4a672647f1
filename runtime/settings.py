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

# -- contacts: touching, resting, impacts ------------------------------------------------------

# -- events and integration -------------------------------------------------------------------

# -- guards ------------------------------------------------------------------------------------

# -- the application (simulate command) ---------------------------------------------------------

PROBE_FROM = 2e5  # steps x bodies: a run this large is probed (a few timed steps) before it
# starts, to warn of its time and memory; below, a run takes about a minute at most
PROBE_STEPS = 20  # steps of the probe: enough for a median step time past the first step's set-up
PROBE_SECONDS = 2.0  # s of wall time the probe may take at most (a slow scene stops it earlier)
WARN_SECONDS = 600.0  # s: expected wall time above which the run is announced with a warning
WARN_BYTES = 2e9  # bytes: expected memory for the recorded steps above which it warns (or half
# the machine's memory if that is less)
