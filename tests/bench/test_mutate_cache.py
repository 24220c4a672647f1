"""`make mutate` shares one warm numba cache between mutants (bench/mutate_cache.py) without ever
loading code compiled from other sources.

Why: numba checks only the stamp of a compiled function's own file, so a cached caller keeps
the code of a callee or a constant from another file after that file changed. The tests show
that hazard on a small repository and that the pruned copy recompiles exactly what it must; and
they check, on the real engine, that what each compiled function names comes from the modules
its own module imports (the import graph the pruning follows).
"""

from __future__ import annotations

import importlib
import os
import shutil
import subprocess
import sys
import types
from pathlib import Path

import numba
import pytest

from bench.mutate_cache import (
    cache_folder,
    changed_files,
    import_graph,
    modules,
    stale_files,
    warm_copy,
)

ROOT = Path(__file__).resolve().parents[2]

SOURCES = {
    "runtime/__init__.py": "",
    "runtime/constants.py": "SCALE = 10.0\n",
    "runtime/callee.py": (
        "from runtime.compiled import njit\n\n\n@njit\ndef gain():\n    return 1.0\n"
    ),
    "runtime/caller.py": (
        "from runtime.callee import gain\nfrom runtime.compiled import njit\n"
        "from runtime.constants import SCALE\n\n\n@njit\ndef force():\n"
        "    return gain() * SCALE\n"
    ),
    "runtime/plain.py": "def helper():\n    return 3\n",
    "tests/helpers.py": "from runtime.caller import force\n",
    "tests/test_force.py": "from helpers import force\n",  # by bare name, as tests/ do
}
PROBE = (
    "from runtime.caller import force\n"
    "print(force(), len(force.stats.cache_hits), len(force.stats.cache_misses))\n"
)


def _tree(folder: Path, changes: dict[str, tuple[str, str]] | None = None) -> Path:
    """The small repository (with the real runtime/compiled.py), one text replaced per file."""
    for name, text in SOURCES.items():
        for old, new in [(changes or {}).get(name, ("", ""))]:
            text = text.replace(old, new) if old else text
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_text(text)
    shutil.copy2(ROOT / "runtime" / "compiled.py", folder / "runtime" / "compiled.py")
    return folder


def _environment(tree: Path, cache: Path) -> dict[str, str]:
    env = dict(os.environ, PYTHONPATH=str(tree), CURVED_EDGE_CACHE=str(cache))
    env.pop("NUMBA_DISABLE_JIT", None)
    return env


def _force(tree: Path, env: dict) -> tuple[float, int, int]:
    """force() in `tree`, and numba's cache hits and misses for it."""
    done = subprocess.run([sys.executable, "-c", PROBE], cwd=tree, env=env, capture_output=True,
                          text=True, check=True, timeout=300)  # fmt: skip
    value, hits, misses = done.stdout.split()
    return float(value), int(hits), int(misses)


@pytest.fixture
def warm(tmp_path):
    """(pristine tree, the cache folder its run built), the work tree's files kept in place."""
    pristine = _tree(tmp_path / "pristine")
    work = tmp_path / "work"
    shutil.copytree(pristine, work)  # copy2: the stamps numba checks stay the pristine ones
    env = _environment(work, tmp_path / "warm")
    assert _force(work, env) == (10.0, 0, 1)  # compiled once, from the unmutated sources
    return pristine, work, cache_folder(work, env)


def _mutate(pristine: Path, work: Path, name: str, old: str, new: str) -> None:
    shutil.rmtree(work)
    shutil.copytree(pristine, work)
    path = work / name
    path.write_text(path.read_text().replace(old, new))


@pytest.mark.parametrize(
    ("name", "old", "new", "expected"),
    [
        ("runtime/callee.py", "return 1.0", "return 2.0", 20.0),  # a compiled callee
        ("runtime/constants.py", "10.0", "5.0", 5.0),  # a constant frozen into the caller
    ],
)
def test_a_mutant_that_reaches_compiled_code_is_recompiled(
    warm, tmp_path, name, old, new, expected
):
    pristine, work, folder = warm
    _mutate(pristine, work, name, old, new)
    assert changed_files(pristine, work) == {name}
    assert stale_files(pristine, work) == {
        name, "runtime/caller.py", "tests/helpers.py", "tests/test_force.py"
    }  # fmt: skip

    # the hazard: the whole warm cache copied over keeps the unmutated caller's code
    env = _environment(work, tmp_path / "unpruned")
    shutil.copytree(folder, cache_folder(work, env), dirs_exist_ok=True)
    assert _force(work, env) == (10.0, 1, 0)

    env = _environment(work, tmp_path / "pruned")
    assert warm_copy(folder, cache_folder(work, env), work, stale_files(pristine, work)) >= 1
    assert _force(work, env) == (expected, 0, 1)


def test_a_mutant_no_compiled_code_reaches_loads_the_warm_cache(warm, tmp_path):
    pristine, work, folder = warm
    _mutate(pristine, work, "runtime/plain.py", "return 3", "return 4")
    env = _environment(work, tmp_path / "copy")
    assert cache_folder(work, env).name != folder.name  # runtime/compiled.py's key changed
    assert warm_copy(folder, cache_folder(work, env), work, stale_files(pristine, work)) == 0
    assert _force(work, env) == (10.0, 1, 0)


def _names(code: types.CodeType) -> set[str]:
    found = set(code.co_names)
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            found |= _names(const)
    return found


def _imported(graph: dict[str, set[str]], module: str) -> set[str]:
    """The module and every module it imports, directly or through others."""
    reached, stack = {module}, [module]
    while stack:
        for target in graph[stack.pop()] - reached:
            reached.add(target)
            stack.append(target)
    return reached


def test_compiled_functions_name_only_what_their_module_imports():
    """Every compiled function of the engine, as loaded: the modules, compiled functions and
    values (floats, tuples, arrays, bound under the same name elsewhere) its code names come
    from modules its own module imports, so the pruning by the import graph is complete."""
    graph = import_graph(ROOT)
    project = set(modules(ROOT))
    loaded = {m: importlib.import_module(m) for m in sorted(project) if m != "runtime.__main__"}
    checked = 0
    for home, module in loaded.items():
        for function in vars(module).values():
            if not isinstance(function, numba.core.registry.CPUDispatcher):
                continue
            if function.py_func.__module__ != home:
                continue
            allowed = _imported(graph, home)
            checked += 1
            for name in _names(function.py_func.__code__):
                value = function.py_func.__globals__.get(name)
                if isinstance(value, types.ModuleType) and value.__name__ in project:
                    sources = {value.__name__}
                elif isinstance(value, numba.core.registry.CPUDispatcher):
                    sources = {value.py_func.__module__}
                elif isinstance(value, float | tuple) or hasattr(value, "dtype"):
                    sources = {m for m, mod in loaded.items() if getattr(mod, name, None) is value}
                else:
                    continue
                assert sources & allowed, f"{home}.{function.__name__} names {name} from {sources}"
    assert checked > 100  # the engine's compiled functions were all found
