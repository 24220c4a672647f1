"""Which compiled code a mutant of `make mutate` can change, and a warm numba cache without it.

Why: runtime/compiled.py names its cache folder after a hash of every source file of runtime/
and generated/, so each mutant of those packages would start from an empty cache and recompile
the whole engine (~1.5 min of CPU each), though most of it cannot depend on the mutated file.
What numba compiles into a function is read at compile time and frozen: the function's own
file, the compiled functions it calls (inlined from any file), and the globals and module
attributes it names (a tolerance of runtime/settings.py). numba's own cache checks only the
stamp of the function's own file, so a cache entry whose code came partly from the mutated
file would be loaded, stale. Every file that can reach a compiled function's code is imported,
directly or through others, by that function's module (the static import statements, anywhere
in the file): so the entries to drop are those of the mutated files and of every module that
imports one of them, transitively. The rest is loaded from the cache the unmutated baseline run
built. tests/bench/test_mutate_cache.py checks the import graph against what the loaded
compiled functions actually name, and that a mutated callee in another file is recompiled.

Compiled functions that take other compiled functions as arguments are keyed by those
arguments' types (their dispatchers), so they cannot load code compiled around other ones. The
test suite's own compiled functions (tests/ imports the engine) are followed the same way; a
test module is also known by its bare name (pytest and tests/conftest.py put its folder on
sys.path).
"""

from __future__ import annotations

import ast
import shutil
import subprocess
import sys
from pathlib import Path

from numba.core.caching import _CacheLocator

PACKAGES = ("runtime", "generated")  # what runtime/compiled.py hashes into its cache key
TESTS = "tests"


def modules(root: Path) -> dict[str, Path]:
    """Module name -> file, for the packages compiled code lives in."""
    found = {}
    for package in PACKAGES:
        for path in sorted((root / package).rglob("*.py")):
            parts = path.relative_to(root).with_suffix("").parts
            found[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return found


def _named(name: str, path: Path) -> set[str]:
    """Modules (and `module.name`s) the file's import statements name, anywhere in it."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    named: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            named.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*anchor, base] if base else anchor)
            named.add(base)
            named.update(f"{base}.{alias.name}" for alias in node.names)
    return named


def _test_modules(root: Path) -> dict[str, Path]:
    """The test suite's modules, by dotted path from the root."""
    return {
        ".".join(p.relative_to(root).with_suffix("").parts): p
        for p in sorted((root / TESTS).rglob("*.py"))
    }


def import_graph(root: Path) -> dict[str, set[str]]:
    """Module -> the repository's modules it imports (a package's import runs its __init__),
    for the compiled packages and the test suite."""
    known = modules(root) | _test_modules(root)
    aliases: dict[str, set[str]] = {name: {name} for name in known}
    for name in _test_modules(root):
        aliases.setdefault(name.rpartition(".")[2], set()).add(name)
    graph = {}
    for name, path in known.items():
        edges = set()
        for target in _named(name, path):
            parts = target.split(".")
            for k in range(1, len(parts) + 1):
                edges |= aliases.get(".".join(parts[:k]), set())
        graph[name] = edges - {name}
    return graph


def importers(graph: dict[str, set[str]], changed: set[str]) -> set[str]:
    """`changed` and every module that imports one of them, directly or through others."""
    reverse: dict[str, set[str]] = {m: set() for m in graph}
    for module, targets in graph.items():
        for target in targets:
            reverse[target].add(module)
    reached, stack = set(changed), list(changed)
    while stack:
        for module in reverse.get(stack.pop(), set()) - reached:
            reached.add(module)
            stack.append(module)
    return reached


def changed_files(pristine: Path, work: Path) -> set[str]:
    """Files of the compiled packages (relative paths) that differ between the two trees."""
    names = {str(p.relative_to(pristine)) for p in modules(pristine).values()}
    names |= {str(p.relative_to(work)) for p in modules(work).values()}

    def content(tree: Path, name: str) -> bytes | None:
        path = tree / name
        return path.read_bytes() if path.is_file() else None

    return {n for n in names if content(pristine, n) != content(work, n)}


def stale_files(pristine: Path, work: Path) -> set[str]:
    """Files of `work` whose compiled code may differ from `pristine`'s (relative paths)."""
    known = modules(work) | _test_modules(work)
    by_path = {str(p.relative_to(work)): m for m, p in known.items()}
    changed = changed_files(pristine, work)
    stale = importers(import_graph(work), {by_path[f] for f in changed if f in by_path})
    return {str(known[m].relative_to(work)) for m in stale} | changed


def entries(cache: Path, work: Path, name: str) -> list[Path]:
    """The cache files numba keeps for the compiled functions of `work/name`: an index (.nbi)
    and data (.nbc) per function, in a folder per source folder, named after the module."""
    source = work / name
    folder = cache / _CacheLocator.get_suitable_cache_subpath(str(source))
    return sorted(folder.glob(f"{source.stem}.*.nb[ic]"))


def cache_folder(work: Path, env: dict) -> Path:
    """The numba cache folder runtime/compiled.py picks in `work` with `env` (it creates it)."""
    code = "from runtime.compiled import CACHE_FOLDER; print(CACHE_FOLDER)"
    done = subprocess.run(
        [sys.executable, "-c", code], cwd=work, env=env, capture_output=True, text=True, timeout=300
    )
    if done.returncode != 0:
        raise RuntimeError(f"runtime.compiled does not load: {done.stderr.strip()[-300:]}")
    return Path(done.stdout.strip().splitlines()[-1])


def warm_copy(warm: Path, target: Path, work: Path, stale: set[str]) -> int:
    """Copy the warm cache folder to `target` without the entries of the `stale` files (the
    warm one was built in `work` from the unmutated sources, so numba's per-file stamps match);
    returns how many stale files had compiled entries."""
    shutil.copytree(warm, target, dirs_exist_ok=True)
    dropped = 0
    for name in sorted(stale):
        found = entries(target, work, name)
        for path in found:
            path.unlink()
        dropped += bool(found)
    return dropped
