"""`simulate`'s time grid and arguments, and how a run's memory grows with the bodies (issue #13).

Why: `--duration 1 --dt 0.6` used to simulate 1.2 s; `record_every = 0` raised
ZeroDivisionError; and 10,000 touching discs tried to allocate 4.45 GiB (a dense matrix of all
contacts). References: free fall under RK4 is exact (a quadratic), so the state at the end says
how long the run really was; the grid is t = k dt exactly.
"""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

import runtime

G = 9.81


def _falling_disc() -> runtime.Scene:
    return runtime.scene_from_dict(
        {"body": [{"name": "disc", "shape": {"type": "disc", "radius": 0.1}, "mass": 1.0,
                   "position": [0.0, 0.0]}]},
        source="fall",
    )  # fmt: skip


def test_duration_not_a_whole_number_of_steps_ends_at_the_duration():
    """duration 1, dt 0.6: records at 0, 0.6 and 1 (the last step 0.4 s), and the disc has
    fallen g / 2 (RK4 is exact for free fall), not g 1.2^2 / 2."""
    run = runtime.simulate(_falling_disc(), duration=1.0, dt=0.6)
    assert run.t.tolist() == [0.0, 0.6, 1.0]
    assert run.poses[-1, 0, 1] == pytest.approx(-G / 2, rel=1e-15)
    assert run.velocities[-1, 0, 1] == pytest.approx(-G, rel=1e-15)


@pytest.mark.parametrize(
    "duration, dt",
    [(1.0, 0.1), (0.7, 0.1), (0.9, 0.3), (1.0, 1 / 3), (1.5269373640913046, 0.0020509206222042355),
     (0.19678057768072746, 0.015145390784481148), (2.5, 0.5), (1e-3, 1.0)],
)  # fmt: skip
def test_the_grid_is_k_dt_exactly_and_ends_at_the_duration(duration, dt):
    """Every record is at k dt to the last bit (not a sum of k rounded steps, which was off by
    up to 2.3e-14 s after 746 steps), the last at the duration."""
    run = runtime.simulate(_falling_disc(), duration=duration, dt=dt)
    k = np.arange(len(run.t) - 1)
    assert run.t[:-1].tolist() == (k * dt).tolist()
    assert run.t[-1] == duration and np.all(np.diff(run.t) > 0)
    assert np.diff(run.t)[-1] <= dt * (1 + 1e-15)


@pytest.mark.parametrize("every", [0, -1, 1.5, 2.0, "2"])
def test_record_every_must_be_a_positive_integer(every):
    with pytest.raises(ValueError, match=rf"^record_every must be an integer >= 1, got {every!r}$"):
        runtime.simulate(_falling_disc(), duration=0.01, dt=1e-3, record_every=every)


def test_record_every_keeps_every_kth_step_and_the_end():
    run = runtime.simulate(_falling_disc(), duration=0.01, dt=1e-3, record_every=4)
    assert run.t.tolist() == [0.0, 4e-3, 8e-3, 0.01]


def _row_of_touching_discs(n: int) -> runtime.Scene:
    """n discs (r = 0.1 m) side by side on a floor, each touching its neighbours and the floor:
    one island of 2n - 1 resting contacts."""
    floor = {"name": "floor", "fixed": True,
             "shape": {"type": "wall", "start": [-1.0, 0.0], "end": [0.2 * n + 1.0, 0.0]}}  # fmt: skip
    discs = [
        {"name": f"d{i}", "shape": {"type": "disc", "radius": 0.1}, "mass": 1.0,
         "position": [0.2 * i, 0.1]}
        for i in range(n)
    ]  # fmt: skip
    return runtime.scene_from_dict({"body": [floor, *discs]}, source="row")


def _peak_bytes_of_a_step(n: int) -> int:
    world = runtime.World(_row_of_touching_discs(n))
    world.step(1e-3)  # compiled code loaded, caches filled
    tracemalloc.start()
    try:
        world.step(1e-3)
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_memory_of_a_step_grows_linearly_with_touching_discs():
    """A row of 400 discs against one of 100: 4x the contacts, so about 4x the memory of a
    step if nothing is m x m (allowed: 6x); a dense matrix of the island's contacts makes it
    16x (10,000 discs: 20,000 contacts, 3.2 GB for one matrix). Measured peaks 0.25, 0.49,
    0.94, 1.9 MB for 100-800 discs since a large island's A is assembled sparse (they were
    0.93, 3.3, 12.4, 47.9 MB). A located impact or a press in a large island still builds
    dense matrices (runtime/step/classify._impacts, runtime/step/resting._press)."""
    small, large = _peak_bytes_of_a_step(100), _peak_bytes_of_a_step(400)
    assert large <= 6 * small, (small, large)


@pytest.mark.parametrize("mu", [0.0, 1.0])
def test_looking_at_the_contacts_between_steps_does_not_change_the_run(mu):
    """World.contacts and contact_forces are a look, not a step: they leave the stepper's
    resting sets, warm-start guesses and friction bases as they were (they used to replace them
    with the look's own: a 200-disc pile failed at t = 0.622 s only when its contacts were asked
    for every 10 steps; with mu = 1 a falling 30-disc pile took another path), and
    the same falling pile stepped 300 times gives the same poses bit for bit whether its
    contacts are asked for after every step or never."""
    from bench.scenes import falling_pile

    def pile():
        scene = falling_pile(12)
        for body in scene.bodies:
            body.friction = mu
        return scene

    plain, watched = runtime.World(pile()), runtime.World(pile())
    touching = 0
    for _ in range(300):
        plain.step(1e-3)
        watched.step(1e-3)
        stepper = watched.stepper
        before = stepper.held, stepper.recent, dict(stepper.forces.memory.items())
        bases = dict(stepper.forces.bases.items()) if mu else None
        touching += len(watched.contacts)
        watched.contact_forces  # noqa: B018 -- the look under test
        assert stepper.held is before[0] and stepper.recent is before[1]
        assert dict(stepper.forces.memory.items()) == before[2]
        if mu:
            assert dict(stepper.forces.bases.items()) == bases
    assert touching > 300  # the pile landed: there was something to look at
    np.testing.assert_array_equal(watched.poses, plain.poses)
    np.testing.assert_array_equal(watched.velocities, plain.velocities)
