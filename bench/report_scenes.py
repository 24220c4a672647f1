"""The report's scenes (bench/report.py): each a scene file with an exact or high-precision
reference (bench/references.py), what to plot, and a paragraph on how its error is measured.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from bench.references import (
    BowlReference,
    CylinderReference,
    InclineReference,
    PlankReference,
    Reference,
    RollingBowlReference,
)

ROOT = Path(__file__).resolve().parent.parent
ADAPTIVE_DT = 0.02  # s: our adaptive methods' outer step (contacts classified and recorded)


@dataclass(frozen=True)
class SceneSpec:
    """A report scene: its file, how long to simulate it, its reference and what to plot."""

    name: str
    duration: float  # s of simulated time
    reference: type[Reference]
    panels: tuple[str, ...]  # error measures plotted, the reference's primary first
    title: str
    note: str  # the reference and how its error is measured (a paragraph of the report)

    @property
    def path(self) -> Path:
        return ROOT / "scenes" / f"{self.name}.toml"

    @property
    def has_bowl(self) -> bool:
        return issubclass(self.reference, BowlReference)


SCENES = (
    SceneSpec(
        "disc_in_bowl",
        2.0,
        BowlReference,
        ("position", "force_rms"),
        "Disc in a bowl (concave circle-circle), 2 s: pendulum reference",
        (
            "Reference: the pendulum phi'' = -(g/L) sin phi with L = R - r = 0.9 m from 0.3 rad, "
            "scipy DOP853 at rtol 1e-12; contact force m (g cos phi + L phi'^2). pymunk and Box2D: the bowl's "
            "arc (-150° … -30°) as N chords with their ends on the circle. Position error = max over "
            "the recorded steps of the distance between the disc's centre and the reference's."
        ),
    ),
    SceneSpec(
        "disc_over_cylinder",
        1.5,
        CylinderReference,
        ("leaving_angle", "position"),
        "Disc sliding over a cylinder (convex circle-circle), 1.5 s: leaving angle",
        (
            "Reference: the leaving angle cos phi = (2/3) cos phi0 + v0^2 / (3 g (R + r)) "
            "(0.8403 rad here); the run's leaving angle is where its contact force reaches 0: the "
            "zero of the parabola through the last three samples with force, kept between the last "
            "sample with force and the first without. The force is only known once per step, so "
            f"this has a resolution of its own: with our adaptive runs' {ADAPTIVE_DT:g} s step it "
            "gives the same few 1e-6 rad for every rtol, which is more likely the resolution than "
            "the integrator. A peer's contact comes and goes (an impulse on some steps only), so its "
            "leaving angle is in effect its last step with an impulse. Our runs that locate the "
            "instant the force reaches 0 themselves (a lift-off, runtime/step/lift_events.py: "
            "where d'' dt of the lifting contact exceeds the resting speed, so not at the smallest "
            "steps nor with Euler, whose one stage never sees the force vanish) are measured "
            "there: the disc's centre at that instant, from the first record after it taken back "
            "along its free flight. Position error: against the circle-then-parabola reference "
            "trajectory."
        ),
    ),
    SceneSpec(
        "plank_on_cylinder",
        1.0,
        PlankReference,
        ("energy", "penetration"),
        "Plank tipping off a cylinder (circle-edge), 1 s: energy conservation",
        (
            "Reference: energy conservation (frictionless, no impacts). Energy drift = max |E - E0| "
            "/ (m g), a height in metres."
        ),
    ),
    SceneSpec(
        "disc_on_incline",
        0.5,
        InclineReference,
        ("position", "energy"),
        "Disc on a 30° incline (straight edge, the control), 0.5 s: closed form",
        (
            "Reference: closed form, the disc slides with g sin 30°. A straight edge: not what the "
            "curved-edge engine is for, but the control -- every method of order >= 2 is exact here "
            "up to rounding (plotted at 1e-16), as is the contact force."
        ),
    ),
    SceneSpec(
        "disc_rolling_in_bowl",
        2.0,
        RollingBowlReference,
        ("position", "slip"),
        "Disc rolling in a bowl (friction mu = 0.5, concave circle-circle), 2 s: pendulum in 2g/3",
        (
            "Reference: the disc rolls without slipping (it needs mu >= 0.10, checked), so it is a "
            "pendulum phi'' = -(g'/L) sin phi in g' = g / (1 + I/(m r^2)) = 2g/3, L = R - r = 0.9 m, "
            "from 0.3 rad, scipy DOP853 at rtol 1e-12. Friction mu = 0.5 on both bodies; pymunk "
            "multiplies its shapes' coefficients, so each of its shapes gets sqrt(0.5) (contact "
            "0.5); Box2D mixes them as sqrt(mu1 mu2), as we do. The bowl as for disc_in_bowl. "
            "Position error as there; slip = the largest speed of the disc's contact point along "
            "the bowl (0 when rolling)."
        ),
    ),
    SceneSpec(
        "block_on_incline",
        0.5,
        InclineReference,
        ("position", "energy"),
        "Block sliding down a 30° incline (friction mu = 0.3, straight edges), 0.5 s: closed form",
        (
            "Reference: closed form, the block slides flat with a = g (sin 30° - mu cos 30°) = "
            "2.357 m/s^2 (tan 30° > mu). Friction as for disc_rolling_in_bowl (pymunk: sqrt(mu) "
            "per shape). Energy error: |E(t) - (E0 - mu m g cos 30° s(t))| / (m g), s the exact "
            "distance slid. Two flat faces: not the curved-edge target, but the sliding friction "
            "of two corners at once, which RK4 integrates exactly (plotted at the 1e-16 floor)."
        ),
    ),
)
