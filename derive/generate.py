"""Render every requested module to generated/<name>.py and generated/compiled/<name>.py.

Modules: the four contact cases (the normal row), the friction module of each case
(<case>_friction: the tangential row), the joints (pin_joint, distance_joint) and the applied
forces (spring, mutual_gravity, body_damping: NumPy only, the runtime calls them from Python).
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable
from dataclasses import dataclass

from derive.applied import ALL_APPLIED, AppliedDerived, derive_applied
from derive.applied_proofs import applied_proofs
from derive.cases import ALL_CASES
from derive.derivation import Derivatives, derive
from derive.emit import batch_call, emit_function, environment, format_python, geometry_columns
from derive.friction import CONTACT_POINTS, FORMULAS, tangential
from derive.friction_proofs import friction_proofs
from derive.joint_proofs import joint_proofs
from derive.joints import ALL_JOINTS, derive_joint
from derive.kernels import applied_specs, friction_specs, joint_specs, kernel_specs
from derive.proofs import Proof, proofs_for
from derive.rows import Derived

FRICTION_SUFFIX = "_friction"
MODULES = (*ALL_CASES, *(c + FRICTION_SUFFIX for c in ALL_CASES), *ALL_JOINTS, *ALL_APPLIED)
_BATCHED = {
    "case": ("gap", "gap_velocity", "jacobian", "bias"),
    "friction": ("tangent_velocity", "tangent_jacobian", "tangent_bias"),
    "joint": ("gap", "gap_velocity", "jacobian", "bias"),
}
_TEMPLATES = {"case": "kernel_module", "friction": "friction_module", "joint": "joint_module"}


@dataclass(frozen=True)
class ModuleResult:
    name: str
    kind: str  # "case", "friction", "joint" or "applied"
    title: str
    derived: Derivatives | Derived | AppliedDerived
    source: str
    compiled_source: str | None  # None: no compiled variant (applied forces)
    proofs: list[Proof]
    seconds: float


def kind_of(name: str) -> str:
    if name in ALL_CASES:
        return "case"
    if name in ALL_APPLIED:
        return "applied"
    return "friction" if name.endswith(FRICTION_SUFFIX) else "joint"


@functools.cache
def contact_derivatives(case: str) -> Derivatives:
    return derive(ALL_CASES[case]())


def _render(kind: str, info, specs, geometry, **context) -> tuple[str, str]:
    """The NumPy module and its compiled variant (with batch loops) from the kernel specs."""
    functions = [emit_function(spec, geometry) for spec in specs]
    columns = geometry_columns(geometry)
    calls = {
        f.name: batch_call(f.arguments, columns, body2_pose_local=kind == "joint")
        for f in functions
        if f.name.removesuffix("_static2") in _BATCHED[kind]
    }
    env = environment()
    source = env.get_template(f"{_TEMPLATES[kind]}.py.j2").render(
        case=info, functions=functions, **context
    )
    compiled = env.get_template(f"{_TEMPLATES[kind]}_compiled.py.j2").render(
        case=info, functions=functions, columns=list(columns.items()), calls=calls, **context
    )
    return format_python(source), format_python(compiled)


def _case(name: str):
    d = contact_derivatives(name)
    rendered = _render("case", d.case, kernel_specs(d), d.case.geometry)
    return d.case.title, d, rendered, proofs_for(d)


def _friction(name: str):
    contact = name.removesuffix(FRICTION_SUFFIX)
    case = ALL_CASES[contact]()
    f = tangential(case)
    info = {"name": name, "title": case.title, "contact": contact}
    specs = friction_specs(f, FORMULAS)
    rendered = _render("friction", info, specs, case.geometry, points=CONTACT_POINTS[contact])
    return case.title, f, rendered, friction_proofs(case, f)


def _joint(name: str):
    joint = ALL_JOINTS[name]()
    j = derive_joint(joint)
    rows = joint.rows
    info = {
        "name": name,
        "title": joint.title,
        "definition": joint.definition,
        "rows": rows,
        "rows_text": "Two rows, x and y of s = p1 - p2 in world axes (outputs end in _x, _y)."
        if rows == 2
        else "One row; it needs |s| > 0 (length > 0: a zero length is a pin joint).",
        "targets": lambda out: ", ".join(f"{out}[k, {r}]" for r in range(rows)),
    }
    specs = joint_specs(j, joint.row_names, joint.formulas)
    return joint.title, j, _render("joint", info, specs, joint.geometry), joint_proofs(joint, j)


def _applied(name: str):
    definition = ALL_APPLIED[name]()
    a = derive_applied(definition)
    coordinates = ", ".join(str(q) for q in definition.coordinates)
    info = {
        "name": name,
        "title": definition.title,
        "potential": definition.potential,
        "dissipation": definition.dissipation,
        "coordinates": coordinates,
        "notes": definition.notes,
    }
    functions = [emit_function(spec, definition.parameters) for spec in applied_specs(a)]
    uses_numpy = any(
        "np." in code
        for f in functions
        for code in (f.returns, *(line[1] for line in f.assignments))
    )
    template = environment().get_template("applied_module.py.j2")
    source = template.render(case=info, functions=functions, uses_numpy=uses_numpy)
    return definition.title, a, (format_python(source), None), applied_proofs(a)


def generate_module(name: str) -> ModuleResult:
    start = time.perf_counter()
    kind = kind_of(name)
    make = {"case": _case, "friction": _friction, "joint": _joint, "applied": _applied}[kind]
    title, derived, (source, compiled), proofs = make(name)
    seconds = time.perf_counter() - start
    return ModuleResult(name, kind, title, derived, source, compiled, proofs, seconds)


def render_init(modules: list[str]) -> str:
    """generated/__init__.py: the modules present and the engine's contract with them (case and
    joint ids, geometry columns, joint rows), so the runtime never retypes a kernel's argument
    list."""
    cases = {
        name: {"id": k, "columns": geometry_columns(make().geometry)}
        for k, (name, make) in enumerate(ALL_CASES.items())
    }
    joints = {
        name: {"id": k, "rows": make().rows, "columns": geometry_columns(make().geometry)}
        for k, (name, make) in enumerate(ALL_JOINTS.items())
    }
    text = (
        environment()
        .get_template("generated_init.py.j2")
        .render(**_listed(modules), contract=cases, joint_contract=joints)
    )
    return format_python(text)


def _listed(modules: list[str]) -> dict[str, list[str]]:
    return {
        "cases": sorted(m for m in modules if kind_of(m) == "case"),
        "friction": sorted(
            m.removesuffix(FRICTION_SUFFIX) for m in modules if kind_of(m) == "friction"
        ),
        "joints": sorted(m for m in modules if kind_of(m) == "joint"),
        "applied": sorted(m for m in modules if kind_of(m) == "applied"),
    }


def render_compiled_init(modules: list[str]) -> str:
    text = environment().get_template("generated_compiled_init.py.j2").render(**_listed(modules))
    return format_python(text)


def generate(names: list[str], report: Callable[[str], None] = print) -> dict[str, ModuleResult]:
    results = {}
    for name in names:
        results[name] = r = generate_module(name)
        failed = [p.statement for p in r.proofs if not p.holds]
        status = "all proofs hold" if not failed else f"{len(failed)} PROOF(S) FAIL"
        report(f"{name:23s} {r.seconds:6.2f} s  {len(r.source.splitlines()):4d} lines  {status}")
    return results
