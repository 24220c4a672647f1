"""Benchmark scenes built in code (the piles of issue #12), shared by the step benchmarks.

- :func:`falling_pile`: n discs (r = 0.05 m, 1 kg, restitution 0) above the floor of a 1 m wide
  open box (rows of 9 and 8, each over the gaps of the one below), each disc jittered
  by 2 mm (fixed seed), released at rest:
  they fall, land on the floor and on each other and pile up;
- :func:`mixed_bodies`: discs, boxes, rounded boxes, half discs and ellipses falling into a V of
  two walls (every contact case, moving arcs against moving corners).
"""

from __future__ import annotations

import math

import numpy as np

import runtime

RADIUS = 0.05  # m
BOX = 1.0  # m, inner width


def falling_pile(n: int, seed: int = 1, height: float = 0.08):
    """n discs falling into a 1 m box (see the module docstring)."""
    rng = np.random.default_rng(seed)
    per_row = 9
    pitch = BOX / per_row
    bodies, row, col = [], 0, 0
    for k in range(n):
        if col == per_row - row % 2:  # odd rows: one disc fewer, in the gaps of the row below
            row, col = row + 1, 0
        x = -BOX / 2 + pitch * (col + 0.5 + 0.5 * (row % 2)) + rng.uniform(-0.002, 0.002)
        y = RADIUS + 0.01 + row * (2 * RADIUS + height) + rng.uniform(0.0, 0.004)
        col += 1
        bodies.append(
            {
                "name": f"disc{k:03d}",
                "shape": {"type": "disc", "radius": RADIUS},
                "mass": 1.0,
                "position": [x, y],
            }
        )
    rows = row + 1
    box = {
        "name": "box",
        "fixed": True,
        "shape": {"type": "box_walls", "width": BOX, "height": rows * (2 * RADIUS + height) + 1},
    }
    data = {
        "scene": {"name": f"falling_pile_{n}"},
        "simulation": {"duration": 1.0, "dt": 1e-3, "method": "rk4"},
        "body": [box, *bodies],
    }
    return runtime.scene_from_dict(data, source=f"falling_pile_{n}")


def mixed_bodies(n: int = 30, seed: int = 2):
    """n bodies of every shape falling into a V (two walls at +-30 degrees from the floor)."""
    rng = np.random.default_rng(seed)
    shapes = [
        {"type": "disc", "radius": 0.05},
        {"type": "polygon", "points": [[-0.05, -0.04], [0.05, -0.04], [0.05, 0.04], [-0.05, 0.04]]},
        {"type": "rounded_rect", "width": 0.12, "height": 0.07, "corner_radius": 0.02},
        {"type": "half_disc", "radius": 0.06},
        {"type": "ellipse", "a": 0.06, "b": 0.035},
    ]
    bodies = []
    for k in range(n):
        row, col = divmod(k, 6)
        bodies.append(
            {
                "name": f"body{k:02d}",
                "shape": shapes[k % len(shapes)],
                "density": 500.0,
                "position": [-0.45 + 0.18 * col + 0.05 * (row % 2), 0.6 + 0.2 * row],
                "angle": float(rng.uniform(-math.pi, math.pi)),
                "restitution": 0.2,
            }
        )
    walls = [
        {"name": "left", "fixed": True, "shape": {"type": "wall", "start": [-1.0, 0.577],
                                                   "end": [0.0, 0.0]}},
        {"name": "right", "fixed": True, "shape": {"type": "wall", "start": [0.0, 0.0],
                                                    "end": [1.0, 0.577]}},
    ]  # fmt: skip
    data = {
        "scene": {"name": f"mixed_{n}"},
        "simulation": {"duration": 2.0, "dt": 1e-3, "method": "rk4"},
        "body": [*walls, *bodies],
    }
    return runtime.scene_from_dict(data, source=f"mixed_{n}")
