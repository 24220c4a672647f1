"""README.md is a contract: every Python example in it runs as written, every command exists.

Why: a new user copies the README first; an example that fails there is the first thing they
meet (issue #14).  Each ```python block runs in a fresh interpreter with the repository as the
working directory and must exit 0 without writing to stderr.  Each line of a ```sh block is
checked by what its first word is: ``make T`` must be a target (``make -n T``), ``simulate`` and
``python -m runtime`` lines run for real in a scratch folder (they are kept short in the README),
``regenerate-equations --check`` runs, other ``regenerate-equations`` lines (they write files)
must use only options its ``--help`` lists, ``pip install`` lines must name extras that
pyproject.toml defines.  A command with no rule here fails the test, so a new kind of command
gets a check when it is added.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
BIN = Path(sys.executable).parent
FENCE = re.compile(r"^```(\w+)[^\n]*\n(.*?)^```", re.M | re.S)

# Blocks that fail for a reason someone else is fixing: first line of the block -> (reason, the
# error it must fail with). Any other failure fails the test; a pass fails it too (strict), so
# the entry is removed when the fix lands.
KNOWN_FAILURES: dict[str, tuple[str, str]] = {}  # first line of a block: (reason, error)


def blocks(language: str) -> list[str]:
    return [m[2] for m in FENCE.finditer(README.read_text()) if m[1] == language]


def commands() -> list[str]:
    lines = []
    for block in blocks("sh") + blocks("console"):
        for line in block.splitlines():
            line = line.removeprefix("$ ").split("#", 1)[0].strip()
            if line:
                lines.append(line)
    return lines


def env() -> dict[str, str]:
    return {**os.environ, "PATH": f"{BIN}:{os.environ.get('PATH', '')}", "PYTHONPATH": str(ROOT)}


def test_the_readme_has_examples_and_commands():
    assert len(blocks("python")) >= 2
    assert commands()[:2] == ["make", "make test"]


def _python_params():
    params = []
    for k, code in enumerate(blocks("python")):
        first = code.splitlines()[0].strip()
        marks = []
        if first in KNOWN_FAILURES:
            reason = KNOWN_FAILURES[first][0]
            marks.append(
                pytest.mark.xfail(raises=pytest.xfail.Exception, strict=True, reason=reason)
            )
        params.append(pytest.param(code, id=f"python-{k}", marks=marks))
    return params


@pytest.mark.parametrize("code", _python_params())
def test_python_example_runs(code):
    done = subprocess.run(
        [sys.executable, "-c", code],
        cwd=ROOT,
        env=env(),
        capture_output=True,
        text=True,
        timeout=300,
    )
    known = KNOWN_FAILURES.get(code.splitlines()[0].strip())
    if known and done.returncode != 0:
        assert known[1] in done.stderr, done.stderr  # fails for the known reason only
        pytest.xfail(known[0])
    assert done.returncode == 0, done.stderr
    assert done.stderr == ""


def _run(argv: list[str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(argv, cwd=cwd, env=env(), capture_output=True, text=True, timeout=600)


def check_make(argv: list[str], tmp_path: Path) -> None:
    targets = argv[1:] or ["all"]
    done = _run(["make", "-n", *targets], ROOT)
    assert done.returncode == 0, f"{shlex.join(argv)}: {done.stderr}"


def check_simulate(argv: list[str], tmp_path: Path) -> None:
    (tmp_path / "scenes").symlink_to(ROOT / "scenes")
    done = _run(argv, tmp_path)
    assert done.returncode == 0, f"{shlex.join(argv)}: {done.stderr}"
    assert "->" in done.stdout  # the one-line summary


def check_regenerate(argv: list[str], tmp_path: Path) -> None:
    if argv[1:] == ["--check"]:
        done = _run(argv, ROOT)
        assert done.returncode == 0, done.stdout + done.stderr
        return
    help_text = _run([argv[0], "--help"], ROOT).stdout
    for option in (a.split("=")[0] for a in argv[1:] if a.startswith("--")):
        assert option in help_text, f"{shlex.join(argv)}: {option} is not an option"


def check_pip(argv: list[str], tmp_path: Path) -> None:
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"][
        "optional-dependencies"
    ]
    for target in argv[2:]:
        match = re.fullmatch(r"-e|\.|'?\.\[([\w,]+)\]'?", target)
        assert match, f"{shlex.join(argv)}: unexpected argument {target!r}"
        for extra in (match[1] or "").split(",") if match[1] else []:
            assert extra in extras, f"{shlex.join(argv)}: no extra {extra!r} in pyproject.toml"


def check_sweep(argv: list[str], tmp_path: Path) -> None:
    """A sweep starts worker processes and runs for a while (tests/app/test_sweep.py runs it):
    here its options must be among those --help lists, and its --vary values must parse."""
    from runtime.app.sweep_grid import parse_vary

    help_text = _run([sys.executable, "-m", "runtime.app.sweep", "--help"], ROOT).stdout
    for k, arg in enumerate(argv):
        if arg.startswith("--"):
            assert arg in help_text, f"{shlex.join(argv)}: {arg} is not an option"
        if arg == "--vary":
            parse_vary(argv[k + 1])


RULES = {
    "make": check_make,
    "simulate": check_simulate,
    "regenerate-equations": check_regenerate,
    "sweep": check_sweep,
}


@pytest.mark.parametrize("line", commands())
def test_command_exists_or_runs(line, tmp_path):
    argv = shlex.split(line)
    if argv[:3] == ["python", "-m", "runtime.app.sweep"]:
        check_sweep(argv, tmp_path)
    elif argv[:3] == ["python", "-m", "runtime"]:
        argv[0] = sys.executable
        check_simulate(argv, tmp_path)
    elif argv[:2] == ["pip", "install"]:
        check_pip(argv, tmp_path)
    elif argv[0] in RULES:
        RULES[argv[0]](argv, tmp_path)
    else:
        pytest.fail(f"README command {line!r} has no check in tests/test_readme.py")
