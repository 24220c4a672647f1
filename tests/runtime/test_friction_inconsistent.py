"""Where no forces obey the frame's friction modes somewhere inside a trial, the friction event
search ends the sub-step there instead of ending the run.

Why: a trial's stages solve the friction LCP at their own states, not at every state the event
search then asks about; a 30-body mixed pile with mu = 0.5 (bench.scenes.mixed_bodies, seed 2)
met a Painleve configuration at a trial's end at t = 0.49 s (17 contacts sliding) and stopped
with "no contact forces obey Coulomb friction". Now (runtime.step.friction_events
FrictionEvents._inconsistent) the instant the modes stop being consistent is bisected and the
island restarts just past it, where the new frame decides the modes again (and jams the island
if it must, runtime.solve.friction); that pile runs its whole second.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from runtime import settings
from runtime.solve.friction_lcp import FrictionInconsistent
from runtime.step.friction_events import FrictionEvents

H = 1e-3


class _Island:
    """The friction problem's one contact: sticking (slide 0)."""

    slide = np.zeros(1)


def _state(inconsistent_from: float, slips_from: float = np.inf):
    """t -> (v_t, a_t, slips) of one sticking contact, which needs more than mu f_n from
    ``slips_from`` on; no forces obey the modes from ``inconsistent_from`` on."""

    def at(t: float):
        if t >= inconsistent_from:
            raise FrictionInconsistent("no contact forces obey Coulomb friction")
        return np.zeros(1), np.zeros(1), np.array([t >= slips_from])

    return at


def _events() -> FrictionEvents:
    """The search alone (what it asks of the state is faked)."""
    return FrictionEvents(None, SimpleNamespace(stabilisation=None), None, None)


def test_the_sub_step_ends_just_past_where_the_modes_stop_being_obeyed():
    """Inconsistent from 0.3 H: the event at most SLIP_TIME H after it, on the inconsistent
    side (so that the new frame decides the modes anew), and the search's own question about
    the trial's end raises as it did."""
    events = _events()
    state = _state(0.3 * H)
    try:
        events._transitions(_Island, state, H)
    except FrictionInconsistent:
        pass
    else:
        raise AssertionError("the fake state did not raise at the trial's end")
    (t,) = events._inconsistent(_Island, state, H)
    assert 0.3 * H <= t <= 0.3 * H + settings.SLIP_TIME * H


def test_a_transition_before_the_inconsistency_comes_first():
    """A stick -> slip at 0.1 H, inconsistent from 0.6 H: both located, the slip first."""
    events = _events()
    times = events._inconsistent(_Island, _state(0.6 * H, slips_from=0.1 * H), H)
    assert len(times) == 2
    assert 0.1 * H <= min(times) <= 0.1 * H + settings.SLIP_TIME * H
    assert 0.6 * H <= max(times) <= 0.6 * H + settings.SLIP_TIME * H


def test_a_search_that_meets_no_forces_halves_the_trial(monkeypatch):
    """The impact search's own integrations can reach such a state too (a 30-body mixed pile
    with mu = 0.5, 43 contacts sliding, stopped so at t = 0.543 s): the stepper then takes a
    trial half as long from the same frame (runtime.step.stepper.Stepper._advance). A block
    sliding at 1 m/s on a floor with mu = 0.4 (constant deceleration mu g: RK4 is exact), its
    search made to fail on any trial longer than 0.3 of the step: the step ends in sub-steps
    of at most that (their searches' lengths add up to the step), at the closed form to 1e-12."""
    import math

    import runtime
    from runtime.io.scene_file import scene_from_dict

    mu, v0, dt, g = 0.4, 1.0, 1e-3, 9.81
    block = {"type": "rounded_rect", "width": 0.2, "height": 0.1, "corner_radius": 0.0}
    scene = scene_from_dict({"body": [
        {"name": "floor", "fixed": True, "friction": mu,
         "shape": {"type": "wall", "start": [-20.0, 0.0], "end": [20.0, 0.0]}},
        {"name": "block", "shape": block, "mass": 1.0, "friction": mu, "position": [0.0, 0.05],
         "velocity": [v0, 0.0]},
    ]})  # fmt: skip
    world = runtime.World(scene)
    stepper = world.stepper
    search, spans = stepper.events.first, []

    def first(frame, q, end, h, labels, trajectory):
        spans.append(h)
        if h > 0.3 * dt:
            raise FrictionInconsistent("no contact forces obey Coulomb friction (made up)")
        return search(frame, q, end, h, labels, trajectory)

    monkeypatch.setattr(stepper.events, "first", first)
    monkeypatch.setattr(stepper, "_quiet", lambda *args: False)  # (every trial searched)
    world.step(dt)
    assert spans[:3] == [dt, dt / 2, dt / 4]  # failed, failed, searched
    assert math.isclose(sum(s for s in spans if s <= 0.3 * dt), dt, rel_tol=1e-12)
    x = v0 * dt - 0.5 * mu * g * dt * dt
    assert (
        abs(world.poses[1, 0] - x) < 1e-12
        and abs(world.velocities[1, 0] - (v0 - mu * g * dt)) < 1e-12
    )
