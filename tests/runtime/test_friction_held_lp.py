"""The held island's linear program (runtime.solve.friction_lcp.held_forces) on an input where
scipy 1.17.1's HiGHS presolve corrupted the heap and aborted the whole process ("corrupted size
vs. prev_size"): captured from a half disc sliding into a V of walls with end vertices, mu = 0.5.
Solved in a child process, so that a crash fails this test instead of killing the test run."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
from scipy import optimize

DATA = Path(__file__).parent / "data" / "held_lp_presolve_crash.json"
SOLVE = """
import json, sys
import numpy as np
from runtime.solve.friction_lcp import held_forces
lp = json.loads(open(sys.argv[1]).read())
found = held_forces(np.array(lp["cost"]), np.array(lp["cone"]), np.array(lp["equations"]),
                    np.array(lp["rhs"]), [tuple(b) for b in lp["bounds"]])
print(json.dumps({"status": int(found.status), "x": found.x.tolist(), "fun": float(found.fun)}))
"""


def test_the_lp_that_crashed_highs_presolve_is_solved():
    root = Path(__file__).resolve().parents[2]
    child = subprocess.run(
        [sys.executable, "-c", SOLVE, str(DATA)], capture_output=True, text=True, cwd=root
    )
    assert child.returncode == 0, child.stderr[-500:]
    found = json.loads(child.stdout.strip().splitlines()[-1])
    lp = json.loads(DATA.read_text())
    cost, cone = np.array(lp["cost"]), np.array(lp["cone"])
    equations, rhs = np.array(lp["equations"]), np.array(lp["rhs"])
    bounds = [(lo, hi) for lo, hi in lp["bounds"]]
    assert found["status"] == 0
    x = np.array(found["x"])
    # within HiGHS's primal feasibility tolerance (1e-7; the engine then checks the forces as a
    # solution of the friction LCP itself, to settings.LCP_TOL)
    scale = np.abs(equations).max() * np.abs(x).max() + np.abs(rhs).max()
    assert np.abs(equations @ x - rhs).max() <= 1e-7 * scale
    assert (cone @ x).max() <= 1e-7 * scale
    lower = np.array([lo for lo, _ in bounds])
    upper = np.array([np.inf if hi is None else hi for _, hi in bounds])
    assert np.all((lower - 1e-12 <= x) & (x <= upper + 1e-12))
    # the optimum, by an interior-point method (without presolve: it crashes there too)
    other = optimize.linprog(cost, cone, np.zeros(len(cone)), equations, rhs, bounds,
                             method="highs-ipm", options={"presolve": False})  # fmt: skip
    assert other.status == 0
    assert abs(found["fun"] - other.fun) <= 1e-9 * max(1.0, abs(other.fun))
