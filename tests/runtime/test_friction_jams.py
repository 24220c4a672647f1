"""Piles of discs with mu = 1 that the friction modes alone could not step (runtime.solve.friction
and runtime.step.stepper): a jam (no forces obey Coulomb's law with the slides as they are) and a
chatter (coupled slips stopping and restarting ~1e-9 s apart)."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import runtime
from bench.scenes import falling_pile
from bench.steps import pile_scene
from runtime import settings
from runtime.solve import friction, lemke
from runtime.solve.friction_lcp import FrictionInconsistent, painleve
from runtime.solve.friction_rows import FrictionRows

DATA = Path(__file__).parent / "data"


def _with_friction(scene, mu):
    for body in scene.bodies:
        body.friction = mu
    return scene


def test_a_jammed_island_sticks_and_the_pile_goes_on():
    """The falling 30-disc pile with mu = 1 stopped at t = 0.219 s: the island's LCP with its two
    sliding contacts has no solution (a mixed-integer search over its 22 unknowns found none).
    Its sliding contacts now stick (their slip removed by the hold impulse), and the run goes on
    with Coulomb's law at every record and no overlap."""
    run = runtime.simulate(_with_friction(falling_pile(30), 1.0), duration=0.3, dt=1e-3)
    assert run.t[-1] >= 0.3 - 1e-12
    assert run.max_penetration < 1e-9
    for f_n, f_t in zip(run.contact_forces, run.friction_forces, strict=True):
        assert np.all(f_n >= 0.0)
        assert np.all(np.abs(f_t) <= f_n * (1 + 1e-9) + 1e-12)


def test_chattering_slips_stick_instead_of_exhausting_the_events():
    """Rows of 20 discs dropped onto each other with mu = 1: at t = 0.062 s coupled contacts
    stopped and restarted in turn until more than settings.MAX_EVENTS transitions in one step.
    After settings.CHATTER of them the slips slower than the resting speed stick, and the step
    ends."""
    world = runtime.World(_with_friction(pile_scene(20, drop=0.01), 1.0))
    for _ in range(63):
        world.step(1e-3)
    assert world.t >= 0.063 - 1e-12
    assert np.all(np.isfinite(world.velocities))


def test_chattering_slips_stick_within_the_event_budget(monkeypatch):
    """The rule above, with its limits scaled down (settings.CHATTER = 5, MAX_EVENTS = 40; the
    piles that needed the full ones no longer chatter so long since their paths changed): the
    falling 20-disc pile with mu = 0.5 has a step at t = 0.364 s whose slips stop and restart
    more than 40 times without the rule. With it, every step ends within the budget."""
    monkeypatch.setattr(settings, "CHATTER", 5)
    monkeypatch.setattr(settings, "MAX_EVENTS", 40)
    run = runtime.simulate(_with_friction(falling_pile(20), 0.5), duration=0.4, dt=1e-3)
    assert run.t[-1] >= 0.4 - 1e-12
    assert run.max_penetration < 1e-9


def test_the_dropped_rows_settle_where_lemke_needs_another_covering_vector():
    """The same rows run by `simulate` stopped at t = 0.063 s (Lemke's path for an island of
    35 sticking contacts ended on a ray, and the held LP had no solution) and then at 0.064 s
    (a path of 33 contacts cut off after settings.LEMKE_PIVOTS). Other covering vectors solve
    both (runtime.solve.lemke.lemke_perturbed), and the rows come to rest with Coulomb's law at
    every record and without overlap: they had sunk 6.5e-8 m into a contact whose force a
    wrong end of Lemke's path (below) left at d'' = -18.9 m/s^2."""
    run = runtime.simulate(_with_friction(pile_scene(20, drop=0.01), 1.0), duration=0.3, dt=1e-3)
    assert run.t[-1] >= 0.3 - 1e-12
    assert run.max_penetration < 1e-9
    for f_n, f_t in zip(run.contact_forces, run.friction_forces, strict=True):
        assert np.all(f_n >= 0.0)
        assert np.all(np.abs(f_t) <= f_n * (1 + 1e-9) + 1e-12)
    assert np.all(np.abs(run.velocities[-1]) < 1e-6)  # at rest


def _linear_slip(v0: float, a: float):
    """state(t) of one contact whose v_t = v0 + a t (a constant tangential acceleration)."""
    return lambda t: (np.array([v0 + a * t]), np.array([a]), np.zeros(1, bool))


def test_only_a_slip_along_its_sliding_direction_is_located_as_it_stops():
    """The falling 30-disc pile with mu = 1 stopped at t = 0.427 s with more than
    settings.MAX_EVENTS located slip -> stick events, all at t = 3.8e-20 s: a contact set sliding
    at s = -1 against its residual v_t = +1.85e-4 m/s (below the raised stick speed; its
    acceleration -0.10 m/s^2 chose the direction) has s v_t < 0 from the start, and was found
    to stop at once, at every restart. A slip that does stop is located where v0 + a t = 0."""

    from runtime.step.friction_events import FrictionEvents

    h = 4.2367e-5
    against = SimpleNamespace(slide=np.array([-1]))
    assert FrictionEvents._slip_to_stick(None, against, _linear_slip(1.85e-4, -0.102), h) is None
    along = SimpleNamespace(slide=np.array([1]))
    t = FrictionEvents._slip_to_stick(None, along, _linear_slip(2e-3, -100.0), h)
    assert t is not None and abs(t - 2e-5) < 1e-9 * h + 1e-12 / 100.0


def test_the_earliest_of_several_stopping_slips_is_located():
    """An island's first slip -> stick is the earliest of its sliding contacts' stops. They are
    taken by their linear guesses, and a contact still sliding its way at the earliest stop
    found so far is not located (it stops later); one that has stopped by then is. Here the
    first guess misleads: v_t = v0 (1 - 3 t / h)^3 guesses 0.11 h but stops at h / 3, and a
    linear slip stopping at 0.2 h is the earliest; a third stopping at 0.9 h is passed over."""
    from runtime.step.friction_events import FrictionEvents

    h, v0 = 1e-3, 2e-3
    stops = np.array([h / 3, 0.2 * h, 0.9 * h])
    asked = []

    def state(t: float):
        asked.append(t)
        v = np.array([v0 * (1 - 3 * t / h) ** 3, v0 * (1 - t / stops[1]), v0 * (1 - t / stops[2])])
        a = np.array([-9 * v0 / h * (1 - 3 * t / h) ** 2, -v0 / stops[1], -v0 / stops[2]])
        return v, a, np.zeros(3, bool)

    t = FrictionEvents._slip_to_stick(None, SimpleNamespace(slide=np.ones(3)), state, h)
    assert t is not None and abs(t - stops[1]) < 1e-12 * h + 1e-12 / (v0 / stops[1])
    # the third contact's stop was not searched: no instant inside the step near it was asked
    assert not any(abs(x - stops[2]) < 0.1 * h for x in asked if 0.0 < x < h)
    alone = FrictionEvents._slip_to_stick(None, SimpleNamespace(slide=np.eye(3)[2]), state, h)
    assert abs(alone - stops[2]) < 1e-12 * h + 1e-12 / (v0 / stops[2])


def _assert_solves(M, q, z):
    """z solves the LCP (M, q): z >= 0, w = M z + q >= 0 and z_i w_i = 0, to 1e-9 of the
    largest z and |q| (numpy, apart from runtime.solve.lemke's own check)."""
    w = M @ z + q
    z_scale, w_scale = max(z.max(), 1e-300), max(np.abs(q).max(), 1.0)
    assert z.min() >= 0.0
    assert w.min() >= -1e-9 * w_scale
    assert np.minimum(z / z_scale, w / w_scale).max() <= 1e-9


def test_an_end_of_lemkes_path_that_does_not_solve_the_problem_is_not_taken():
    """The friction LCP (140 unknowns) of the dropped rows' 35-contact island at an RK4 stage
    after t = 0.0639 s: Lemke's path with the covering vector of ones ends with z0 out of the
    basis, "solved", at a z whose w_22 = -18.9 beside z_22 = 120 (the tableau's rounding chose
    a wrong basis). lemke_perturbed checks every end against M and q and goes on to perturbed
    and other covering vectors until one solves it."""
    data = np.load(DATA / "lemke_wrong_end.npz")
    M, q = data["M"], data["q"]
    z, basic = np.zeros(q.size), np.zeros(q.size, bool)
    assert lemke.lemke(M, q, z, basic) == lemke.SOLVED
    assert (M @ z + q).min() < -10.0  # the wrong end this test is about
    assert lemke.lemke_perturbed(M, q, z, basic, settings.LEMKE_COVERS) == lemke.SOLVED
    _assert_solves(M, q, z)


def test_where_a_failure_would_end_the_run_lemke_tries_more_covering_vectors():
    """The friction LCP (151 unknowns, 3 contacts sliding) of the falling 30-disc pile with
    mu = 1 at an RK4 stage of t = 0.529 s: no path of the first settings.LEMKE_COVERS covering
    vectors solves it (the 28th does). With its modes decided such a failure would end the run,
    so there (runtime.solve.friction.FrictionalForces.solve) LEMKE_COVERS_LAST are tried."""
    data = np.load(DATA / "lemke_late_cover.npz")
    M, q = data["M"], data["q"]
    z, basic = np.zeros(q.size), np.zeros(q.size, bool)
    assert lemke.lemke_perturbed(M, q, z, basic, settings.LEMKE_COVERS) != lemke.SOLVED
    status = lemke.lemke_perturbed(M, q, z, basic, settings.LEMKE_COVERS_LAST)
    assert status == lemke.SOLVED
    _assert_solves(M, q, z)


def test_a_frame_whose_island_sticks_everywhere_tries_the_last_covering_vectors():
    """A frame of the falling 20-disc pile with mu = 0.5 (t = 0.645 s): one island of 38
    contacts, every one sticking (its slides, at |v_t| <= 1.9e-4 m/s, stuck as slow). It cannot
    be held, and none of the first settings.LEMKE_COVERS covering vectors solves its friction
    LCP; with nothing left to stick, that failure would end the run, so the modes' decision
    (runtime.solve.friction.FrictionalForces) tries the LEMKE_COVERS_LAST of a final solve.
    The forces found obey the contact and Coulomb conditions (numpy, from the rows)."""
    data = np.load(DATA / "friction_all_sticking.npz")
    rows = FrictionRows(**{name: data[name] for name in FrictionRows.__dataclass_fields__})
    m = rows.mu.size
    forces = friction.FrictionalForces(_with_friction(falling_pile(20), 0.5))
    forces.stick_speed = 2e-4  # every contact sticks at first
    problem = SimpleNamespace(offsets=data["offsets"], basis=np.zeros(m, np.int8), slide=None)
    with pytest.raises(FrictionInconsistent):
        forces._solve(problem, rows, np.zeros(m), final=False)
    problem.basis[:] = 0
    solution = forces.solve(problem, rows)
    acc, f_n, f_t = solution.accelerations, solution.forces, solution.tangent_forces
    b1, b2 = rows.body1, rows.body2

    def rates(jac, bias):
        return (jac[:, :3] * acc[b1]).sum(1) + (jac[:, 3:] * acc[b2]).sum(1) + bias

    d2, a_t = rates(rows.jacobian, rows.bias), rates(rows.tangent_jacobian, rows.tangent_bias)
    scale = np.abs(d2).max() + np.abs(a_t).max() + 9.81
    assert f_n.min() >= 0.0 and d2.min() >= -1e-9 * scale
    assert np.abs(f_n * d2).max() <= 1e-9 * scale * f_n.max()
    limit, slide = 0.5 * f_n, problem.slide
    assert np.all(np.abs(f_t) <= limit * (1 + 1e-9) + 1e-13 * f_n.max())
    sticks = slide == 0
    inside = sticks & (np.abs(f_t) < limit * (1 - 1e-6))
    np.testing.assert_allclose(a_t[inside], 0.0, atol=1e-9 * scale)
    assert np.all(f_t[sticks] * a_t[sticks] <= 1e-9 * scale * f_n.max())  # it opposes a slip
    # a contact that slides (from rest: v_t ~ 0) takes mu f_n against its way and moves that way
    np.testing.assert_allclose(f_t[~sticks], -slide[~sticks] * limit[~sticks], rtol=1e-12)
    assert np.all(slide[~sticks] * a_t[~sticks] >= -1e-9 * scale)
    assert (~sticks).any()  # it is not held: something slips


def test_a_path_that_meets_a_basis_again_ends_there(monkeypatch):
    """In rounding, Lemke's path can cycle: on the same 140-unknown problem, the path with one
    of the quasi-random covering vectors returns to a basis ~10 pivots after meeting it, and
    would run on to settings.LEMKE_PIVOTS x (n + 1) = 7,050 pivots (4 paths of a packed 60-disc
    pile's 660 unknowns so cost 18.5 s each). It ends as it meets a basis again: the bases are
    followed here apart from lemke's hash of them, pivot by pivot (the Python body of the
    compiled function, its pivots counted)."""
    data = np.load(DATA / "lemke_wrong_end.npz")
    M, q = data["M"], data["q"]
    n = q.size
    basis, met, pivot = list(range(n)), [], lemke._pivot

    def followed(T, rhs, row, col):
        pivot(T, rhs, row, col)
        basis[row] = col
        met.append(frozenset(basis))

    monkeypatch.setattr(lemke, "_pivot", followed)
    d = 0.1 + 0.9 * ((np.arange(n) * 0.6180339887498949 + 5 * 0.7548776662466927) % 1.0)
    z, basic = np.zeros(n), np.zeros(n, bool)
    assert lemke.lemke_covering.py_func(M, q, d, z, basic) == lemke.ITERATIONS
    assert len(met) < 2 * (n + 1)
    assert met[-1] in met[:-1]  # it stopped at the first basis met twice
    assert len(set(met[:-1])) == len(met) - 1


def test_a_pile_whose_trial_meets_a_painleve_configuration_goes_on():
    """The falling 20-disc pile with mu = 0.5 stopped at t = 0.672 s: an RK4 stage of the trial
    from a frame (21 contacts, 19 sliding at up to 1.4 cm/s) found no forces that obey the
    frame's modes -- they were consistent at the frame, not half a step on. Such a trial is
    now cut (runtime.step.stepper.Stepper._trial) and a new frame decides the modes again;
    the pile runs its second with Coulomb's law at every record and without overlap."""
    run = runtime.simulate(_with_friction(falling_pile(20), 0.5), duration=1.0, dt=1e-3)
    assert run.t[-1] >= 1.0 - 1e-12
    assert run.max_penetration < 1e-9
    for f_n, f_t in zip(run.contact_forces, run.friction_forces, strict=True):
        assert np.all(f_n >= 0.0)
        # (+ rounding, to the solver's aim, settings.LCP_SHARP of the largest force: |f_t| up
        # to 5.3e-12 N at f_n = 0 beside normal forces of ~30 N where the held island's LP,
        # HiGHS without presolve, chose its vertex)
        sharp = settings.LCP_SHARP * f_n.max(initial=1.0)
        assert np.all(np.abs(f_t) <= 0.5 * f_n * (1 + 1e-9) + sharp)


@pytest.mark.parametrize("searched", [False, True])
def test_a_cut_trial_ends_at_a_frame_and_the_step_goes_on(searched, monkeypatch):
    """A block sliding down a 30 degree incline with mu = 0.3 (scenes/block_on_incline.toml),
    stepped with every trial longer than 0.3 ms refused as a Painleve configuration would be:
    each step is cut into sub-steps of at most 0.3 ms, each from a frame, and the block still
    slides as the exact solution says, s = a t^2 / 2 along the slope with a = g (sin 30 -
    mu cos 30) (RK4 integrates a constant acceleration exactly). The cut trials are quiet, or
    (``searched``) sent through the event search, which finds nothing."""
    world = runtime.World(
        runtime.load_scene(Path(__file__).parents[2] / "scenes/block_on_incline.toml")
    )
    stepper, spans = world.stepper, []
    trajectory = stepper.trajectory

    def refusing(problem, q, v, h, a0):
        if h > 3e-4:
            raise painleve(np.array([0.3]), np.array([1.0]))
        spans.append(h)
        return trajectory(problem, q, v, h, a0)

    monkeypatch.setattr(stepper, "trajectory", refusing)
    if searched:
        monkeypatch.setattr(stepper, "_quiet", lambda *args: False)
    start = world.poses[1, :2].copy()
    for _ in range(10):
        world.step(1e-3)
    a = 9.81 * (np.sin(np.pi / 6) - 0.3 * np.cos(np.pi / 6))
    s = 0.5 * a * world.t**2
    slope = np.array([np.cos(np.pi / 6), np.sin(np.pi / 6)])
    np.testing.assert_allclose(world.poses[1, :2], start - s * slope, atol=1e-13)
    assert abs(world.t - 0.01) < 1e-15
    assert max(spans) <= 3e-4 and len(spans) >= 40  # every millisecond in four sub-steps or more
