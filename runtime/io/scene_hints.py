"""Hints for scene input that is probably a mistake of intent rather than a typo.

Why: "did you mean" from string similarity helps with ``positon``, but for a key that names a
feature the engine lacks (``damping``) it can only list the valid keys or point to a wrong one,
which sends the user after the wrong key: such a key should say so. Likewise a word from another
engine's vocabulary (``bounciness``, ``mu``, ``circle``), and an angle written in degrees
(``angle = 90``), which is a valid number of radians and would silently turn the body by 90 rad.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Sequence

__all__ = ["degrees_hint", "looks_like_degrees", "unknown_key_hint", "unknown_type_hint"]

# Keys (any table, any case) naming features the engine does not have -> what to say.
_ROLLING = (
    "rolling resistance is not supported: friction is Coulomb friction at the contact point, "
    "one coefficient 'friction' per body"
)
_MOTORS = "motors are not supported yet: a joint holds its anchors (pin) or distance only"
_FORCES = "applied forces are not supported yet: only gravity and contact forces act on a body"
_FILTERS = "collision filtering is not supported: every pair of bodies can touch"
UNSUPPORTED: dict[str, str] = {
    **dict.fromkeys(("rolling_friction", "rolling_resistance"), _ROLLING),
    **dict.fromkeys(("motor", "motors"), _MOTORS),
    **dict.fromkeys(("force", "forces", "torque", "impulse"), _FORCES),
    **dict.fromkeys(("collision_group", "collision_mask", "collision_layer", "collision_filter"),
                    _FILTERS),
}  # fmt: skip

# Other engines' words for keys and shape types this one has (used only where valid).
SYNONYMS: dict[str, str] = {
    "elasticity": "restitution",
    "bounciness": "restitution",
    "coefficient_of_restitution": "restitution",
    "rotation": "angle",
    "orientation": "angle",
    "omega": "angular_velocity",
    "spin": "angular_velocity",
    "static": "fixed",
    "moment_of_inertia": "inertia",
    "joints": "joint",
    "constraint": "joint",
    "constraints": "joint",
    "hinge": "joint",
    "springs": "spring",
    "damping": "linear_damping",
    "drag": "linear_damping",
    "air_resistance": "linear_damping",
    "gravitational_constant": "mutual_gravity",
    "attraction": "mutual_gravity",
    "length": "rest_length",
    "k": "stiffness",
    **dict.fromkeys(
        (
            "mu",
            "static_friction",
            "dynamic_friction",
            "kinetic_friction",
            "coefficient_of_friction",
        ),
        "friction",
    ),  # fmt: skip
}
SHAPE_SYNONYMS: dict[str, str] = {
    "circle": "disc",
    "ball": "disc",
    "rectangle": "rounded_rect (with corner_radius = 0)",
    "rect": "rounded_rect (with corner_radius = 0)",
    "box": "rounded_rect (with corner_radius = 0) for a body, box_walls for a container",
    "square": "rounded_rect (with corner_radius = 0)",
    "capsule": "rounded_rect (with corner_radius = height / 2)",
    "triangle": "polygon",
    "oval": "ellipse",
    "semicircle": "half_disc",
    "segment": "wall",
    "line": "wall",
    "floor": "wall",
    "ground": "wall",
}


def _normal(word: str) -> str:
    return word.strip().lower().replace("-", "_").replace(" ", "_")


def unknown_key_hint(key: str, valid: Sequence[str]) -> str:
    """What to say about a key that is not in ``valid``: a missing feature, another engine's
    word for a valid key, or the closest valid key (a typo)."""
    word = _normal(key)
    if word in UNSUPPORTED:
        return f"{UNSUPPORTED[word]}; remove this key"
    if SYNONYMS.get(word) in valid:
        return f"unknown key; did you mean {SYNONYMS[word]!r}?"
    return f"unknown key; {closest(key, valid)}"


def unknown_type_hint(kind: str, valid: Sequence[str]) -> str:
    word = _normal(kind)
    if word in SHAPE_SYNONYMS:
        return f"unknown shape type {kind!r}; use {SHAPE_SYNONYMS[word]}"
    return f"unknown shape type {kind!r}; {closest(kind, valid, 'types')}"


def closest(key: str, valid: Sequence[str], what: str = "keys") -> str:
    """``did you mean '...'?`` for a near miss, else the list of valid names."""
    close = difflib.get_close_matches(key, valid, n=1, cutoff=0.6)
    if close:
        return f"did you mean {close[0]!r}?"
    return f"valid {what}: " + ", ".join(repr(k) for k in valid)


# An angle read as degrees: beyond a full turn in radians, at most a full turn in degrees,
# and a whole multiple of 5 degrees (90, 180, 45, -150, 270, 360 ...).
_DEGREE_STEP = 5.0


def looks_like_degrees(value: float) -> bool:
    """Whether ``value`` (an angle in radians) is more likely a number of degrees."""
    return (
        2 * math.pi < abs(value) <= 360.0
        and abs(value / _DEGREE_STEP - round(value / _DEGREE_STEP)) < 1e-9
    )


def degrees_hint(values: Sequence[float]) -> str:
    """``angles are in radians: 90 looks like degrees (90 deg = 1.5708 rad)``."""
    given = " and ".join(f"{v:g}" for v in values)
    verb = "looks" if len(values) == 1 else "look"
    radians = " and ".join(f"{math.radians(v):.6g}" for v in values)
    return f"angles are in radians: {given} {verb} like degrees ({given} deg = {radians} rad)"
