"""`make` on the machines people have: without TeX as a non-root user it goes on with a notice;
as root (CI) it installs TeX; and the package's metadata is current (SPDX license, py.typed).

The Makefile's TeX logic runs for real with a PATH that holds only a fake ``id`` (reporting a
user or root) and, for root, a fake ``apt-get`` that records what it was asked to install.
"""

from __future__ import annotations

import subprocess
import tomllib
from importlib import metadata
from pathlib import Path

from app_helpers import ROOT

FAKE_ID = "#!/bin/sh\necho {uid}\n"
FAKE_APT = '#!/bin/sh\necho "$@" >> "{log}"\n'


def make(targets: list[str], bin_dir: Path) -> subprocess.CompletedProcess:
    """make TARGETS with PATH = bin_dir only: no pdflatex, no sudo, the fakes there."""
    return subprocess.run(
        ["/usr/bin/make", "--no-print-directory", "-s", "-C", str(ROOT), *targets],
        env={"PATH": str(bin_dir), "HOME": str(bin_dir)},
        capture_output=True,
        text=True,
        timeout=60,
    )


def fake_bin(tmp_path: Path, uid: int) -> Path:
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    for name, text in (
        ("id", FAKE_ID.format(uid=uid)),
        ("apt-get", FAKE_APT.format(log=tmp_path / "apt.log")),
    ):
        (bin_dir / name).write_text(text)
        (bin_dir / name).chmod(0o755)
    return bin_dir


def test_without_tex_and_not_root_make_goes_on_with_one_notice(tmp_path):
    done = make(["tex", "pdf-check"], fake_bin(tmp_path, 1000))
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == [
        "make: pdflatex not found and not root (no passwordless sudo): going on without TeX; the "
        "PDF is skipped (install: apt-get install texlive-latex-base texlive-latex-recommended "
        "texlive-fonts-recommended lmodern)",
        "make: pdflatex not found: the PDF build check is skipped",
    ]
    assert "sudo" not in done.stderr
    assert not (tmp_path / "apt.log").exists()


def test_as_root_without_tex_make_installs_it(tmp_path):
    done = make(["tex"], fake_bin(tmp_path, 0))
    assert done.returncode == 0, done.stderr
    calls = (tmp_path / "apt.log").read_text().splitlines()
    assert calls[0] == "update -qq"
    assert calls[1].split()[-4:] == [
        "texlive-latex-base", "texlive-latex-recommended", "texlive-fonts-recommended", "lmodern",
    ]  # fmt: skip


def test_the_main_job_does_not_depend_on_tex_succeeding():
    """`make` = regenerate + demo; the only TeX step it has is `tex`, tested above."""
    done = subprocess.run(
        ["make", "-n", "-C", str(ROOT), "all"], capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 0, done.stderr
    assert "regenerate-equations" in done.stdout and "simulate" in done.stdout
    assert "sudo apt-get" not in done.stdout


def test_license_is_an_spdx_expression_and_the_package_is_typed():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert project["project"]["license"] == "MIT"
    assert project["tool"]["setuptools"]["package-data"]["runtime"] == ["py.typed"]
    assert (ROOT / "runtime" / "py.typed").is_file()
    assert metadata.metadata("curved-edge-physics")["License-Expression"] == "MIT"
    assert "box2d==2.3.10" in project["project"]["optional-dependencies"]["peers"]
