"""Long runs, shortened for CI: the per-step bounds of bench/long_runs.py on fewer steps.

bench/long_runs.py runs 10^5 steps (RK4, dt = 1 ms, no stabilisation) of the disc in the bowl and
of the stack of 5 rounded blocks; the figures are in bench/README.md ("## Long runs") and the
bounds are explained in docs/numerics.md (section 3). Both drifts grow with the step number k
like a k + b k^2 (the k^2 part: a systematic residual of d'' at the resting contacts, integrated
twice, and the work the contact force does on the resulting d'); the coefficients (in
bench/long_runs.py) are about 10x the measured 10^5-step values, and CI checks them at every
step of 5*10^3 steps:

* |E(k) - E(0)| <= |E(0)| (a_E k + b_E k^2) + 4 ulp(E(0))         (energy drift)
* |gap(k)| (bowl) or penetration(k) (stack) <= a_d k + b_d k^2 + 4 ulp(1 m)   (constraint drift)

and nothing may be NaN or fail (runtime.simulate raises SimulationError on a solver failure).
"""

from __future__ import annotations

import functools
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import runtime
from bench import long_runs

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "scenes"
G = 9.81
DT = 1e-3
# steps in CI (the bench runs 10^5)
STEPS = {"disc_in_bowl": 5_000, "rounded_stack": 5_000}
# The per-step laws a k + b k^2 live in bench/long_runs.py (ENERGY_LAW, GAP_LAW), which checks
# them over 10^5 steps; measured there (bench/README.md):
#   bowl:  energy 1.1e-9 relative (2.7e-16 k over the first 10^3 steps, then ~1.1e-19 k^2),
#          gap 9.6e-10 m (~9.6e-20 k^2), never negative
#   stack: energy 0, penetration 5.6e-13 m (1.9e-18 k at first, then ~5.6e-23 k^2)


def ulp(x: float) -> float:
    return float(np.spacing(abs(float(x))))


@functools.cache
def _long_run(name: str):
    scene = runtime.load_scene(SCENES / f"{name}.toml")
    return name, scene, runtime.simulate(scene, STEPS[name] * DT, DT, "rk4")


@pytest.fixture(params=list(STEPS))
def long_run(request):
    return _long_run(request.param)


def _steps(run) -> np.ndarray:
    return np.rint(np.asarray(run.t) / DT)


def test_long_run_is_finite_and_complete(long_run):
    name, _, run = long_run
    assert len(run.t) == STEPS[name] + 1
    assert np.all(np.isfinite(np.asarray(run.poses)))
    assert np.all(np.isfinite(np.asarray(run.velocities)))
    assert all(np.all(np.isfinite(f)) for f in run.contact_forces)
    assert run.impact_times.size == 0  # both scenes start touching exactly and never collide


def test_long_run_energy_drift_per_step(long_run):
    name, _, run = long_run
    energy = np.asarray(run.energy)
    k = _steps(run)
    drift = np.abs(energy - energy[0])
    bound = long_runs.energy_bound(name, energy[0], k)
    worst = int(np.argmax(drift - bound))
    print(
        f"\n[long run] {name}: energy drift {drift.max():.3g} J ({drift.max() / abs(energy[0]):.2g})"
    )
    assert np.all(drift <= bound), f"step {k[worst]:.0f}: drift {drift[worst]:.3g} J"


def test_long_run_constraint_drift_per_step(long_run):
    """The bowl's one contact may drift either way (|gap|); the stack's contacts may only
    penetrate (their largest gap is 0). Run.min_gap must agree with the contact finder."""
    name, scene, run = long_run
    k = _steps(run)
    gaps = np.asarray(run.min_gap)
    drift = long_runs.constraint_drift(name, gaps)
    bound = long_runs.gap_bound(name, k)
    print(f"\n[long run] {name}: constraint drift {drift.max():.3g} m")
    assert np.all(drift <= bound), f"step {k[np.argmax(drift - bound)]:.0f}: {drift.max():.3g} m"
    for j in np.linspace(0, len(run.poses) - 1, 6).astype(int):
        found = min(scene.contacts(run.poses[j]).gap)
        assert abs(found - gaps[j]) <= 4 * ulp(1.0)


def test_long_run_disc_in_bowl_follows_the_pendulum():
    """Phase error against the exact pendulum (solve_ivp at rtol 1e-12): RK4's global error is
    O(dt^4) per unit time (omega dt = 3.3e-3), below 1e-9 rad over 5 s (measured ~1e-11)."""
    _, scene, run = _long_run("disc_in_bowl")
    disc = scene.index("disc")
    poses = np.asarray(run.poses)[:, disc]
    phi = np.arctan2(poses[:, 0], -poses[:, 1])
    sol = solve_ivp(
        lambda _t, y: [y[1], -G / 0.9 * math.sin(y[0])],
        (0.0, run.t[-1]),
        [0.3, 0.0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-14,
        t_eval=run.t,
    )
    error = np.max(np.abs(phi - sol.y[0]))
    print(f"\n[long run] disc_in_bowl: phase error {error:.3g} rad")
    assert error < 1e-9


def test_long_run_stack_stays_put():
    """The blocks start exactly at rest on each other (binary fractions) and may only creep by
    rounding; sideways is a neutral direction of a frictionless stack and the creep grows like
    ~k^3 (steeper late in the 10^5-step bench, docs/numerics.md): asserted
    <= CREEP_LAW k^3 + 4 ulp(1) at every step."""
    _, scene, run = _long_run("rounded_stack")
    moving = [i for i, b in enumerate(scene.bodies) if not b.fixed]
    crept = long_runs.creep(run.poses, moving)
    bound = long_runs.creep_bound(_steps(run))
    print(f"\n[long run] rounded_stack: creep {crept.max():.3g}")
    assert np.all(crept <= bound), f"step {_steps(run)[np.argmax(crept - bound)]:.0f}"
