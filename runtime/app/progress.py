"""Progress of a run on stderr: a redrawn bar on a terminal, a line every few seconds elsewhere.

Why both: on a terminal a bar redrawn in place is the least noise; in a log file, a CI job or a
pipe, carriage returns pile up into one unreadable line, so there a plain line is written every
``interval`` seconds instead.  Both are fed by the ``progress`` callback of
:func:`runtime.simulate` (the fraction of the simulated time done) and stay silent for the first
``delay`` seconds, so short runs print nothing.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import TextIO

from runtime.app.text import human_seconds

__all__ = ["ProgressBar", "ProgressLines", "remaining"]


def remaining(elapsed: float, fraction: float) -> str:
    """'~12 s left' from the rate so far, or '' before any progress."""
    if not fraction > 0:
        return ""
    left = elapsed * (1.0 - fraction) / fraction
    return f"~{human_seconds(left)} left" if math.isfinite(left) else ""


class ProgressBar:
    """A one-line text bar redrawn in place (for a terminal); at most every ``interval`` s."""

    def __init__(
        self,
        stream: TextIO,
        *,
        delay: float = 2.0,
        interval: float = 0.2,
        width: int = 30,
        clock: Callable[[], float] = time.perf_counter,
    ) -> None:
        self.stream, self.clock = stream, clock
        self.delay, self.interval, self.width = delay, interval, width
        self.start = clock()
        self.last_draw = -math.inf
        self.drawn = False

    def __call__(self, fraction: float) -> None:
        now = self.clock()
        elapsed = now - self.start
        if elapsed < self.delay or now - self.last_draw < self.interval:
            return
        self.last_draw = now
        fraction = min(max(float(fraction), 0.0), 1.0)
        filled = int(round(self.width * fraction))
        bar = "#" * filled + "." * (self.width - filled)
        self.stream.write(
            f"\r[{bar}] {100 * fraction:5.1f}%  {elapsed:.0f} s  {remaining(elapsed, fraction)}   "
        )
        self.stream.flush()
        self.drawn = True

    def close(self) -> None:
        """Erase the bar (if one was drawn): the summary line that follows replaces it."""
        if self.drawn:
            self.stream.write("\r" + " " * (self.width + 40) + "\r")
            self.stream.flush()
            self.drawn = False


class ProgressLines:
    """A plain line per ``interval`` s (for a log, a pipe, CI):
    ``simulate: 41% (t = 4.1 of 10 s simulated), 12 s elapsed, ~17 s left``."""

    def __init__(
        self,
        stream: TextIO,
        duration: float,
        *,
        prog: str = "simulate",
        delay: float = 5.0,
        interval: float = 5.0,
        clock: Callable[[], float] = time.perf_counter,
    ) -> None:
        self.stream, self.clock, self.prog = stream, clock, prog
        self.duration, self.delay, self.interval = duration, delay, interval
        self.start = clock()
        self.next = self.start + delay

    def __call__(self, fraction: float) -> None:
        now = self.clock()
        if now < self.next:
            return
        self.next = now + self.interval
        fraction = min(max(float(fraction), 0.0), 1.0)
        elapsed = now - self.start
        left = remaining(elapsed, fraction)
        self.stream.write(
            f"{self.prog}: {100 * fraction:.3g}% (t = {fraction * self.duration:.4g} of "
            f"{self.duration:.4g} s simulated), {elapsed:.0f} s elapsed"
            f"{', ' + left if left else ''}\n"
        )
        self.stream.flush()

    def close(self) -> None:
        """Nothing to erase: the lines stay in the log."""
