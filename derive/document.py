"""The derivations as a LaTeX document (templates/derivations.tex.j2) and its PDF."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import sympy as sp

from derive.applied import ALL_APPLIED
from derive.derivation import ACCELERATION
from derive.emit import environment
from derive.friction import CONTACT_POINTS
from derive.generate import ModuleResult
from derive.joints import ALL_JOINTS
from derive.osculating import check as osculating_check

_NAMES = {
    "sg2": r"\sigma",
    "v_len": r"|v|",
    "v_tan": r"v_{\perp}",
    "dx": r"\Delta x",
    "dy": r"\Delta y",
    "th1": r"\theta_1",
    "th2": r"\theta_2",
    "w1": r"\omega_1",
    "w2": r"\omega_2",
    "al1": r"\alpha_1",
    "al2": r"\alpha_2",
}
_NAMES.update({"s_len": r"|s|", "s_tan": r"s_{\perp}", "length": r"\ell"})
_NAMES.update({"s_inv": r"|s|^{-1}", "s_rate": r"\dot{|s|}", "rest_length": "L", "stiffness": "k"})
_NAMES.update({"damping": "c", "k_lin": r"k_{\mathrm{lin}}", "k_ang": r"k_{\mathrm{ang}}"})
_NAMES.update({"m1": "m_1", "m2": "m_2", "i1": "I_1"})
for _stem, _tex in (("n", "n_"), ("v", "v_"), ("s", "s_"), ("l1", "L_1"), ("l2", "L_2")):
    for _c in ("x", "y"):
        _sub = f"{_tex[0]}_{{{_tex[2:]}{_c}}}"  # n_{x}, L_{1x}
        _NAMES[f"{_stem}_{_c}"] = _sub
        _NAMES[f"{_stem}_{_c}_t"] = rf"\dot {_sub}"
        _NAMES[f"{_stem}_{_c}_tt"] = rf"\ddot {_sub}"


for _i in ("1", "2"):
    _NAMES.update({f"ax{_i}": f"a_{{x{_i}}}", f"ay{_i}": f"a_{{y{_i}}}", f"vx{_i}": f"v_{{x{_i}}}"})
    _NAMES[f"vy{_i}"] = f"v_{{y{_i}}}"


_TEXT_ESCAPES = {
    "\\": r"\textbackslash{}",
    "_": r"\_",
    "&": r"\&",
    "%": r"\%",
    "#": r"\#",
    "$": r"\$",
    "{": r"\{",
    "}": r"\}",
    ">": "$>$",
    "<": "$<$",
    "|": "$|$",
}


def tex_text(text: str) -> str:
    """Plain text (a proof statement, a feature) as LaTeX text: specials escaped, and >, <, |
    in math mode (the default OT1 text font prints them as an inverted question mark and
    dashes); t^2, M^-1 as superscripts; d'' as two primes, not a closing double quote."""
    out = "".join(_TEXT_ESCAPES.get(ch, ch) for ch in text)
    out = re.sub(r"\^(-?\d+|\w)", r"$^{\1}$", out)
    return out.replace("''", "'{}'")


def latex(expr: sp.Expr, terms_per_line: int = 4) -> str:
    """LaTeX of `expr`; a long sum is broken over aligned lines so it fits the page."""
    names = {s: _NAMES.get(str(s), sp.latex(s)) for s in expr.free_symbols}
    terms = expr.as_ordered_terms() if isinstance(expr, sp.Add) else [expr]
    lines = []
    for k in range(0, len(terms), terms_per_line):
        text = sp.latex(sp.Add(*terms[k : k + terms_per_line], evaluate=False), symbol_names=names)
        lines.append(text if k == 0 or text.startswith("-") else "+ " + text)
    return r" \\ &\quad ".join(lines)


def _case_context(result: ModuleResult) -> dict:
    d = result.derived
    case = d.case
    return {
        "case": case,
        "intermediates": [(latex(s), latex(v)) for s, v in d.intermediates],
        "gap": latex(d.gap),
        "gap_velocity": latex(d.gap_velocity),
        "gap_acceleration": latex(d.gap_acceleration),
        "jacobian": [
            (latex(a), latex(j, 2)) for a, j in zip(ACCELERATION, d.jacobian, strict=True)
        ],
        "proofs": result.proofs,
    }


def _rows_context(result: ModuleResult, outputs: dict[str, str]) -> dict:
    """A friction or joint module: its intermediates, outputs (per row) and Jacobian rows."""
    f = result.derived
    rows = f.rows
    return {
        "name": result.name,
        "title": result.title,
        "intermediates": [(latex(s), latex(v)) for s, v in f.intermediates],
        "outputs": [
            (tex.format(row=_row_label(k, rows)), latex(e, 3))
            for name, tex in outputs.items()
            for k, e in enumerate(f.values[name])
        ],
        "jacobian": [
            (_row_label(k, rows), latex(a), latex(j, 2))
            for k, row in enumerate(f.jacobian)
            for a, j in zip(ACCELERATION, row, strict=True)
        ],
        "proofs": result.proofs,
    }


def _applied_context(result: ModuleResult) -> dict:
    """An applied force: its intermediates, V, R and the generalized forces Q."""
    a = result.derived
    definition = ALL_APPLIED[result.name]()
    forces = [rf"Q_{{{q}}}" for q in ("x_1", "y_1", r"\theta_1", "x_2", "y_2", r"\theta_2")]
    return {
        "name": result.name,
        "title": result.title,
        "textbook": tex_text(definition.textbook),
        "intermediates": [(latex(s), latex(v)) for s, v in a.intermediates],
        "outputs": [("V", latex(a.potential)), ("R", latex(a.dissipation))]
        + [(name, latex(f, 3)) for name, f in zip(forces, a.forces, strict=False)],
        "proofs": result.proofs,
    }


def _row_label(k: int, rows: int) -> str:
    return ("_x", "_y")[k] if rows == 2 else ""


def render(results: dict[str, ModuleResult]) -> str:
    osc = [osculating_check(), osculating_check(a=3.0, b=0.5, phi=2.0)]
    env = environment()
    env.filters["tex_text"] = tex_text
    template = env.get_template("derivations.tex.j2")
    by_kind = {
        k: [r for r in results.values() if r.kind == k]
        for k in ("case", "friction", "joint", "applied")
    }
    friction = [
        dict(
            _rows_context(r, {"tangent_velocity": "v_t", "tangent_acceleration": r"\dot v_t"}),
            points=tex_text(CONTACT_POINTS[r.name.removesuffix("_friction")]),
        )
        for r in by_kind["friction"]
    ]
    joints = [
        dict(
            _rows_context(
                r,
                {"gap": "d{row}", "gap_velocity": "d'{row}", "gap_acceleration": "d''{row}"},
            ),
            definition=tex_text(ALL_JOINTS[r.name]().definition),
        )
        for r in by_kind["joint"]
    ]
    return template.render(
        cases=[_case_context(r) for r in by_kind["case"]],
        friction=friction,
        joints=joints,
        applied=[_applied_context(r) for r in by_kind["applied"]],
        osculating=osc,
    )


def build_pdf(tex_path: Path) -> Path | None:
    """pdflatex twice in a scratch folder; returns the PDF path, or None when pdflatex is absent."""
    pdflatex = shutil.which("pdflatex")
    if pdflatex is None:
        return None
    env = {**os.environ, "SOURCE_DATE_EPOCH": "0", "FORCE_SOURCE_DATE": "1"}
    with tempfile.TemporaryDirectory() as scratch:
        for _ in range(2):
            done = subprocess.run(
                [pdflatex, "-interaction=nonstopmode", "-halt-on-error", str(tex_path.resolve())],
                cwd=scratch,
                env=env,
                capture_output=True,
                text=True,
                check=False,
            )
            if done.returncode != 0:
                log = done.stdout[-3000:]
                raise RuntimeError(f"pdflatex failed on {tex_path}:\n{log}")
        pdf = tex_path.with_suffix(".pdf")
        shutil.copyfile(Path(scratch) / pdf.name, pdf)
    return pdf
