"""Kernel speed benchmark: contacts per second of the generated kernels (`make bench`).

For each case, function and batch size N the generated kernel is timed against
  (a) `sympy.lambdify(..., "numpy")` of derive/'s un-simplified expressions (state symbols, no cse),
  (b) the hand-written NumPy kernels of bench/baseline_numpy.py.
Before timing, (a) and (b) must agree with the generated kernel on the same inputs (`check`).

Timing is timeit-style (time.perf_counter, garbage collection off): calls are looped so one run
takes >= MIN_RUN seconds, and the best of >= MIN_REPEAT runs and >= MIN_TOTAL seconds counts. N = 1
is timed with Python floats (the per-call overhead) and with 1-element arrays; N = 10^6 with single
calls. Each case runs in a fresh process (`run_case`); N = 10^4 is run a second time with glibc's
heap trimming off (NO_TRIM), which separates page-fault time from arithmetic.

    python -m bench.kernels                # full run, rewrites "## Kernels" in bench/README.md
    python -m bench.kernels --quick        # N <= 100, short runs, README untouched (smoke test)
    python -m bench.kernels --sizes 10000  # only these N, README untouched
"""

from __future__ import annotations

import argparse
import datetime
import gc
import importlib
import inspect
import json
import math
import os
import platform
import re
import resource
import subprocess
import sys
import time
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np
import sympy as sp

from bench import baseline_numpy
from bench.machine import cpu

CASES = ("vertex_edge", "vertex_circle", "circle_edge", "circle_circle")
FUNCTIONS = (
    "gap",
    "gap_velocity",
    "gap_acceleration",
    "jacobian",
    "bias",
    "jacobian_static2",
    "bias_static2",
)
SIZES = (1, 100, 10_000, 1_000_000)
IMPLEMENTATIONS = ("generated", "lambdify", "hand")
TIMED = (*IMPLEMENTATIONS, "floor")  # floor: the kernel's sin/cos/sqrt calls alone (floor_call)
MIN_RUN = 0.002  # seconds per timed run: short, to fit between other processes' time slices
MIN_TOTAL = 0.2  # seconds of runs per measurement
MIN_REPEAT = 5  # runs per measurement (and pass), at least
PASSES = 2  # round-robin passes over the functions, N < 10^6
LARGE_REPEAT = 3  # runs of a single call at N = 10^6
FAULT_COLUMNS_FROM = 10_000  # N from which the tables show page faults per call
TOLERANCE = 1e-9
TARGET_LAMBDIFY = 3.0  # generated >= 3x faster than lambdify at N = 10^4
TARGET_HAND = 1.0  # and no slower than the hand-written kernels
TARGET_OVERHEAD = 20e-6  # seconds per call at N = 1 (Python floats)
NOISE = 0.05  # a miss by less than this is reported as such (single rows vary by 5-15%)
NO_TRIM = {"MALLOC_TRIM_THRESHOLD_": str(2**30)}  # glibc keeps freed heap memory: no page faults
NO_TRIM_LABEL = "arrays, heap trimming off"
ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "bench" / "README.md"
SECTION = "## Kernels"


# --- inputs ---------------------------------------------------------------------------------------


def random_inputs(case: str, n: int, seed: int = 0) -> dict[str, np.ndarray]:
    """Valid random states and geometry for n contacts of `case`, keyed by argument name.

    Body-2 circles have radii of both signs (|r2| in [0.1, 2]), r1 > 0, edge normals are unit
    vectors, and body 1's vertex or centre is 0.2 to 3 away from body 2's centre or edge point
    (placed there by choosing x1, y1).
    """
    rng = np.random.default_rng(seed)
    u = rng.uniform
    values = {name: u(-np.pi, np.pi, n) for name in ("th1", "th2")}
    for name in ("vx1", "vy1", "w1", "vx2", "vy2", "w2", "ax1", "ay1", "al1", "ax2", "ay2", "al2"):
        values[name] = rng.normal(size=n)
    values["x2"], values["y2"] = u(-5, 5, n), u(-5, 5, n)
    q1 = ("px1", "py1") if case.startswith("vertex") else ("cx1", "cy1")
    anchor2 = ("cx2", "cy2") if case.endswith("circle") else ("ex2", "ey2")
    for name in q1 + anchor2:
        values[name] = u(-1, 1, n)
    values["r1"] = u(0.1, 2, n)
    values["r2"] = u(0.1, 2, n) * rng.choice([-1.0, 1.0], n)
    normal_angle = u(-np.pi, np.pi, n)
    values["nx2"], values["ny2"] = np.cos(normal_angle), np.sin(normal_angle)
    # x1 = x2 + R(th2) anchor2 - R(th1) q1 + v with |v| in [0.2, 3]
    length, angle = u(0.2, 3, n), u(-np.pi, np.pi, n)
    a2 = _rotate(values["th2"], values[anchor2[0]], values[anchor2[1]])
    b1 = _rotate(values["th1"], values[q1[0]], values[q1[1]])
    values["x1"] = values["x2"] + a2[0] - b1[0] + length * np.cos(angle)
    values["y1"] = values["y2"] + a2[1] - b1[1] + length * np.sin(angle)
    return values


def _rotate(th, px, py):
    return np.cos(th) * px - np.sin(th) * py, np.sin(th) * px + np.cos(th) * py


def as_floats(values: dict[str, np.ndarray]) -> dict[str, float]:
    """The first contact as Python floats."""
    return {name: float(v[0]) for name, v in values.items()}


def as_one_element(values: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    return {name: v[:1].copy() for name, v in values.items()}


# --- the three implementations --------------------------------------------------------------------


def lambdified(case: str, generated_module) -> dict[str, object]:
    """lambdify of derive/'s expressions in state symbols, no cse, with the generated arguments."""
    from derive.cases import ALL_CASES
    from derive.derivation import derive

    d = derive(ALL_CASES[case]())
    s2 = d.static2
    expressions = {
        "gap": d.in_state_symbols(d.gap),
        "gap_velocity": d.in_state_symbols(d.gap_velocity),
        "gap_acceleration": d.in_state_symbols(d.gap_acceleration),
        "jacobian": tuple(d.in_state_symbols(e) for e in d.jacobian),
        "bias": d.bias.in_state_symbols(d.bias.gap_acceleration),
        "jacobian_static2": tuple(s2.in_state_symbols(e) for e in s2.jacobian[:3]),
        "bias_static2": s2.bias.in_state_symbols(s2.bias.gap_acceleration),
    }
    functions = {}
    for name, expr in expressions.items():
        arguments = [sp.Symbol(a, real=True) for a in generated_module.ARGUMENTS[name]]
        functions[name] = sp.lambdify(arguments, expr, "numpy", cse=False)
    return functions


def implementations(case: str) -> dict[str, dict[str, object]]:
    """{implementation: {function name: callable}} for one case."""
    module = importlib.import_module(f"generated.{case}")
    hand = baseline_numpy.CASES[case]
    return {
        "generated": {f: getattr(module, f) for f in FUNCTIONS},
        "lambdify": lambdified(case, module),
        "hand": {f: getattr(hand, f) for f in FUNCTIONS},
    }


TRANSCENDENTAL = re.compile(r"\bnp\.(sin|cos|sqrt)\(")


def floor_call(function, values: dict) -> tuple[object, dict]:
    """(callable, kwargs) doing only the sin, cos and sqrt calls of the generated ``function``,
    on arrays of the batch's size: a lower bound on the time of any kernel that evaluates them
    (lambdify's included), so ``lambdify time / floor time`` bounds the possible speedup."""
    ops = [getattr(np, name) for name in TRANSCENDENTAL.findall(inspect.getsource(function))]
    x = np.abs(values["th1"])

    def floor(x):
        for op in ops:
            op(x)

    return floor, {"x": x}


def keyword_arguments(function, values: dict) -> dict:
    """The arguments `function` declares, from `values` (each implementation asks for its own)."""
    return {name: values[name] for name in inspect.signature(function).parameters}


# --- agreement ------------------------------------------------------------------------------------


def _outputs(result) -> list[np.ndarray]:
    parts = result if isinstance(result, tuple) else (result,)
    return [np.asarray(p, dtype=float) for p in parts]


def relative_error(result, reference) -> float:
    """max |result - reference| / max |reference| per output, the worst output (normwise).

    Normwise, not per element: a gap or bias that cancels to ~0 for one contact has no meaningful
    per-element relative error, and 10^6 random contacts produce such cancellations.
    """
    got, want = _outputs(result), _outputs(reference)
    if len(got) != len(want):
        raise AssertionError(f"{len(got)} outputs instead of {len(want)}")
    worst = 0.0
    for g, w in zip(got, want, strict=True):
        g, w = np.broadcast_arrays(g, w)
        scale = max(float(np.max(np.abs(w))), np.finfo(float).tiny)
        worst = max(worst, float(np.max(np.abs(g - w))) / scale)
    return worst


def check(case: str, function: str, impls: dict, values: dict) -> tuple[dict, dict]:
    """Call every implementation once (also the warm-up); assert (a), (b) agree with generated.

    Returns the relative errors of (a) and (b), and the (seconds, page faults) of each call.
    """
    first_call, results = {}, {}
    for impl in IMPLEMENTATIONS:
        f = impls[impl][function]
        kwargs = keyword_arguments(f, values)
        faults, start = _minor_faults(), time.perf_counter()
        results[impl] = f(**kwargs)
        first_call[impl] = (time.perf_counter() - start, _minor_faults() - faults)
    errors = {}
    for impl in ("lambdify", "hand"):
        errors[impl] = relative_error(results[impl], results["generated"])
        assert errors[impl] <= TOLERANCE, (
            f"{case}.{function}: {impl} differs from the generated kernel by {errors[impl]:.3g} "
            f"(relative) on the benchmark inputs"
        )
    return errors, first_call


# --- timing ---------------------------------------------------------------------------------------


def _minor_faults() -> int:
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt


def _run(function, kwargs: dict, number: int) -> tuple[float, int]:
    """Seconds and minor page faults of `number` calls (garbage collection off)."""
    gc_was_enabled = gc.isenabled()
    gc.disable()
    try:
        faults, start = _minor_faults(), time.perf_counter()
        for _ in range(number):
            function(**kwargs)
        return time.perf_counter() - start, _minor_faults() - faults
    finally:
        if gc_was_enabled:
            gc.enable()


def _autorange(function, kwargs: dict, min_run: float) -> tuple[int, tuple[float, int]]:
    """Calls per run so that one run takes >= min_run (timeit.autorange), and that run."""
    number, run = 1, _run(function, kwargs, 1)
    while run[0] < min_run:
        number = max(number * 2, math.ceil(number * 1.2 * min_run / max(run[0], 1e-9)))
        run = _run(function, kwargs, number)
    return number, run


def best_times(calls: dict[str, tuple], min_run: float, min_total: float, min_repeat: int):
    """{name: (seconds, page faults) per call} of each (function, kwargs) in its best run.

    Each implementation gets at least `min_repeat` runs of >= min_run seconds and >= min_total
    seconds of runs (the last calibration run counts). Short runs, many of them, interleaved between
    the implementations: the best run is then one that no other process on the machine interrupted.
    """
    loops, best, total, runs = {}, {}, {}, {}
    for name, (f, kwargs) in calls.items():
        loops[name], (elapsed, faults) = _autorange(f, kwargs, min_run)
        best[name] = (elapsed / loops[name], faults / loops[name])
        total[name], runs[name] = elapsed, 1
    pending = set(calls)
    while pending:
        for name in [n for n in calls if n in pending]:
            f, kwargs = calls[name]
            elapsed, faults = _run(f, kwargs, loops[name])
            best[name] = min(best[name], (elapsed / loops[name], faults / loops[name]))
            total[name] += elapsed
            runs[name] += 1
            if runs[name] >= min_repeat and total[name] >= min_total:
                pending.discard(name)
    return best


# --- the benchmark --------------------------------------------------------------------------------


@dataclass(frozen=True)
class Timing:
    case: str
    function: str
    n: int
    inputs: str  # "arrays", NO_TRIM_LABEL, "floats" (N = 1) or "1-element arrays" (N = 1)
    seconds: dict[str, float]  # per call, by implementation
    faults: dict[str, float]  # minor page faults per call (in the best run), by implementation
    errors: dict[str, float]  # relative difference to generated, by implementation

    def speedup(self, impl: str, over: str = "generated") -> float:
        """How many times faster `over` (the generated kernel) is than `impl`."""
        return self.seconds[impl] / self.seconds[over]


def input_sets(case: str, sizes: tuple[int, ...]):
    """(n, label, values) for each batch size; N = 1 as Python floats and as 1-element arrays."""
    for n in sizes:
        values = random_inputs(case, n, seed=n)
        if n == 1:
            yield n, "floats", as_floats(values)
            yield n, "1-element arrays", as_one_element(values)
        else:
            yield n, "arrays", values


def measure(case: str, sizes: tuple[int, ...], min_total: float = MIN_TOTAL) -> list[Timing]:
    """Check, then time every function of `case` at each size.

    Below N = 10^6 the functions are timed in PASSES round-robin passes (min_total / PASSES
    seconds each) and the best of the passes counts, so that one busy moment of the machine does
    not decide a function's result.
    """
    impls = implementations(case)
    timings = []
    for n, label, values in input_sets(case, sizes):
        calls, errors, first_call = {}, {}, {}
        for function in FUNCTIONS:
            errors[function], first_call[function] = check(case, function, impls, values)
            calls[function] = {"floor": floor_call(impls["generated"][function], values)}
            for impl in IMPLEMENTATIONS:
                f = impls[impl][function]
                calls[function][impl] = (f, keyword_arguments(f, values))
        if n >= 1_000_000:  # lambdify takes seconds per call: its checked call is its timing
            best = {}
            for function, by_impl in calls.items():
                del by_impl["lambdify"]
                best[function] = best_times(by_impl, 0.0, min_total=0.0, min_repeat=LARGE_REPEAT)
                best[function]["lambdify"] = first_call[function]["lambdify"]
        else:
            best = {function: dict.fromkeys(TIMED, (math.inf, 0.0)) for function in calls}
            for _ in range(PASSES):
                for function, by_impl in calls.items():
                    new = best_times(by_impl, MIN_RUN, min_total / PASSES, MIN_REPEAT)
                    best[function] = {i: min(best[function][i], new[i]) for i in TIMED}
        for function in FUNCTIONS:
            seconds = {impl: best[function][impl][0] for impl in TIMED}
            faults = {impl: best[function][impl][1] for impl in TIMED}
            timings.append(Timing(case, function, n, label, seconds, faults, errors[function]))
    return timings


# --- report ---------------------------------------------------------------------------------------


def markdown_table(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def _rate(seconds: float, n: int) -> str:
    rate = n / seconds
    return f"{rate / 1e6:.3g} M" if rate >= 1e6 else f"{rate / 1e3:.3g} k"


def _us(seconds: float) -> str:
    return f"{seconds * 1e6:.3g}"


def size_table(timings: list[Timing], n: int, label: str) -> str:
    """One row per case and function: contacts/s of each implementation and the two speedups.

    From N = 10^4 on, also the minor page faults per call of generated and hand-written (fresh
    memory for temporaries: the kernel time includes the kernel's own page faults).
    """
    header = ["case", "function", "generated c/s", "lambdify c/s", "hand c/s"]
    header += ["gen vs lambdify", "gen vs hand"]
    if n == 1:
        header[2:5] = ["generated µs", "lambdify µs", "hand µs"]
    with_faults = n >= FAULT_COLUMNS_FROM
    if with_faults:
        header += ["gen faults/call", "hand faults/call"]
    rows = []
    for t in timings:
        if t.n != n or t.inputs != label:
            continue
        show = _us if n == 1 else (lambda s, n=n: _rate(s, n))
        cells = [show(t.seconds[impl]) for impl in IMPLEMENTATIONS]
        cells += [f"{t.speedup('lambdify'):.2f}×", f"{t.speedup('hand'):.2f}×"]
        if with_faults:
            cells += [f"{t.faults['generated']:.0f}", f"{t.faults['hand']:.0f}"]
        rows.append([t.case, t.function, *cells])
    return markdown_table(header, rows)


def _groups(timings: list[Timing]) -> list[tuple[int, str]]:
    """The (N, inputs) pairs measured, by N (in order of measurement for the same N)."""
    return sorted(dict.fromkeys((t.n, t.inputs) for t in timings), key=lambda group: group[0])


def _geomean(values: list[float]) -> float:
    return math.exp(sum(math.log(v) for v in values) / len(values))


def summary_table(timings: list[Timing]) -> str:
    """Per N: geometric mean, min and max of the speedups over all case x function kernels."""
    header = ["N", "inputs", "gen vs lambdify: geo-mean [min, max]"]
    header += ["gen vs hand: geo-mean [min, max]", "generated µs/call: median [max]"]
    rows = []
    for n, label in _groups(timings):
        group = [t for t in timings if t.n == n and t.inputs == label]
        cells = []
        for impl in ("lambdify", "hand"):
            s = [t.speedup(impl) for t in group]
            cells.append(f"{_geomean(s):.2f}× [{min(s):.2f}, {max(s):.2f}]")
        per_call = sorted(t.seconds["generated"] for t in group)
        cells.append(f"{_us(per_call[len(per_call) // 2])} [{_us(per_call[-1])}]")
        rows.append([f"{n:,}", label, *cells])
    return markdown_table(header, rows)


def targets(timings: list[Timing]) -> list[str]:
    """One line per target: met or not, and the kernels that miss it and by how much."""
    checks = []
    for label in dict.fromkeys(t.inputs for t in timings if t.n == 10_000):
        group = [t for t in timings if t.n == 10_000 and t.inputs == label]
        checks += [
            (f"N = 10^4 ({label}): generated >= {TARGET_LAMBDIFY:g}× faster than lambdify", group,
             lambda t: t.speedup("lambdify") >= TARGET_LAMBDIFY,
             lambda t: f"{t.speedup('lambdify'):.2f}× (bound {t.speedup('lambdify', 'floor'):.2f}×)"),
            (f"N = 10^4 ({label}): generated no slower than hand-written", group,
             lambda t: t.speedup("hand") >= TARGET_HAND,
             lambda t: f"{t.speedup('hand'):.2f}× ({t.faults['generated']:.0f} vs "
                       f"{t.faults['hand']:.0f} faults)"),
        ]  # fmt: skip
    for label in ("floats", "1-element arrays"):
        group = [t for t in timings if t.n == 1 and t.inputs == label]
        checks.append(
            (f"N = 1 ({label}): generated < {TARGET_OVERHEAD * 1e6:g} µs per call", group,
             lambda t: t.seconds["generated"] < TARGET_OVERHEAD,
             lambda t: f"{_us(t.seconds['generated'])} µs")
        )  # fmt: skip
    lines = []
    for title, group, ok, show in checks:
        if not group:
            continue
        misses = [t for t in group if not ok(t)]
        if not misses:
            lines.append(f"- **met** — {title} (all {len(group)} kernels)")
            continue
        detail = ", ".join(f"{t.case}.{t.function} {show(t)}" for t in misses)
        if "lambdify" in title:
            bounded = sum(t.speedup("lambdify", "floor") < TARGET_LAMBDIFY for t in misses)
            detail += (
                f"; *bound*: lambdify's time over that of the kernel's sin, cos and sqrt calls "
                f"alone, the most any kernel evaluating them can gain: below "
                f"{TARGET_LAMBDIFY:g}× for {bounded} of them"
            )
        if "hand-written" in title:
            close = sum(t.speedup("hand") >= TARGET_HAND - NOISE for t in misses)
            detail += f" ({close} of them by less than {NOISE:.0%})"
        lines.append(f"- **missed** by {len(misses)}/{len(group)} — {title}: {detail}")
    return lines


def machine() -> str:
    """CPU model and cores, Python, NumPy, SymPy and BLAS versions."""
    return (
        f"{cpu()}; Python {platform.python_version()}, NumPy {np.__version__}, "
        f"SymPy {sp.__version__}; BLAS: {blas()}"
    )


def blas() -> str:
    try:
        from threadpoolctl import threadpool_info

        libs = [i for i in threadpool_info() if i.get("user_api") == "blas"]
        if libs:
            return ", ".join(f"{i['internal_api']} {i['version']}" for i in libs)
    except ImportError:
        pass
    try:
        info = np.show_config(mode="dicts")["Build Dependencies"]["blas"]
        return f"{info['name']} {info['version']}"
    except (TypeError, KeyError):
        return "unknown"


def code_size() -> str:
    """Lines and bytes of each generated module."""
    rows, lines_total, bytes_total = [], 0, 0
    for case in CASES:
        path = ROOT / "generated" / f"{case}.py"
        data = path.read_bytes()
        lines = data.count(b"\n")
        lines_total, bytes_total = lines_total + lines, bytes_total + len(data)
        rows.append([f"`generated/{case}.py`", str(lines), f"{len(data):,}"])
    rows.append(["total", str(lines_total), f"{bytes_total:,}"])
    return markdown_table(["module", "lines", "bytes"], rows)


def method(timings: list[Timing], elapsed: float, load: tuple[float, float]) -> list[str]:
    """The paragraphs that say what was measured and how."""
    worst = {impl: max(t.errors[impl] for t in timings) for impl in ("lambdify", "hand")}
    trim = NO_TRIM["MALLOC_TRIM_THRESHOLD_"]
    return [
        "Contacts per second of the generated kernels (`generated/<case>.py`) against (a) "
        '`sympy.lambdify(..., "numpy")` of derive/\'s un-simplified expressions in state symbols '
        "(no cse) and (b) the hand-written NumPy of `bench/baseline_numpy.py`. *gen vs X* = time "
        "of X / time of generated (> 1: generated is faster). Random valid inputs (radii of both "
        "signs, unit normals, centres apart).",
        "",
        f"Time per call: the best run (runs of >= {MIN_RUN * 1e3:g} ms, the three implementations "
        f"interleaved, >= {MIN_TOTAL:g} s per measurement in {PASSES} passes over the functions); "
        f"N = 10^6: best of {LARGE_REPEAT} single calls, lambdify one call (the one checked). Each "
        "case runs in a fresh Python process (a fresh memory allocator). Before timing, (a) and "
        "(b) agree with the generated kernels on every input set: largest normwise relative "
        f"difference {worst['lambdify']:.1e} (lambdify), {worst['hand']:.1e} (hand-written). "
        f"Whole benchmark: {elapsed:.0f} s; 1-minute load average {load[0]:.1f} before, "
        f"{load[1]:.1f} after (other processes share the cores, so single rows can be noisy).",
        "",
        "*Page faults:* from N = 10^4 on (80 kB per array) the tables show the minor page faults "
        "per call. With glibc's default heap trimming, memory freed when a kernel returns goes "
        "back to the OS and the next call faults it in again, which can cost as much as the "
        "arithmetic; the more temporaries a kernel holds at once, the more faults. The rows "
        f"*{NO_TRIM_LABEL}* repeat N = 10^4 with `MALLOC_TRIM_THRESHOLD_={trim}` (no faults: "
        "the arithmetic alone).",
    ]


def report(timings: list[Timing], elapsed: float, load: tuple[float, float]) -> str:
    """The "## Kernels" section of bench/README.md."""
    date = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    parts = [
        SECTION,
        "",
        "Written by `python -m bench.kernels` (`make bench`); rerun it to refresh this section.",
        "",
        f"Run {date} on {machine()}. The kernels are elementwise NumPy (no BLAS calls).",
        "",
        *method(timings, elapsed, load),
        "",
        "### Targets",
        "",
        *targets(timings),
        "",
        "### Summary over the 28 kernels (4 cases × 7 functions)",
        "",
        summary_table(timings),
    ]
    for n, label in _groups(timings):
        unit = "µs per call" if n == 1 else "contacts per second"
        parts += ["", f"### N = {n:,} ({label}; {unit})", "", size_table(timings, n, label)]
    parts += ["", "### Generated code size", "", code_size(), ""]
    return "\n".join(parts)


def write_section(section: str, path: Path = README) -> None:
    """Replace this benchmark's section of the README (up to the next "## " heading), or add it.

    A hand-written "### Findings" subsection of the old section is kept (moved to the end).
    """
    text = path.read_text() if path.exists() else "# Benchmarks\n\n"
    pattern = re.compile(rf"^{re.escape(SECTION)}\n.*?(?=^## |\Z)", flags=re.M | re.S)
    old = pattern.search(text)
    if old:
        findings = re.search(r"^### Findings\n.*?(?=^##|\Z)", old.group(0), flags=re.M | re.S)
        if findings:
            section = section.rstrip("\n") + "\n\n" + findings.group(0).rstrip("\n") + "\n"
        text = text[: old.start()] + section.rstrip("\n") + "\n\n" + text[old.end() :]
    else:
        text = text.rstrip("\n") + "\n\n" + section
    path.write_text(text.rstrip("\n") + "\n")


def run_case(case: str, sizes: tuple[int, ...], min_total: float, env: dict | None = None):
    """Measure one case in a fresh Python process.

    A fresh process has a fresh memory allocator, so a case's page faults (and timings) do not
    depend on which cases ran before it. `env` adds environment variables (e.g. NO_TRIM).
    """
    command = [sys.executable, "-m", "bench.kernels", "--worker", case]
    command += ["--sizes", ",".join(map(str, sizes)), "--min-total", str(min_total)]
    done = subprocess.run(
        command, cwd=ROOT, env={**os.environ, **(env or {})}, capture_output=True, text=True
    )
    if done.returncode != 0:
        raise RuntimeError(f"benchmark of {case} failed:\n{done.stderr}")
    return [Timing(**row) for row in json.loads(done.stdout)]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="N <= 100, short runs, no README")
    parser.add_argument("--sizes", help="comma-separated N to run (no README), e.g. 10000")
    parser.add_argument("--min-total", type=float, default=MIN_TOTAL, help=argparse.SUPPRESS)
    parser.add_argument("--worker", metavar="CASE", help=argparse.SUPPRESS)  # see run_case
    args = parser.parse_args(argv)
    sizes, min_total = SIZES, args.min_total
    if args.quick:
        sizes, min_total = SIZES[:2], 0.02
    if args.sizes:
        sizes = tuple(int(n) for n in args.sizes.split(","))
    if args.worker:
        print(json.dumps([asdict(t) for t in measure(args.worker, sizes, min_total)]))
        return
    start, load_before = time.perf_counter(), os.getloadavg()[0]
    timings = []
    for case in CASES:
        case_start = time.perf_counter()
        timings += run_case(case, sizes, min_total)
        if 10_000 in sizes:
            no_trim = run_case(case, (10_000,), min_total, env=NO_TRIM)
            timings += [replace(t, inputs=NO_TRIM_LABEL) for t in no_trim]
        print(f"{case}: {time.perf_counter() - case_start:.0f} s", file=sys.stderr)
    elapsed = time.perf_counter() - start
    section = report(timings, elapsed, (load_before, os.getloadavg()[0]))
    print(section)
    if sizes == SIZES and min_total == MIN_TOTAL:
        write_section(section)
        print(f"\nwritten to {README.relative_to(ROOT)}", file=sys.stderr)


if __name__ == "__main__":
    main()
