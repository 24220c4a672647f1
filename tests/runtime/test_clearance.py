"""runtime.step.clearance: a fast pair is clear (no new contact can be found within the step)
only where every feature pair that no contact of the frame has is farther apart than the
bodies' margins and the deepest admitted contact; and the event search that skips clear pairs
finds the same impacts as the search that samples them all."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from stepping import states_and_impacts

import runtime
from runtime.collide.features import features, scene_tables
from runtime.model import shapes
from runtime.step import clearance, pair_scan
from runtime.step.stepper import Stepper

SCENES = Path(__file__).resolve().parents[2] / "scenes"


def test_a_fast_pair_is_clear_only_farther_than_the_margins_from_features_no_contact_has():
    """runtime.step.quiet.clear on the box (0.4 x 0.2) resting flat on the floor: its bottom
    corners have contacts; the features no contact has that can meet the floor are its top
    corners, 0.2 m above it (its straight edges meet the floor's at corners). So the box is
    clear while its margin stays below 0.2 m less the deepest contact the finder admits (its
    half width, 0.1 m) -- and, with no contact known, never clear of the floor."""
    world = runtime.World(runtime.load_scene(SCENES / "box_on_floor.toml"))
    stepper = world.stepper
    tables = stepper.collision.finder.tables
    frame, _ = stepper.settled_frame(world.poses, world.velocities, 0.01, stepper.limits(0.01))
    c = frame.contacts
    box, floor = int(np.flatnonzero(~stepper.fixed)[0]), int(np.flatnonzero(stepper.fixed)[0])
    assert len(c) == 2 and set(c.body1.tolist()) == {box}  # the two bottom corners
    room = 0.2 - 0.1

    def clear(margin_of_box: float, contacts=c) -> bool:
        margin = np.zeros(stepper.n)
        margin[box] = margin_of_box
        return clearance.clear(
            box, floor, world.poses, world.poses, margin, stepper.radii, stepper.events.deepest,
            stepper.touch,
            tables.rows, tables.body_start, contacts.body1, contacts.body2, contacts.feature,
        )  # fmt: skip

    assert clear(0.0) and clear(room * (1 - 1e-6))
    assert not clear(room * (1 + 1e-6))
    assert not clear(0.0, c.take(np.zeros(0, dtype=np.int64)))  # its bottom corners: unknown
    turned = world.poses.copy()  # turned upside down about its centre: the same, top for bottom
    turned[box, 2] = np.pi
    margin = np.zeros(stepper.n)
    assert clearance.clear(box, floor, turned, turned, margin, stepper.radii, stepper.events.deepest, stepper.touch,
                       tables.rows, tables.body_start, c.body1, c.body2, c.feature) is False  # fmt: skip


def _run(scene, steps: int, dt: float, skip: bool, monkeypatch) -> tuple:
    """States after every step and impact times with the general path's search (the quiet check
    off), skipping clear pairs or not; and how often a pair was clear."""
    said = {True: 0, False: 0}

    def counted(*args):
        found = clearance.clear(*args)
        said[found] += 1
        return found and skip

    monkeypatch.setattr(pair_scan, "clear", counted)
    monkeypatch.setattr(Stepper, "_quiet", lambda *args: False)
    world = runtime.World(scene)
    states, impacts = states_and_impacts(world, steps, dt)
    monkeypatch.undo()
    return states, impacts, said


@pytest.mark.parametrize(
    ("name", "steps", "dt", "skips"),
    [
        ("disc_rolling_in_bowl.toml", 40, 0.05, True),  # friction: rolling fast on an arc
        ("disc_over_cylinder.toml", 30, 0.05, True),  # fast over a disc, then flying off it
        ("rounded_box_into_bowl.toml", 40, 0.05, True),  # corners and arcs landing in an arc
        ("wall_shot.toml", 30, 1 / 60, True),  # 1.67 m a step at a 1 cm wall
        # its corners turn within a margin of the floor: sampled at every fast step
        ("d_shape_rolling.toml", 40, 0.05, False),
    ],
)
def test_the_search_skipping_clear_pairs_finds_the_same_impacts(
    name, steps, dt, skips, monkeypatch
):
    scene = runtime.load_scene(SCENES / name)
    states, impacts, said = _run(scene, steps, dt, True, monkeypatch)
    every, every_impacts, _ = _run(scene, steps, dt, False, monkeypatch)
    assert np.array_equal(states, every)
    assert np.array_equal(impacts, every_impacts)
    assert (said[True] > 0) == skips  # pairs were skipped, or could not be


def test_the_deepest_contact_on_a_compound_body_is_its_thickest_parts():
    """The finder admits a contact as deep as half the thinner unit of the pair
    (runtime.collide.selection), so a compound body of a disc (r = 0.3) and a bar 0.02 thick
    can take one 0.3 deep on its disc, not only 0.01 (its own half width, the thinnest part's)."""
    bar = shapes.polygon([(0.3, -0.01), (1.0, -0.01), (1.0, 0.01), (0.3, 0.01)])
    body = shapes.compound([shapes.disc(0.3), bar])
    tables = scene_tables([body, shapes.disc(0.1)], [False, False])
    assert features(body).half_width == pytest.approx(0.01, rel=1e-9)
    assert clearance.deepest(tables) == pytest.approx([0.3, 0.1], rel=1e-12)
