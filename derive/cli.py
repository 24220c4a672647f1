"""`regenerate-equations`: derive every case, write generated/ and docs/derivations.tex (+ PDF).

The generated modules: the contact cases (the normal row), <case>_friction (the tangential row of
a case), the joints and the applied forces (springs, mutual gravity, body damping). A subset
(`--cases`) writes those modules and the module lists only: the document covers every module, so
only a full run writes (or checks) it. This module imports nothing
beyond the standard library until the derive extra (SymPy, Jinja2, mpmath, ruff) is installed.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

GENERATED_MARK = "DO NOT EDIT"
ROOT = Path(__file__).resolve().parent.parent
CASE_NAMES = ("vertex_edge", "vertex_circle", "circle_edge", "circle_circle")
FRICTION_NAMES = tuple(f"{case}_friction" for case in CASE_NAMES)
JOINT_NAMES = ("pin_joint", "distance_joint")
APPLIED_NAMES = ("spring", "mutual_gravity", "body_damping")
MODULE_NAMES = CASE_NAMES + FRICTION_NAMES + JOINT_NAMES + APPLIED_NAMES
EXTRA = ("sympy", "jinja2", "mpmath", "ruff")


def _require_derive_extra() -> None:
    for module in EXTRA:
        try:
            __import__(module)
        except ImportError:
            raise SystemExit(
                f"regenerate-equations needs {module}, which is not installed: "
                "pip install 'curved-edge-physics[derive]'"
            ) from None


def _parse_cases(text: str | None) -> list[str]:
    if not text:
        return list(MODULE_NAMES)
    names = [n.strip() for n in text.split(",") if n.strip()]
    if not names:
        raise SystemExit(
            f"regenerate-equations: --cases names no case; valid cases: {', '.join(MODULE_NAMES)}"
        )
    unknown = [n for n in names if n not in MODULE_NAMES]
    if unknown:
        raise SystemExit(
            f"regenerate-equations: unknown case(s) {', '.join(unknown)}; "
            f"valid cases: {', '.join(MODULE_NAMES)}"
        )
    return names


def _whole(names: list[str]) -> bool:
    return set(names) == set(MODULE_NAMES)


def _planned_files(args, names: list[str]) -> dict[Path, str]:
    from derive.generate import generate, render_compiled_init, render_init

    results = generate(names)
    code_dir, docs_dir = Path(args.code_dir), Path(args.docs_dir)
    files = {code_dir / f"{name}.py": r.source for name, r in results.items()}
    present = {p.stem for p in code_dir.glob("*.py") if p.stem in MODULE_NAMES}
    cases_listed = sorted(set(names) | (set() if _whole(names) else present))
    files.update(
        {
            code_dir / "compiled" / f"{n}.py": r.compiled_source
            for n, r in results.items()
            if r.compiled_source is not None
        }
    )
    files[code_dir / "__init__.py"] = render_init(cases_listed)
    files[code_dir / "compiled" / "__init__.py"] = render_compiled_init(cases_listed)
    if _whole(names):
        from derive.document import render

        files[docs_dir / "derivations.tex"] = render(results)
    failed = [p.statement for r in results.values() for p in r.proofs if not p.holds]
    if failed:
        raise SystemExit("regenerate-equations: proofs fail:\n  " + "\n  ".join(failed))
    return files


def _check(files: dict[Path, str]) -> int:
    stale = [p for p, text in files.items() if not p.exists() or p.read_text() != text]
    if stale:
        print("stale (run regenerate-equations):", file=sys.stderr)
        for p in stale:
            print(f"  {p}", file=sys.stderr)
        return 1
    print(f"up to date: {len(files)} files")
    return 0


def _write(files: dict[Path, str], force: bool) -> None:
    for path in files:
        if path.exists() and GENERATED_MARK not in path.read_text()[:400] and not force:
            raise SystemExit(
                f"regenerate-equations: {path} exists and was not written by this tool "
                "(no 'DO NOT EDIT' header); refusing to overwrite it without --force"
            )
    for path, text in files.items():
        path.parent.mkdir(parents=True, exist_ok=True)
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
            print(f"wrote {path}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="regenerate-equations", description=__doc__.splitlines()[0]
    )
    parser.add_argument("--check", action="store_true", help="exit 1 if any output is stale")
    parser.add_argument(
        "--cases",
        help="comma-separated modules (default: all; a subset leaves the document as it is): "
        + ", ".join(MODULE_NAMES),
    )
    parser.add_argument("--code-dir", default=str(ROOT / "generated"), help="kernel output folder")
    parser.add_argument("--docs-dir", default=str(ROOT / "docs"), help="document output folder")
    parser.add_argument("--no-pdf", action="store_true", help="write the .tex but skip pdflatex")
    parser.add_argument(
        "--force", action="store_true", help="overwrite files this tool did not write"
    )
    args = parser.parse_args(argv)
    names = _parse_cases(args.cases)
    _require_derive_extra()
    start = time.perf_counter()
    files = _planned_files(args, names)
    if args.check:
        return _check(files)
    _write(files, args.force)
    print(f"derived and generated in {time.perf_counter() - start:.1f} s")
    if not _whole(names):
        print("derivations.tex left as it is: it covers every case (run without --cases)")
    elif not args.no_pdf:
        from derive.document import build_pdf

        pdf = build_pdf(Path(args.docs_dir) / "derivations.tex")
        print(
            f"wrote {pdf}" if pdf else "pdflatex not found: PDF skipped (`make docs` installs it)"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
