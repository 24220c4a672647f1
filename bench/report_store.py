"""The report's measurements of each scene kept as JSON (docs/report/<scene>.json).

Why: a run of the report can then measure some scenes only (bench.report --scenes) and still
write the whole pages, the other scenes as they were last measured; the comparisons are read
off the stored points again (bench.compare), so only measurements are stored.
"""

from __future__ import annotations

import json
from dataclasses import asdict
from pathlib import Path
from typing import Any

from bench.compare import Point, compare
from bench.report_pages import SceneResult


def save(result: SceneResult, path: Path) -> None:
    """Write one scene's runs (and when they were measured), replacing the file whole."""
    data = {
        "scene": result.spec.name,
        "measured": result.measured,
        "ours": [asdict(p) for p in result.ours],
        "theirs": {peer: [asdict(p) for p in points] for peer, points in result.theirs.items()},
    }
    partial = path.with_name(path.name + ".partial")
    partial.write_text(json.dumps(data, indent=1) + "\n")
    partial.replace(path)


def load(spec: Any, path: Path) -> SceneResult:
    """The scene's stored runs, compared again on its reference's primary error."""
    data = json.loads(path.read_text())
    if data.get("scene") != spec.name:
        raise ValueError(f"{path}: holds scene {data.get('scene')!r}, not {spec.name!r}")
    ours = [Point(**p) for p in data["ours"]]
    theirs = {peer: [Point(**p) for p in points] for peer, points in data["theirs"].items()}
    metric = spec.reference.primary
    comparisons = {peer: compare(ours, points, metric) for peer, points in theirs.items()}
    return SceneResult(spec, ours, theirs, comparisons, data["measured"])
