"""The command's robustness (issue #13): numbers out of range, names with escape codes, Ctrl-C at
start-up, a warning before a very long run, progress in a log, and ``python -m runtime``.

Each bad input is checked for the whole line it gets, exit status 2, no traceback and no output
folder; the long-run warning's figures against lower bounds counted from the arrays a run
records (poses and velocities: 48 bytes per body per step).
"""

from __future__ import annotations

import io
import re
import signal
import time

import pytest
from app_helpers import start_command, wait_for
from conftest import SMALL_SCENE

from runtime.app import cli, estimate, progress
from runtime.app.text import folder_name, human_bytes, human_seconds, terminal_safe


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--fps", "0.001"], "--fps must be a number from 0.01 to 1000, got 0.001"),
        (["--fps", "1e308"], "--fps must be a number from 0.01 to 1000, got 1e308"),
        (["--fps", "1e-310"], "--fps must be a number from 0.01 to 1000, got 1e-310"),
        (["--dt", "1e308"], "--dt must be a number from 1e-50 to 1e+50 s, got 1e308"),
        (["--dt", "1e-310"], "--dt must be a number from 1e-50 to 1e+50 s, got 1e-310"),
        (["--duration", "1e308"], "--duration must be a number from 1e-50 to 1e+50 s, got 1e308"),
        (["--duration", "1e-310"], "--duration must be a number from 1e-50 to 1e+50 s, got 1e-310"),
        (["--duration", "nan"], "--duration must be a number from 1e-50 to 1e+50 s, got nan"),
        (["--dt", "fast"], "--dt must be a number from 1e-50 to 1e+50 s, got 'fast'"),
        (
            ["--size", "10x10"],
            "--size must be WIDTHxHEIGHT in pixels, each from 64 to 4096, got '10x10'",
        ),
        (
            ["--size", "big"],
            "--size must be WIDTHxHEIGHT in pixels, each from 64 to 4096, got 'big'",
        ),
        (["--dpi", "0"], "--dpi must be a number from 10 to 600, got 0"),
    ],
    ids=lambda v: " ".join(v) if isinstance(v, list) else None,
)
def test_numbers_out_of_range_name_the_flag(tmp_path, scene_file, capsys, args, message):
    out = tmp_path / "out"
    assert cli.main([str(scene_file()), "--out", str(out), *args]) == 2
    captured = capsys.readouterr()
    assert captured.err == f"simulate: error: {message}\n"
    assert captured.out == ""
    assert not out.exists()


def test_names_with_terminal_escapes_are_refused_in_plain_text(tmp_path, scene_file, capsys):
    """The loader refuses a name with control characters (runtime.io); the message names the
    character in plain text, so nothing reaches the terminal raw."""
    scene = scene_file(SMALL_SCENE.replace('name = "small"', 'name = "\\u001b[31mred\\u0007"'))
    assert cli.main([str(scene), "--duration", "0.005", "--out", str(tmp_path / "o")]) == 2
    captured = capsys.readouterr()
    assert "\x1b" not in captured.err + captured.out and "\x07" not in captured.err
    assert "field 'name': contains the non-printing character U+001B" in captured.err


def test_an_error_naming_a_body_with_escapes_is_printed_escaped(tmp_path, scene_file, capsys):
    bad = SMALL_SCENE.replace('name = "resting"', 'name = "\\u001b]0;owned\\u0007"').replace(
        "radius = 0.1 }", "radius = -0.1 }"
    )
    assert cli.main([str(scene_file(bad)), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "\x1b" not in err and "\x07" not in err
    assert "body #2: field 'name': contains the non-printing character U+001B" in err
    assert len(err.splitlines()) == 1


def test_terminal_safe_and_folder_name():
    assert terminal_safe("plain Größe $x$") == "plain Größe $x$"
    assert terminal_safe("a\nb\r\x1b[2J\u202e") == "a\\x0ab\\x0d\\x1b[2J\\u202e"
    assert folder_name("../../etc/passwd") == "etc_passwd"
    assert folder_name("\x1b[31m") == "31m"
    assert folder_name("...") == "scene"


@pytest.mark.parametrize("delay", [0.3, 1.0])
def test_ctrl_c_during_start_up_is_one_line(tmp_path, scene_file, delay):
    run = start_command([str(scene_file()), "--duration", "100", "--out", "o"], tmp_path)
    time.sleep(delay)
    run.send_signal(signal.SIGINT)
    out, err = run.communicate(timeout=60)
    assert run.returncode == 130, err
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("python -m runtime: interrupted"), err
    assert out == ""
    assert not (tmp_path / "o").exists()


FINALISER_INTERRUPTED = """
import os, signal, sys, time
from runtime.app.interrupts import redeliver

class Interrupted:
    def __del__(self):  # as llvmlite's finalisers, run while numba compiles
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(0.05)  # the KeyboardInterrupt is raised here, inside the finaliser

class Failing:
    def __del__(self):
        raise ValueError("a finaliser's own error")

sys.unraisablehook = redeliver
Failing()
try:
    Interrupted()
    time.sleep(5)
    print("not interrupted")
except KeyboardInterrupt:
    print("interrupted in the main thread")
"""


def test_a_ctrl_c_in_a_finaliser_reaches_the_main_thread_and_other_errors_still_print(tmp_path):
    """The start-up Ctrl-C of test_ctrl_c_during_start_up_is_one_line, when it lands in a
    finaliser (where Python can only print it): interrupts.redeliver raises it again in the main thread;
    a finaliser's other errors are printed as Python prints them."""
    import subprocess
    import sys

    done = subprocess.run(
        [sys.executable, "-c", FINALISER_INTERRUPTED], capture_output=True, text=True, timeout=60
    )
    assert done.stdout.strip() == "interrupted in the main thread"
    assert "KeyboardInterrupt" not in done.stderr
    assert "ValueError: a finaliser's own error" in done.stderr


def test_python_dash_m_runtime_is_the_command(tmp_path):
    run = start_command(["--help"], tmp_path)
    out, err = run.communicate(timeout=60)
    assert run.returncode == 0, err
    assert out.startswith("usage: python -m runtime [-h]")
    assert "--out DIR" in out and "default: out/<scene name>" in out


def test_a_very_long_run_is_announced_with_its_time_and_memory(tmp_path, scene_file):
    """--duration 1e9 at dt = 1 ms: 1e12 steps of 3 bodies. The warning comes before the run
    (which is then interrupted); its figures are at least what the recorded poses and
    velocities alone need (2 x 3 bodies x 3 x 8 bytes per step) and at least 1 us a step."""
    run = start_command([str(scene_file()), "--duration", "1e9", "--out", "o"], tmp_path)
    lines: list[str] = []
    try:
        wait_for(lambda: lines.append(run.stderr.readline()) or "warning" in lines[-1], 120, "it")
        run.send_signal(signal.SIGINT)
        rest = run.communicate(timeout=60)[1]
    finally:
        run.kill()
    warning = lines[-1].strip()
    match = re.fullmatch(
        r"python -m runtime: warning: 1e\+12 steps of 3 bodies: expect ~([\d.e+]+) years and "
        r"~([\d.e+]+) GB of memory to record them \(([\d.e+-]+) ms and ([\d.e+]+) (k?B) per step "
        r"in a 20-step probe\); Ctrl-C stops the run, a larger --dt or a shorter --duration "
        r"shortens it",
        warning,
    )
    assert match, warning
    years, gigabytes = float(match[1]), float(match[2])
    assert years * 365.25 * 86400 >= 1e12 * 1e-6
    assert gigabytes * 1e9 >= 1e12 * 2 * 3 * 3 * 8
    assert run.returncode == 130
    assert (
        rest.strip().splitlines()[-1]
        == "python -m runtime: interrupted; 'o' keeps its previous contents"
    )


def test_short_runs_are_not_probed(scene_file, tmp_path):
    from runtime import load_scene

    scene = load_scene(scene_file())
    assert estimate.probe(scene, 1000, 1e-3, "rk4") is None  # 3000 < PROBE_FROM


def test_estimate_units():
    assert human_seconds(42) == "42 s"
    assert human_seconds(600) == "10 min"
    assert human_seconds(3 * 86400) == "3 days"
    assert human_seconds(1e12 * 5e-4) == "15.8 years"
    assert human_seconds(1e12) == "3.17e+04 years"
    assert human_bytes(3.5e5) == "350 kB"
    assert human_bytes(2.1e9) == "2.1 GB"


# -- progress ------------------------------------------------------------------------------------


class Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def test_progress_lines_every_interval_after_the_delay():
    stream, clock = io.StringIO(), Clock()
    lines = progress.ProgressLines(stream, 10.0, delay=5.0, interval=5.0, clock=clock)
    for k in range(1, 41):  # a step every 0.5 s of wall time, 0.25 s simulated each
        clock.now = 0.5 * k
        lines(k / 40)
    assert stream.getvalue().splitlines() == [
        "simulate: 25% (t = 2.5 of 10 s simulated), 5 s elapsed, ~15 s left",
        "simulate: 50% (t = 5 of 10 s simulated), 10 s elapsed, ~10 s left",
        "simulate: 75% (t = 7.5 of 10 s simulated), 15 s elapsed, ~5 s left",
        "simulate: 100% (t = 10 of 10 s simulated), 20 s elapsed, ~0 s left",
    ]


def test_progress_goes_to_a_log_when_stderr_is_not_a_terminal(
    tmp_path, scene_file, capsys, monkeypatch
):
    class Often(progress.ProgressLines):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **{**kwargs, "delay": 0.0, "interval": 0.0})

    monkeypatch.setattr(progress, "ProgressLines", Often)
    assert cli.main([str(scene_file()), "--duration", "0.01", "--out", str(tmp_path / "o")]) == 0
    err = capsys.readouterr().err.splitlines()
    # one a report of progress: a step one by one, or a stretch of coasted steps at once
    shares = [float(re.match(r"simulate: (\d+)%", line)[1]) for line in err]
    assert len(err) >= 2 and shares == sorted(set(shares)) and shares[-1] == 100
    assert re.match(r"simulate: 100% \(t = 0\.01 of 0\.01 s simulated\), \d+ s elapsed", err[-1])
    assert all("\r" not in line for line in err)
    assert (
        cli.main([str(scene_file()), "--duration", "0.01", "--out", str(tmp_path / "q"), "--quiet"])
        == 0
    )
    assert capsys.readouterr().err == ""


def test_an_interrupt_inside_a_c_extension_import_is_one_line(monkeypatch, capsys):
    """Ctrl-C while scipy's HiGHS extension initialises surfaces as "ImportError:
    initialization failed" (and the next import of the half-loaded package fails again): the
    command still ends as interrupted, status 130, one line; another ImportError is not hidden."""

    def interrupted_import(args, prog):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt:
            try:
                raise ImportError("initialization failed")
            except ImportError:
                raise ImportError("cannot import name 'SceneError'") from None

    monkeypatch.setattr(cli, "run_command", interrupted_import)
    assert cli.main(["scene.toml"]) == 130
    assert capsys.readouterr().err.strip().splitlines() == ["simulate: interrupted"]

    def broken(args, prog):
        raise ImportError("no module named 'foo'")

    monkeypatch.setattr(cli, "run_command", broken)
    with pytest.raises(ImportError, match="foo"):
        cli.main(["scene.toml"])


def test_an_interrupt_inside_a_compiled_call_is_one_line_and_keeps_the_results(
    monkeypatch, capsys, scene_file, tmp_path
):
    """Ctrl-C while numba's dispatcher is in a compiled call (it runs Python to unpickle the
    result) surfaces as "SystemError: ... returned a result with an exception set" with the
    KeyboardInterrupt as its cause: a --force rerun still ends as interrupted, status 130, one
    line, the previous results untouched; another SystemError is not hidden."""
    scene, out = str(scene_file()), tmp_path / "out"
    assert cli.main([scene, "--duration", "0.01", "--out", str(out), "--quiet"]) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    capsys.readouterr()

    def interrupted(*args, **kwargs):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as exc:
            raise SystemError("CPUDispatcher(<function _merged>) returned a result") from exc

    monkeypatch.setattr(cli, "_simulate", interrupted)
    assert cli.main([scene, "--duration", "0.01", "--out", str(out), "--force"]) == 130
    assert capsys.readouterr().err.strip().splitlines() == [
        f"simulate: interrupted; {str(out)!r} keeps its previous contents"
    ]
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before

    def broken(*args, **kwargs):
        raise SystemError("a bug")

    monkeypatch.setattr(cli, "_simulate", broken)
    with pytest.raises(SystemError, match="a bug"):
        cli.main([scene, "--duration", "0.01", "--out", str(out), "--force"])
