"""docs/derivations.tex prints what it means: no character that the default (OT1) text font
misprints (">" as an inverted question mark, "|" as a dash, "''" as a closing double quote)
outside math mode, and every case's proofs listed with a check mark."""

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from derive.cases import ALL_CASES
from derive.document import tex_text

TEX = Path(__file__).resolve().parents[2] / "docs" / "derivations.tex"
MATH = re.compile(
    r"\$[^$]*\$|\\\[.*?\\\]|\\begin\{(align\*|tabular)\}.*?\\end\{\1\}", flags=re.DOTALL
)


def _text_mode(tex: str) -> str:
    """The document without comments and math (inline, display, align, tabular)."""
    tex = re.sub(r"(?m)^%.*$", "", tex)
    return MATH.sub(" ", tex)


def test_text_escapes_put_symbols_in_math_mode():
    assert tex_text("radius r1 > 0 and |v| < 1") == "radius r1 $>$ 0 and $|$v$|$ $<$ 1"
    assert tex_text("d'' = t^2, M^-1 J^T, a_b") == "d'{}' = t$^{2}$, M$^{-1}$ J$^{T}$, a\\_b"


def test_document_text_has_no_misprinted_characters():
    tex = TEX.read_text()
    text = _text_mode(tex)
    for bad in (">", "<", "|", "d''", "'''"):  # a double prime; ``quotes'' are fine
        where = text.find(bad)
        assert where < 0, f"{bad!r} in text mode: ...{text[max(where - 60, 0) : where + 20]}..."
    assert "radius r1 $>$ 0" in tex
    assert "$|$v$|$" in tex


def test_document_lists_every_case_with_its_proofs():
    tex = TEX.read_text()
    for case in ALL_CASES:
        section = tex.split(f"\\texttt{{{case.replace('_', chr(92) + '_')}}}")[1].split(
            "\\section"
        )[0]
        items = re.findall(r"\\item\[(.*?)\]", section)
        assert len(items) >= 5 and set(items) == {"$\\checkmark$"}, (case, items)
        assert "the whole d'{}' (velocity terms included)" in section


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason="pdflatex is not installed")
def test_document_builds(tmp_path):
    """The committed .tex compiles (a statement with a stray ^ or _ would stop pdflatex)."""
    done = subprocess.run(
        ["pdflatex", "-interaction=nonstopmode", "-halt-on-error", str(TEX)],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stdout[-2000:]


def test_document_lists_every_friction_row_and_joint_with_its_proofs():
    """Each tangential row and joint has its subsection with its proofs, every one holding."""
    tex = TEX.read_text()
    expected = {f"{case}_friction": 4 for case in ALL_CASES} | {"pin_joint": 4, "distance_joint": 4}
    for name, least in expected.items():
        title = f"\\texttt{{{name.replace('_', chr(92) + '_')}}}"
        assert tex.count(title) == 1, name
        section = tex.split(title)[1].split("section")[0]
        items = re.findall(r"\\item\[(.*?)\]", section)
        assert len(items) >= least and set(items) == {"$\\checkmark$"}, (name, items)
    assert tex.index("\\section{Tangential (friction) rows}") < tex.index("\\section{Joints}")
