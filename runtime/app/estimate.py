"""How long a run will take and how much memory its record needs, told before it starts.

Why: ``--duration 1e9`` or a fine ``--dt`` on a large scene asks for years of computing and
more memory than the machine has, and nothing said so until the machine ran out.  A run whose
step count times its body count reaches settings.PROBE_FROM is first *probed*: up to
settings.PROBE_STEPS steps (at most settings.PROBE_SECONDS of wall time) are run and timed, the
median step time scaled by the step count gives the time; a second, shorter probe under
``tracemalloc`` measures the memory the run's record holds per recorded step (every step is
recorded), which scaled the same way gives the memory.  Both are estimates from the start of the
run: a scene whose contacts multiply later takes longer.
"""

from __future__ import annotations

import math
import os
import statistics
import time
import tracemalloc
from dataclasses import dataclass
from typing import Any

from runtime import settings
from runtime.app.text import human_bytes, human_seconds

__all__ = ["Estimate", "per_step_times", "probe", "warning"]


@dataclass(frozen=True)
class Estimate:
    """A run of ``steps`` steps, from a probe of ``probe_steps`` steps."""

    steps: int
    seconds_per_step: float
    bytes_per_step: float
    probe_steps: int

    @property
    def seconds(self) -> float:
        return self.steps * self.seconds_per_step

    @property
    def bytes(self) -> float:
        return (self.steps + 1) * self.bytes_per_step


class _ProbeDone(Exception):
    """Raised from the progress callback to end a probe early."""


def _timed(scene: Any, dt: float, method: str, steps: int) -> list[float]:
    """Wall time of each step of a short run (at most PROBE_SECONDS after the first step, which
    also sets up the engine: compiled code loaded, or compiled on a fresh machine). A stretch of
    steps that `simulate` coasts in one call (runtime.step.coast) reports its progress once:
    each of its steps counts its share of the stretch's time."""
    import runtime

    marks: list[tuple[float, float]] = [(time.perf_counter(), 0.0)]  # (time, fraction done)

    def tick(fraction: float) -> None:
        marks.append((time.perf_counter(), fraction))
        if marks[-1][0] - marks[1][0] > settings.PROBE_SECONDS:
            raise _ProbeDone

    off = runtime.Guards(penetration=None, energy_growth=None)
    try:
        runtime.simulate(scene, steps * dt, dt, method, progress=tick, guards=off)
    except (_ProbeDone, runtime.SimulationError):
        pass
    return per_step_times(marks, steps)


def per_step_times(marks: list[tuple[float, float]], steps: int) -> list[float]:
    """Wall time of each step of a run of ``steps`` steps from its progress ``marks`` ((time,
    fraction done), the first at the start): the steps of a stretch that `simulate` coasted in
    one call (runtime.step.coast), reported at once, share its time evenly."""
    times: list[float] = []
    for (t0, f0), (t1, f1) in zip(marks, marks[1:], strict=False):
        done = round((f1 - f0) * steps)
        times += [(t1 - t0) / max(done, 1)] * done
    return times


def _memory_per_step(scene: Any, dt: float, method: str, steps: int) -> float:
    """Bytes held by a run's record per recorded step (tracemalloc: what stays allocated)."""
    import runtime

    off = runtime.Guards(penetration=None, energy_growth=None)
    tracemalloc.start()
    try:
        base = tracemalloc.get_traced_memory()[0]
        run = runtime.simulate(scene, steps * dt, dt, method, guards=off)
        held = tracemalloc.get_traced_memory()[0] - base
    except runtime.SimulationError:
        return math.nan
    finally:
        tracemalloc.stop()
    return held / max(len(run.t), 1)


def probe(scene: Any, steps: int, dt: float, method: str) -> Estimate | None:
    """An estimate for ``steps`` steps of ``scene``, or None when the run is too small to
    probe (steps x bodies below settings.PROBE_FROM) or the probe fails at once."""
    if steps * max(len(scene.bodies), 1) < settings.PROBE_FROM:
        return None
    times = _timed(scene, dt, method, settings.PROBE_STEPS)
    if not times:
        return None
    per_step = statistics.median(times[1:] or times)
    traced = max(1, min(5, len(times), int(settings.PROBE_SECONDS / (3.0 * per_step))))
    memory = _memory_per_step(scene, dt, method, traced)  # tracemalloc: ~3x slower steps
    return Estimate(steps, per_step, memory, len(times))


def _memory_limit() -> float:
    try:
        physical = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError):
        return settings.WARN_BYTES
    return min(settings.WARN_BYTES, 0.5 * physical)


def warning(estimate: Estimate | None, bodies: int) -> str | None:
    """The one-line warning for a run expected to take longer than settings.WARN_SECONDS or to
    need more memory than settings.WARN_BYTES (or half the machine's), else None."""
    if estimate is None:
        return None
    memory_known = math.isfinite(estimate.bytes_per_step)
    long = estimate.seconds > settings.WARN_SECONDS
    big = memory_known and estimate.bytes > _memory_limit()
    if not (long or big):
        return None
    memory = f"~{human_bytes(estimate.bytes)} of memory" if memory_known else "memory unknown"
    per_step = f"{1e3 * estimate.seconds_per_step:.2g} ms"
    if memory_known:
        per_step += f" and {human_bytes(estimate.bytes_per_step)}"
    return (
        f"{estimate.steps:.3g} steps of {bodies} bodies: expect ~{human_seconds(estimate.seconds)} "
        f"and {memory} to record them ({per_step} per step in a {estimate.probe_steps}-step "
        "probe); Ctrl-C stops the run, a larger --dt or a shorter --duration shortens it"
    )
