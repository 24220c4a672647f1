"""Shared pieces of the application tests: a small scene and a way to run the command."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

# A disc resting on a floor (one contact carrying its weight from the start) and a box falling.
SMALL_SCENE = """
[scene]
name = "small"

[simulation]
duration = 1.0
dt = 0.001
method = "rk4"

[[body]]
name = "floor"
fixed = true
shape = { type = "wall", start = [-1.0, 0.0], end = [1.0, 0.0] }

[[body]]
name = "resting"
shape = { type = "disc", radius = 0.1 }
density = 1000.0
position = [0.0, 0.1]

[[body]]
name = "falling"
shape = { type = "rounded_rect", width = 0.2, height = 0.1, corner_radius = 0.02 }
density = 500.0
position = [0.4, 0.3]
angle = 0.3
"""


@pytest.fixture
def scene_file(tmp_path: Path):
    """Write a scene (SMALL_SCENE by default) into tmp_path and return its path."""

    def write(text: str = SMALL_SCENE, name: str = "small.toml") -> Path:
        path = tmp_path / name
        path.write_text(textwrap.dedent(text))
        return path

    return write
