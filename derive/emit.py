"""Turn kernel specs into NumPy source through the Jinja2 templates in templates/.

Common subexpressions are eliminated per function with sympy.cse; named intermediates (the world
vectors of the derivation) keep their names so the code reads like the derivation. Output is passed
through `ruff format` so it is byte-identical from run to run (the stale check relies on it).
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import jinja2
import sympy as sp
from sympy.printing.numpy import NumPyPrinter
from sympy.printing.precedence import PRECEDENCE

from derive.kernels import KernelSpec

TEMPLATES = Path(__file__).resolve().parent.parent / "templates"


class KernelPrinter(NumPyPrinter):
    """NumPy printer that writes x**-k as 1/x**k (a reciprocal, not a pow call) and uses `np.`."""

    def __init__(self) -> None:
        super().__init__({"fully_qualified_modules": True, "allow_unknown_functions": False})

    def _print_Pow(self, expr, rational=False):
        base, exp = expr.as_base_exp()
        if exp.is_Integer and 2 <= abs(exp) <= 3:
            # A product, not `**`: NumPy's scalar pow and array power differ in the last bit, and
            # a kernel must give the same answer for a float and a 1-element array.
            factor = self.parenthesize(base, PRECEDENCE["Mul"], strict=True)
            product = " * ".join([factor] * abs(int(exp)))
            return product if exp > 0 else f"1 / ({product})"
        if exp == -1:
            return f"1 / {self.parenthesize(base, PRECEDENCE['Mul'])}"
        if exp == sp.Rational(1, 2):
            return f"{self._module_format('numpy.sqrt')}({self._print(base)})"
        return super()._print_Pow(expr, rational=rational)

    def _print_Mul(self, expr):
        """A lone denominator x**2 or x**3 printed as a product stays one factor: a / (x * x),
        not a / x * x (G m1 m2 / r**3 of derive/applied.py)."""
        text = super()._print_Mul(expr)
        _, denominator = expr.as_numer_denom()
        if denominator.is_Pow and denominator.exp.is_Integer and 2 <= denominator.exp <= 3:
            product = self._print(denominator)
            if text.endswith("/" + product):
                return f"{text[: -len(product)]}({product})"
        return text

    def _module_format(self, fqn, register=True):
        return "np." + fqn.split(".", 1)[1] if fqn.startswith("numpy.") else fqn


@dataclass(frozen=True)
class EmittedFunction:
    name: str
    summary: str
    formula: str
    arguments: tuple[str, ...]
    assignments: tuple[tuple[str, str, tuple[str, ...]], ...]  # (name, code, names freed after)
    returns: str
    output_names: tuple[str, ...]


def _function_body(spec: KernelSpec, args: tuple[sp.Symbol, ...]):
    named = spec.needed_intermediates()
    exprs = [v for _, v in named] + list(spec.outputs)
    temps, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("e"), order="canonical")
    pending = list(temps) + [(s, reduced[i]) for i, (s, _) in enumerate(named)]
    outputs = reduced[len(named) :]
    defined, lines = set(args), []
    while pending:  # emit in an order where every name is defined before use
        for item in pending:
            if item[1].free_symbols <= defined:
                lines.append(item)
                defined.add(item[0])
                pending.remove(item)
                break
        else:
            raise RuntimeError(f"{spec.name}: circular intermediates {pending}")
    return lines, outputs


def _last_uses(lines, outputs, args) -> list[tuple[str, ...]]:
    """For each line, the temporaries used there for the last time.

    `del` after the last use lets NumPy reuse the memory of dead arrays at once; with every
    temporary alive to the end, a call on 10^4 contacts page-faults its freshly mapped memory and
    runs up to 2x slower (bench/README.md, Kernels, Findings).
    """
    last: dict[sp.Symbol, int] = {}
    for k, (_, value) in enumerate(lines):
        for s in value.free_symbols:
            last[s] = k
    live_at_return = set().union(*(o.free_symbols for o in outputs))
    freed: list[list[str]] = [[] for _ in lines]
    for s, k in last.items():
        if s not in args and s not in live_at_return:
            freed[k].append(str(s))
    return [tuple(sorted(names)) for names in freed]


def emit_function(spec: KernelSpec, geometry: tuple[sp.Symbol, ...]) -> EmittedFunction:
    printer = KernelPrinter()
    args = spec.arguments(geometry)
    lines, outputs = _function_body(spec, args)
    freed = _last_uses(lines, outputs, set(args))
    # a constant output (a pin joint's unit directions) as a float: numba types a tuple of floats
    # (an int among them makes it heterogeneous, not indexable in a loop)
    ret = ", ".join(repr(float(o)) if o.is_number else printer.doprint(o) for o in outputs)
    return EmittedFunction(
        name=spec.name,
        summary=spec.summary,
        formula=spec.formula,
        arguments=tuple(str(a) for a in args),
        assignments=tuple(
            (str(s), printer.doprint(v), gone) for (s, v), gone in zip(lines, freed, strict=True)
        ),
        returns=ret,
        output_names=spec.output_names,
    )


_STATE_SOURCES = {
    "x": "poses[{b}, 0]",
    "y": "poses[{b}, 1]",
    "th": "poses[{b}, 2]",
    "vx": "velocities[{b}, 0]",
    "vy": "velocities[{b}, 1]",
    "w": "velocities[{b}, 2]",
}
BODY2_COLUMN = 3  # geometry columns: body 1's feature from 0, body 2's from 3 (7 in all)


def geometry_columns(geometry: tuple[sp.Symbol, ...]) -> dict[str, int]:
    """Column of each geometry argument in the engine's (m, 7) geometry array: body 1's from 0,
    body 2's from 3, then those of neither body (a joint's length)."""
    first = [str(g) for g in geometry if str(g).endswith("1")]
    second = [str(g) for g in geometry if str(g).endswith("2")]
    shared = [str(g) for g in geometry if str(g) not in first + second]
    columns = {name: c for c, name in enumerate(first)}
    columns.update({name: BODY2_COLUMN + c for c, name in enumerate(second + shared)})
    return columns


def batch_call(
    arguments: tuple[str, ...], columns: dict[str, int], body2_pose_local: bool = False
) -> str:
    """The argument list of a kernel call inside a batch loop over contacts k (bodies i, j).

    body2_pose_local: body 2's pose is in the loop's locals x2, y2, th2 (a joint's loop, where
    body 2 may be the world)."""
    parts = []
    for a in arguments:
        if a in columns:
            parts.append(f"geometry[k, {columns[a]}]")
        elif body2_pose_local and a in ("x2", "y2", "th2"):
            parts.append(a)
        else:
            parts.append(_STATE_SOURCES[a[:-1]].format(b="i" if a.endswith("1") else "j"))
    return ", ".join(parts)


def environment() -> jinja2.Environment:
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(TEMPLATES),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
    )


def format_python(source: str) -> str:
    """ruff format, so generated code is stable and readable."""
    beside_python = Path(sys.executable).parent / "ruff"
    ruff = str(beside_python) if beside_python.exists() else shutil.which("ruff")
    if ruff is None:
        raise RuntimeError("ruff is needed to format generated code: pip install ruff")
    done = subprocess.run(
        [ruff, "format", "--line-length", "100", "-"],
        input=source,
        capture_output=True,
        text=True,
        check=False,
    )
    if done.returncode != 0:
        raise RuntimeError(f"ruff format failed on generated code:\n{done.stderr}")
    return done.stdout
