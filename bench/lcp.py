"""Contact-force solve benchmark (`make bench`): time per solve of resting piles, before/after.

The engine solves the contact LCP at every integrator stage (four times per RK4 step) for each
contact island, and from one stage to the next the clamped set rarely changes. So this times
one solve of the LCP of a resting pile of discs in a box (bench/steps.py's pile_scene: every
disc in the notch of two below it, the long rows wall to wall) with 10, 100 and 1,000
contacts, cold (no guess) and warm (the previous solve's clamped set), for:

- after: ``runtime.lcp.solve`` (islands, validation, cold), ``solve_warm`` cold and warm (the
  engine's entry: dense compiled up to settings.LCP_DENSE_MAX rows, sparse above; A given
  dense up to that size and sparse above, as the engine would build it), and the compiled core
  ``solve_dense`` warm (what compiled engine code would call);
- before: the solver as it was (bench/lcp_baseline.py: Baraff's pivoting in NumPy) cold, and
  the warm start the engine used with it (``solve_with_guess``: a dense solve of the block);
- projected Gauss-Seidel with 10 and 100 sweeps from zero (compiled, on the sparse A), the
  iterative method engines often use instead;
- scipy's bound-constrained QP (min 1/2 f.A f + b.f, f >= 0, L-BFGS-B), for reference only.

A and b are built from the pile's geometry (each contact's normal through the two centres,
masses from the scene), not through the engine's step, so the benchmark does not depend on it.
Every method's residual is reported: the largest violation of the contact conditions
(|a| where f > 0, -a where f = 0, in m/s^2), and relative to each row's size
sum_j |A_ij f_j| + |b_i| (the solver's measure; settings.LCP_TOL = 1e-9 accepts).

Timing is timeit-style, in CPU time of the process (the machine is shared: wall time would
time the other processes' load): calls looped to >= MIN_RUN seconds, the best of REPEATS runs;
a solve that takes longer than a run is timed once; one that exceeds BUDGET (of wall time) is
cut and reported as a lower bound. BLAS runs on one thread (the module re-executes itself with
OPENBLAS_NUM_THREADS=1): on the shared 2-core machine OpenBLAS's threads made a 92 x 153
product take 31 ms instead of 0.15 ms, which would have timed the machine's load, not the
methods (the compiled solver uses no BLAS).

    python -m bench.lcp            # rewrites the "## Contact forces" section of bench/README.md
    python -m bench.lcp --quick    # 10 and 100 contacts, short runs, README untouched
"""

from __future__ import annotations

import argparse
import datetime
import gc
import os
import platform
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy
import scipy.sparse as sp
from scipy.optimize import minimize

from bench import lcp_baseline
from bench.machine import cpu
from bench.markdown import replace_section
from bench.steps import RADIUS, OutOfTime, deadline, pile_scene
from runtime import settings
from runtime.compiled import njit
from runtime.solve import lcp

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "bench" / "README.md"
SECTION = "## Contact forces"
SIZES = (10, 100, 1000)  # contacts (the pile gets the first disc count reaching each)
G = 9.81
MIN_RUN = 0.2  # s per timed run
REPEATS = 5
BUDGET = 120.0  # s for one solve before it is cut


@dataclass
class Problem:
    discs: int
    A: sp.csr_array
    b: np.ndarray

    @property
    def dense(self) -> np.ndarray:
        return np.ascontiguousarray(self.A.toarray())


def pile_problem(contacts: int) -> Problem:
    """The LCP of the smallest resting pile with at least ``contacts`` contacts."""
    discs = max(2, contacts // 2)
    while True:
        problem = _pile(discs)
        if len(problem.b) >= contacts:
            return problem
        discs += 1


def _pile(discs: int) -> Problem:
    scene = pile_scene(discs)
    bodies = [body for body in scene.bodies if not body.fixed]
    centre = np.array([body.position for body in bodies])
    mass = np.array([body.mass for body in bodies])
    half = np.max(np.abs(centre[:, 0])) + RADIUS  # the long rows touch both walls
    touch = 1e-9 * RADIUS
    rows: list[tuple[int, int, np.ndarray]] = []
    for i, (x, y) in enumerate(centre):
        for ok, normal in (
            (abs(y - RADIUS) < touch, (0.0, 1.0)),
            (abs(x - RADIUS + half) < touch, (1.0, 0.0)),
            (abs(x + RADIUS - half) < touch, (-1.0, 0.0)),
        ):
            if ok:
                rows.append((i, -1, np.array(normal)))
    apart = centre[:, None, :] - centre[None, :, :]
    distance = np.hypot(apart[..., 0], apart[..., 1])
    for i, j in zip(*np.nonzero(np.abs(distance - 2 * RADIUS) < touch), strict=True):
        if centre[i, 1] > centre[j, 1]:  # the normal from the disc below to the one above
            rows.append((i, j, apart[i, j] / distance[i, j]))
    J = sp.lil_array((len(rows), 2 * len(bodies)))
    for k, (i, j, normal) in enumerate(rows):
        J[k, 2 * i : 2 * i + 2] = normal
        if j >= 0:
            J[k, 2 * j : 2 * j + 2] = -normal
    J = sp.csr_array(J)
    A = sp.csr_array(J @ sp.diags_array(np.repeat(1.0 / mass, 2)) @ J.T)
    gravity = np.zeros(2 * len(bodies))
    gravity[1::2] = -G
    return Problem(discs, A, J @ gravity)


def residual(A, b: np.ndarray, f: np.ndarray) -> tuple[float, float]:
    """(largest violation in m/s^2, largest relative to its row's size) of the conditions."""
    a = A @ f + b
    violation = np.where(f > 0, np.abs(a), np.maximum(-a, 0.0))
    violation = np.maximum(violation, np.maximum(-f, 0.0) * A.diagonal())
    size = abs(A) @ np.abs(f) + np.abs(b)
    return float(np.max(violation)), float(np.max(violation / np.maximum(size, 1e-300)))


@njit
def _pgs(indptr, indices, data, diag, b, f, sweeps):
    """Projected Gauss-Seidel sweeps on a symmetric CSR A (row i is column i), in place."""
    m = b.size
    a = b.copy()
    for i in range(m):
        for p in range(indptr[i], indptr[i + 1]):
            a[i] += data[p] * f[indices[p]]
    for _ in range(sweeps):
        for i in range(m):
            fi = max(0.0, f[i] - a[i] / diag[i])
            step = fi - f[i]
            if step != 0.0:
                for p in range(indptr[i], indptr[i + 1]):
                    a[indices[p]] += step * data[p]
                f[i] = fi


def pgs(A: sp.csr_array, b: np.ndarray, sweeps: int) -> np.ndarray:
    f = np.zeros(len(b))
    _pgs(A.indptr, A.indices, A.data, A.diagonal(), b, f, sweeps)
    return f


def scipy_qp(A: sp.csr_array, b: np.ndarray) -> np.ndarray:
    """min 1/2 f.A f + b.f with f >= 0 (its KKT conditions are the LCP), L-BFGS-B defaults."""
    result = minimize(
        lambda f: (0.5 * f @ (A @ f) + b @ f, A @ f + b),
        np.zeros(len(b)),
        jac=True,
        bounds=[(0.0, None)] * len(b),
        method="L-BFGS-B",
    )
    return result.x


def time_call(fn) -> tuple[float, object, bool]:
    """(best seconds per call, the last result, finished) -- timeit-style, see the module
    docstring; ``finished`` is False if a single call ran past BUDGET (then a lower bound).
    A first call (compiling what it needs) is not counted unless it took over 10 s. Garbage
    collection runs before each measurement and is off only within the loops of short calls."""
    for _ in range(2):
        gc.collect()
        start = time.process_time()
        try:
            with deadline(BUDGET):
                result = fn()
        except OutOfTime:
            return time.process_time() - start, None, False
        once = time.process_time() - start
        if once > 10.0:
            break
    if once > MIN_RUN:
        return once, result, True
    calls = max(1, int(MIN_RUN / max(once, 1e-7)))
    best = once
    for _ in range(REPEATS):
        gc.collect()
        gc.disable()
        try:
            start = time.process_time()
            for _ in range(calls):
                result = fn()
            best = min(best, (time.process_time() - start) / calls)
        finally:
            gc.enable()
    return best, result, True


def methods(problem: Problem) -> list[tuple[str, object]]:
    """(name, call returning f) of every method timed, warm ones primed with their guess."""
    A, b, dense = problem.A, problem.b, problem.dense
    m = len(b)
    given = dense if m <= settings.LCP_DENSE_MAX else A  # as the engine would build it
    f, clamped = lcp.solve_warm(given, b)
    old = f > 0.0  # the old warm start's guess: the contacts with a force
    none = np.zeros(m, bool)
    f_out, held = np.empty(m), np.empty(m, bool)

    def core() -> np.ndarray:
        lcp.solve_dense(dense, b, none, clamped, 0.0, f_out, held)
        return f_out.copy()

    def before_warm() -> np.ndarray:
        f = lcp_baseline.solve_with_guess(dense, b, old)
        return lcp_baseline.solve(dense, b) if f is None else f

    return [
        ("after: `lcp.solve` (cold, islands)", lambda: lcp.solve(given, b)),
        ("after: `lcp.solve_warm`, cold", lambda: lcp.solve_warm(given, b)[0]),
        ("after: `lcp.solve_warm`, warm", lambda: lcp.solve_warm(given, b, guess=clamped)[0]),
        ("after: `lcp.solve_dense` (compiled, dense A), warm", core),
        ("before: `lcp.solve` (Baraff, NumPy), cold", lambda: lcp_baseline.solve(dense, b)),
        ("before: warm start `solve_with_guess`", before_warm),
        ("PGS, 10 sweeps from 0 (compiled)", lambda: pgs(A, b, 10)),
        ("PGS, 100 sweeps from 0 (compiled)", lambda: pgs(A, b, 100)),
        ("scipy QP (L-BFGS-B), reference only", lambda: scipy_qp(A, b)),
    ]


def _time(seconds: float, finished: bool) -> str:
    text = (
        f"{seconds * 1e6:.3g} µs" if seconds < 1e-3 else
        f"{seconds * 1e3:.3g} ms" if seconds < 1 else f"{seconds:.3g} s"
    )  # fmt: skip
    return text if finished else f"> {text} (cut)"


def run(sizes) -> tuple[list[Problem], dict[str, list[str]]]:
    problems = [pile_problem(n) for n in sizes]
    cells: dict[str, list[str]] = {}
    for problem in problems:
        for name, call in methods(problem):
            seconds, f, finished = time_call(call)
            if f is None:
                cell = _time(seconds, finished)
            else:
                absolute, relative = residual(problem.A, problem.b, f)
                cell = f"{_time(seconds, finished)}; {absolute:.1e} ({relative:.0e})"
            cells.setdefault(name, []).append(cell)
            print(f"{len(problem.b):5d} contacts  {name}: {cell}", file=sys.stderr)
    return problems, cells


def section(problems: list[Problem], cells: dict[str, list[str]], wall: float) -> str:
    when = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    load = os.getloadavg()[0]
    head = " | ".join(f"{len(p.b)} contacts ({p.discs} discs)" for p in problems)
    lines = [
        SECTION,
        "",
        f"Written by `python -m bench.lcp` (`make bench`); run {when} on {cpu()}, Python "
        f"{platform.python_version()}, NumPy {np.__version__}, SciPy {scipy.__version__}; "
        f"{wall:.0f} s, 1-minute load average {load:.1f} at the end (other processes share "
        "the cores: CPU time of the process, best of several runs, one BLAS thread).",
        "",
        "One solve of the contact LCP of a resting pile of discs in a box (bench/steps.py's "
        "pile, A and b from its geometry). Each cell: time per solve; the largest violation "
        "of the contact conditions in m/s^2 (in brackets: relative to its row's size "
        "sum_j |A_ij f_j| + |b_i|, the solver's measure, LCP_TOL = 1e-9). *Warm*: from the "
        "previous solve's clamped set (the engine's case: the set rarely changes between RK "
        "stages). The after-solver returns the least-norm forces, so where the pile has "
        "redundant contacts its forces may differ from the others' while a is the same.",
        "",
        f"| method | {head} |",
        "|---|" + "---|" * len(problems),
    ]
    lines += [f"| {name} | {' | '.join(row)} |" for name, row in cells.items()]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> None:
    if os.environ.get("OPENBLAS_NUM_THREADS") != "1":  # see the module docstring
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
        os.execve(sys.executable, [sys.executable, "-m", "bench.lcp", *sys.argv[1:]], env)
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="10 and 100 contacts, no README")
    args = parser.parse_args(argv)
    global MIN_RUN, REPEATS, BUDGET
    if args.quick:
        MIN_RUN, REPEATS, BUDGET = 0.02, 2, 20.0
    start = time.perf_counter()
    lcp.solve_warm(pile_problem(10).A, pile_problem(10).b)  # compile (or load) first
    problems, cells = run(SIZES[:2] if args.quick else SIZES)
    text = section(problems, cells, time.perf_counter() - start)
    print(text)
    if not args.quick:
        replace_section(README, SECTION, text, before="## Report")


if __name__ == "__main__":
    main()
