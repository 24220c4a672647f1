"""Fuzz tests: random valid scenes never crash, lose data or blow up; random bad input always
gets a SceneError.

The strategies and the checks are in tests/strategies.py (shared with bench/soak.py, which runs
the same checks for minutes). Here every test runs with a fixed seed (``derandomize=True``) and
a bounded number of examples, so CI sees the same scenes every time and the file takes about a
minute of CPU (62 s measured on the shared 2-core machine; bench/soak.py is the long, random
version).

Properties of a run of a random valid scene (1-4 discs, convex polygons, rounded rectangles,
half discs and ellipses of sizes 1e-3 .. 1e3 m, some at angles of up to 1e11 turns, on a floor
or in a box, see strategies.drawn_scenes; and 2-3 bodies flying at each other in empty space,
strategies.moving_pairs, where momentum is conserved as well):

* loading never fails (the scene is valid; a SceneError is a generator bug);
* simulate raises nothing but SimulationError, whose message names the step and the time and
  whose ``.state`` is finite;
* no NaN or inf anywhere in what was recorded, and no NumPy RuntimeWarning on the way;
* energy never grows by more than ``ENERGY_BOUND`` (1e-6) times the scene's energy scale
  (sum of m (V^2 + g (height + L)), V a bound on the speeds): there is no friction and
  restitution <= 1, so any growth is integration or impact error (RK4 and midpoint only:
  explicit Euler gains energy in free fall by construction);
* penetration, measured at every recorded step by the exact contact gaps and by sampled
  boundary points (which also catch contacts too deep for the contact finder), stays below
  ``PENETRATION_BOUND`` (1e-3; explicit Euler, first order: 1e-2) half-widths of the thinnest
  body, and no centre of mass ends up below the floor or outside the box (tunnelling);
* a second run of the same scene gives a bitwise identical trajectory, in the same process
  and in two fresh interpreters with different hash seeds.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import strategies as S
from hypothesis import HealthCheck, Phase, find, given, settings
from hypothesis import strategies as st

import runtime
from runtime.io.scene_file import SceneError, load_scene, scene_from_dict


def fuzz(examples: int) -> settings:
    """Fixed seed, bounded examples, no deadline (a run takes 10-500 ms), no example database
    (CI starts clean; the seed makes the examples the same anyway)."""
    return settings(
        derandomize=True,
        max_examples=examples,
        deadline=None,
        database=None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    )


def _explain(report: S.Report) -> str:
    return f"{report.problems}\nscene: {report.drawn.data!r}"


# -- random valid scenes ----------------------------------------------------------------------


@fuzz(70)
@given(S.drawn_scenes())
def test_random_scenes_run_without_crash_nan_energy_growth_or_penetration(drawn):
    report = S.check_scene(drawn)
    assert not report.failures("simulation"), _explain(report)


@fuzz(30)
@given(S.drawn_scenes(elastic=True, method="rk4", steps=(20, 40)))
def test_elastic_scene_energy_stays_within_the_bound(drawn):
    """Frictionless, restitution 1, RK4: E(t) <= E(0) + 1e-6 x the energy scale."""
    report = S.check_scene(drawn)
    assert not report.failures("simulation"), _explain(report)
    if report.run is not None and len(report.run.t):
        energy = np.asarray(report.run.energy)
        assert np.max(energy - energy[0]) <= S.ENERGY_BOUND * drawn.energy_scale


@fuzz(30)
@given(S.drawn_scenes(max_bodies=3, densities=9.0))
def test_mass_ratios_up_to_1e9_run_without_crash_energy_growth_or_penetration(drawn):
    """Densities over nine decades (10 .. 1e10 kg/m^2; with the sizes, mass ratios beyond 1e9):
    the contact matrices' condition numbers reach ~1e9, and the properties above still hold."""
    report = S.check_scene(drawn)
    assert not report.failures("simulation"), _explain(report)


@fuzz(20)
@given(S.moving_pairs(elastic=True))
def test_moving_pairs_at_high_speed_meet_exactly(drawn):
    """2-3 bodies flying at each other in empty space (S.moving_pairs), 0.5-8 half-widths of
    the thinnest body a step (2 and 8: they would pass through each other between two steps),
    sizes 1e-4 .. 1e4 m, mass ratios beyond 1e9, large angles, ovals: no error of any kind (a
    guard tripping is a failure here: nothing needs one), no overlap beyond 1e-3 half-widths
    (sampled), linear momentum kept to 1e-9, angular momentum to 1e-6, energy not growing."""
    report = S.check_scene(drawn)
    assert not report.problems, _explain(report)


@fuzz(25)
@given(S.moving_pairs(travel=0.5))
def test_moving_pairs_that_stick_or_bounce_meet_exactly(drawn):
    """The same with any restitution (plastic pairs stay in contact and turn together) at
    half a half-width a step."""
    report = S.check_scene(drawn)
    assert not report.problems, _explain(report)


@fuzz(15)
@given(S.drawn_scenes(max_bodies=3))
def test_runs_are_bitwise_reproducible(drawn):
    runs = []
    for _ in range(2):
        scene = scene_from_dict(drawn.data, source="fuzz")
        try:
            runs.append(runtime.simulate(scene))
        except runtime.SimulationError as exc:
            runs.append(exc.run)
    first, second = (r.arrays() for r in runs)
    assert first.keys() == second.keys()
    for key in first:
        a, b = np.asarray(first[key]), np.asarray(second[key])
        assert a.shape == b.shape and a.tobytes() == b.tobytes(), key  # bitwise, NaN and -0 too
    assert runs[0].rhs_evaluations == runs[1].rhs_evaluations


_DIGEST = """
import hashlib, sys, numpy as np, runtime
run = runtime.simulate(runtime.load_scene(sys.argv[1]), duration=0.25)
digest = hashlib.sha256()
for key, values in sorted(run.arrays().items()):
    digest.update(key.encode() + np.ascontiguousarray(values).tobytes())
print(digest.hexdigest(), len(run.impact_times))
"""


def test_runs_are_bitwise_reproducible_across_processes():
    """The same scene in two fresh interpreters with different hash seeds (set and dict order
    of anything keyed by str) gives the same bytes: 20 discs dropping into a box, 13 impacts."""
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    outputs = []
    for seed in ("1", "2"):
        done = subprocess.run(
            [sys.executable, "-c", _DIGEST, str(root / "scenes" / "disc_pile.toml")],
            cwd=root,
            env={"PYTHONHASHSEED": seed, "PATH": str(Path(sys.executable).parent)},
            capture_output=True,
            text=True,
            check=True,
        )
        outputs.append(done.stdout.split())
    assert outputs[0] == outputs[1]
    assert int(outputs[0][1]) > 0  # the run has impacts, not just free fall


_REACHED = {
    "small scale": lambda d: 1e-3 <= d.scale < 3e-3,
    "large scale": lambda d: 3e2 < d.scale <= 1e3,
    "four bodies": lambda d: len(d.bodies) - 1 == 4,
    **{
        kind: lambda d, k=kind: any(b["shape"]["type"] == k for b in d.bodies[1:])
        for kind in S.SHAPE_KINDS
    },
    **{env: lambda d, e=env: d.environment == e for env in S.ENVIRONMENTS},
    **{method: lambda d, m=method: d.data["simulation"]["method"] == m for method in S.METHODS},
}


@pytest.mark.parametrize("what", list(_REACHED))
def test_the_strategy_spans_six_orders_of_magnitude_and_every_shape(what):
    """The examples above come from this range: both ends of the scale, every shape kind,
    environment and method are reached. Searched for (hypothesis.find), not counted in a sample:
    300 draws missed the small end under some seeds (the examples differ between machines)."""
    condition = _REACHED[what]
    found = find(
        S.drawn_scenes(),
        condition,
        settings=settings(max_examples=3000, database=None, phases=[Phase.generate]),
    )
    assert condition(found), what
    assert 1e-3 <= found.scale <= 1e3 and 1 <= len(found.bodies) - 1 <= 4  # never beyond


# -- random bad input -----------------------------------------------------------------------


def _scene_error_is_well_formed(message: str, source: str) -> None:
    assert message.startswith(f"{source}: "), message
    assert "\n" not in message, message
    assert "field '" in message or "expected a table" in message, message


@fuzz(200)
@given(S.mutated_scenes())
def test_mutated_scene_gets_a_scene_error_or_runs_cleanly(case):
    """One value replaced (NaN, inf, negative, extreme, wrong type), one key added or removed:
    the loader raises SceneError naming the source and the field, or, if the scene is still
    valid, a few steps run without any exception but SimulationError and without NaN."""
    data, what = case
    try:
        scene = scene_from_dict(data, source="mutant")
    except SceneError as exc:
        assert exc.__cause__ is None and exc.__suppress_context__, what
        _scene_error_is_well_formed(str(exc), "mutant")
        return
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            run = runtime.simulate(scene, duration=3 * scene.simulation.dt)
        except runtime.SimulationError as exc:
            run = exc.run
    assert not [w for w in caught if issubclass(w.category, RuntimeWarning)], (what, caught)
    for key, values in run.arrays().items():
        if key != "min_gap":  # +inf there means "no contact"
            assert np.all(np.isfinite(values)), (what, key)


@fuzz(100)
@given(st.binary(max_size=300) | st.text(max_size=300).map(lambda t: t.encode()))
def test_any_file_content_gets_a_scene_error_or_loads(tmp_path_factory, content):
    path = tmp_path_factory.mktemp("fuzz") / "random.toml"
    path.write_bytes(content)
    try:
        load_scene(path)
    except SceneError as exc:
        assert str(exc).startswith(f"{path}: ") and "\n" not in str(exc)


@fuzz(100)
@given(
    st.recursive(
        st.none() | st.booleans() | st.floats() | st.integers() | st.text(max_size=8),
        lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner),
        max_leaves=12,
    )
)
def test_any_value_in_any_body_field_gets_a_scene_error(value):
    """Every body field and shape parameter, given an arbitrary TOML-like value."""
    base = {"name": "b", "shape": {"type": "disc", "radius": 0.1}, "density": 1.0,
            "position": [0.0, 1.0]}  # fmt: skip
    for key in (*sorted(base), "mass", "inertia", "angle", "velocity", "restitution", "fixed"):
        for where in ("body", "shape"):
            body = {**base, "shape": dict(base["shape"])}
            (body if where == "body" else body["shape"])[key] = value
            try:
                scene_from_dict({"body": [body]}, source="any")
            except SceneError as exc:
                _scene_error_is_well_formed(str(exc), "any")


def test_the_escape_check_tells_a_wall_crossing_from_a_flight_over_the_top():
    """The soak's six "silent escapes" at 30x coarse steps were light bodies (mass ratios up to
    1e7) thrown out over the open box's walls by heavy ones, energy kept to 4e-6 J of 3e4 J: no
    escape. A centre through a side wall below its top, or through the floor, still is one."""
    drawn = S.Drawn({}, 1.0, 0.01, 1e-3, 1.0, 1.0, "box", 2.0, True, wall_top=5.0)
    over = np.array([[1.5, 5.5], [1.9, 6.0], [2.2, 6.1], [2.5, -3.0]])  # then falls outside
    assert S._escape(over, drawn) is None
    through = np.array([[1.5, 4.0], [1.9, 4.9], [2.3, 5.2]])  # crosses x = 2 at y = 4.975
    assert S._escape(through, drawn) == 2
    assert S._escape(np.array([[0.0, 1.0], [0.0, -0.5]]), drawn) == 1  # through the floor
    assert S._escape(np.array([[0.0, 1.0], [1.0, 4.0]]), drawn) is None
