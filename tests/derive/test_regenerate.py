"""generated/ and docs/derivations.tex are what regenerate-equations produces now (stale check),
the output is deterministic, a subset leaves the document whole, and the CLI refuses bad input
(or a missing derive extra) clearly."""

import functools
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from derive import cli, generate
from derive.cases import ALL_CASES

ROOT = Path(__file__).resolve().parents[2]
INSTALL_HINT = "pip install 'curved-edge-physics[derive]'"


@pytest.fixture(autouse=True, scope="module")
def _derive_each_case_once():
    """Several tests here run the CLI in-process; derive each module once for all of them."""
    original = generate.generate_module
    generate.generate_module = functools.cache(original)
    yield
    generate.generate_module = original


def test_committed_outputs_are_up_to_date(capsys):
    assert cli.main(["--check"]) == 0, capsys.readouterr().err


def test_check_names_a_modified_generated_file(tmp_path, capsys):
    code, docs = tmp_path / "generated", tmp_path / "docs"
    args = ["--cases", "vertex_edge", "--code-dir", str(code), "--docs-dir", str(docs)]
    assert cli.main([*args, "--no-pdf"]) == 0
    assert cli.main([*args, "--check"]) == 0
    target = code / "vertex_edge.py"
    target.write_text(target.read_text().replace("n_x = ", "n_x = 1.0 + ", 1))
    capsys.readouterr()
    assert cli.main([*args, "--check"]) == 1
    assert "vertex_edge.py" in capsys.readouterr().err


def test_output_is_deterministic_across_hash_seeds(tmp_path):
    """Two runs with different PYTHONHASHSEED write byte-identical kernels."""
    outputs = []
    for seed in ("1", "2"):
        out = tmp_path / seed
        subprocess.run(
            [
                sys.executable,
                "-m",
                "derive.cli",
                "--cases",
                "circle_circle",
                "--no-pdf",
                "--code-dir",
                str(out / "generated"),
                "--docs-dir",
                str(out / "docs"),
            ],
            check=True,
            cwd=ROOT,
            env={"PYTHONHASHSEED": seed, "PATH": str(Path(sys.executable).parent)},
            capture_output=True,
        )
        outputs.append((out / "generated" / "circle_circle.py").read_bytes())
    assert outputs[0] == outputs[1]


def test_unknown_case_is_named():
    with pytest.raises(SystemExit, match="unknown case.*banana.*valid cases: vertex_edge"):
        cli.main(["--cases", "vertex_edge,banana", "--check"])


def test_refuses_to_overwrite_a_file_it_did_not_write(tmp_path):
    code = tmp_path / "generated"
    code.mkdir()
    (code / "vertex_edge.py").write_text("# my own notes\n")
    args = ["--cases", "vertex_edge", "--code-dir", str(code), "--docs-dir", str(tmp_path)]
    with pytest.raises(SystemExit, match="refusing to overwrite"):
        cli.main([*args, "--no-pdf"])
    assert (code / "vertex_edge.py").read_text() == "# my own notes\n"


def test_generated_modules_list_only_requested_cases(tmp_path):
    code = tmp_path / "generated"
    args = ["--cases", "circle_edge,circle_circle", "--code-dir", str(code)]
    assert cli.main([*args, "--docs-dir", str(tmp_path), "--no-pdf"]) == 0
    assert sorted(p.name for p in code.glob("*.py")) == [
        "__init__.py",
        "circle_circle.py",
        "circle_edge.py",
    ]
    namespace: dict = {}
    exec((code / "__init__.py").read_text(), namespace)
    assert namespace["CASES"] == ("circle_circle", "circle_edge")


def test_subset_leaves_the_document_whole(tmp_path, capsys):
    """--cases vertex_circle rewrites that case's kernels only; the document keeps every case
    and the full --check stays green afterwards (issue #14)."""
    code, docs = tmp_path / "generated", tmp_path / "docs"
    shutil.copytree(ROOT / "generated", code, ignore=shutil.ignore_patterns("__pycache__"))
    docs.mkdir()
    shutil.copy(ROOT / "docs" / "derivations.tex", docs)
    before = (docs / "derivations.tex").read_bytes()
    dirs = ["--code-dir", str(code), "--docs-dir", str(docs)]
    assert cli.main(["--cases", "vertex_circle", *dirs]) == 0
    assert "derivations.tex left as it is" in capsys.readouterr().out
    assert (docs / "derivations.tex").read_bytes() == before
    sections = re.findall(r"\\section\{.*\(\\texttt\{(\w+)\}", before.decode().replace("\\_", "_"))
    assert sections == list(ALL_CASES)
    assert cli.main(["--check", *dirs]) == 0, capsys.readouterr().err


def test_case_names_without_sympy_match_the_cases():
    assert cli.CASE_NAMES == tuple(ALL_CASES)


def test_missing_derive_extra_names_the_install_command():
    """Without SymPy, the command says how to install it: one line, no traceback."""
    code = "import sys; sys.modules['sympy'] = None; from derive.cli import main; main(['--check'])"
    done = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=False
    )
    assert done.returncode == 1
    assert done.stderr.strip() == (
        f"regenerate-equations needs sympy, which is not installed: {INSTALL_HINT}"
    )


def test_python_dash_m_derive_runs_the_command(tmp_path):
    out = tmp_path / "generated"
    args = [
        "--cases",
        "vertex_edge",
        "--no-pdf",
        "--code-dir",
        str(out),
        "--docs-dir",
        str(tmp_path),
    ]
    done = subprocess.run(
        [sys.executable, "-m", "derive", *args],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert "vertex_edge" in done.stdout and "all proofs hold" in done.stdout
    assert (out / "vertex_edge.py").read_text() == (
        ROOT / "generated" / "vertex_edge.py"
    ).read_text()
    assert not (tmp_path / "derivations.tex").exists()
