"""Render every requested case to generated/<case>.py and the derivations to docs/derivations.tex."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

from derive.cases import ALL_CASES
from derive.derivation import Derivatives, derive
from derive.emit import batch_call, emit_function, environment, format_python, geometry_columns
from derive.kernels import kernel_specs
from derive.proofs import Proof, proofs_for


@dataclass(frozen=True)
class CaseResult:
    derivatives: Derivatives
    source: str
    compiled_source: str
    proofs: list[Proof]
    seconds: float


def generate_case(name: str) -> CaseResult:
    start = time.perf_counter()
    case = ALL_CASES[name]()
    d = derive(case)
    functions = [emit_function(spec, case.geometry) for spec in kernel_specs(d)]
    env = environment()
    source = env.get_template("kernel_module.py.j2").render(case=case, functions=functions)
    columns = geometry_columns(case.geometry)
    batched = ("gap", "gap_velocity", "jacobian", "bias")
    calls = {
        f.name: batch_call(f.arguments, columns)
        for f in functions
        if f.name.removesuffix("_static2") in batched
    }
    compiled = env.get_template("kernel_module_compiled.py.j2").render(
        case=case, functions=functions, columns=list(columns.items()), calls=calls
    )
    proofs = proofs_for(d)
    return CaseResult(
        d, format_python(source), format_python(compiled), proofs, time.perf_counter() - start
    )


def render_init(cases: list[str]) -> str:
    """generated/__init__.py: the cases present and the engine's contract with them (case ids,
    geometry columns), so the runtime never retypes a kernel's argument list."""
    every = {name: make() for name, make in ALL_CASES.items()}
    contract = {
        name: {"id": k, "columns": geometry_columns(case.geometry)}
        for k, (name, case) in enumerate(every.items())
    }
    text = (
        environment()
        .get_template("generated_init.py.j2")
        .render(cases=sorted(cases), contract=contract)
    )
    return format_python(text)


def render_compiled_init(cases: list[str]) -> str:
    text = environment().get_template("generated_compiled_init.py.j2").render(cases=sorted(cases))
    return format_python(text)


def generate(names: list[str], report: Callable[[str], None] = print) -> dict[str, CaseResult]:
    results = {}
    for name in names:
        results[name] = r = generate_case(name)
        failed = [p.statement for p in r.proofs if not p.holds]
        status = "all proofs hold" if not failed else f"{len(failed)} PROOF(S) FAIL"
        report(f"{name:14s} {r.seconds:6.2f} s  {len(r.source.splitlines()):4d} lines  {status}")
    return results
