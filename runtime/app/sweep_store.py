"""The output folder of a sweep: written chunk by chunk, resumable, never half a file.

    DIR/sweep.json              what was swept (scene file hash, --vary, options, chunk size)
    DIR/runs/run-000123.npz     run 123's trajectory: t, poses, velocities, energy, its values
    DIR/chunks/chunk-00004.parquet   the table rows of chunk 4 (written last: the chunk is done)
    DIR/table.parquet, table.csv     one row per run, when every chunk is done

Why this shape: a sweep can run for hours on a cluster, so each chunk's results are kept as
soon as they arrive, each file written under a temporary name and renamed into place; a chunk
whose rows file exists is complete, so a sweep run again with the same command resumes where it
stopped. A folder holding another sweep, a finished one, or files that are not a sweep's is
refused without ``--force`` (which removes the sweep files of the earlier sweep, nothing else);
two sweeps into one folder at once are refused by the folder's lock (runtime.app.output_dir).
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
from pathlib import Path

import numpy as np

from runtime.app.output_dir import FolderLock, OutputError

MANIFEST, TABLE, CSV = "sweep.json", "table.parquet", "table.csv"
STATE = ("x", "y", "angle", "vx", "vy", "angular_velocity")  # final-state columns per body


def scene_hash(path: Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


class SweepFolder:
    """The folder ``path`` of the sweep described by ``spec`` (a JSON-able dict; its "chunk"
    may be None: then a resumed sweep keeps the chunk size it was started with)."""

    def __init__(self, path: Path, spec: dict, *, force: bool) -> None:
        self.path, self.spec, self.force = Path(path), dict(spec), force
        self.runs_dir, self.chunks_dir = self.path / "runs", self.path / "chunks"
        self.lock = FolderLock(self.path, "sweep")
        self.resumed: set[int] = set()

    # -- before the sweep -------------------------------------------------------------------

    def open(self, chunk: int) -> set[int]:
        """Check and lock the folder, start or resume the sweep; returns the chunks already
        done. ``chunk``: the chunk size of a new sweep (when the spec does not fix one)."""
        out = self.path
        if out.exists() and not out.is_dir():
            raise OutputError(f"output {str(out)!r} exists and is not a directory")
        try:
            out.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise OutputError(f"cannot create the output {str(out)!r}: {exc.strerror}") from None
        self.lock.acquire()
        try:
            done = self._start_or_resume(chunk)
        except BaseException:
            self.lock.release()
            raise
        self.resumed = done
        return done

    def _start_or_resume(self, chunk: int) -> set[int]:
        out, old = self.path, self._manifest()
        resuming = old is not None and not self.force
        if self.spec.get("chunk") is None:
            kept = old.get("chunk") if resuming else None
            self.spec["chunk"] = kept if isinstance(kept, int) and kept >= 1 else chunk
        self.spec["chunks"] = -(-self.spec["runs"] // self.spec["chunk"])
        if resuming:
            difference = _difference(old, self.spec)
            if difference:
                raise OutputError(
                    f"output {str(out)!r} holds another sweep ({difference}); use --force to "
                    "replace it, or choose another --out"
                )
            done = self.done_chunks()
            if (out / TABLE).exists() and len(done) == old.get("chunks"):
                raise OutputError(
                    f"output {str(out)!r} holds this sweep, finished; use --force to run it again"
                )
            self._remove_temporary()
            return done
        if old is None and not self.force and any(out.iterdir()):
            raise OutputError(
                f"output directory {str(out)!r} is not empty and holds no sweep; use --force to "
                "write into it anyway"
            )
        self._remove_sweep()
        try:
            self.runs_dir.mkdir(exist_ok=True)
            self.chunks_dir.mkdir(exist_ok=True)
            self._write(out / MANIFEST, json.dumps(self.spec, indent=1).encode())
        except OSError as exc:
            raise OutputError(f"cannot write into {str(out)!r}: {exc.strerror}") from None
        return set()

    def _manifest(self) -> dict | None:
        try:
            found = json.loads((self.path / MANIFEST).read_text())
        except FileNotFoundError:
            return None
        except (OSError, ValueError) as exc:
            raise OutputError(
                f"output {str(self.path)!r}: its {MANIFEST} cannot be read ({exc}); use --force "
                "to start the sweep over"
            ) from None
        return found if isinstance(found, dict) else {}

    def done_chunks(self) -> set[int]:
        done = set()
        for path in self.chunks_dir.glob("chunk-*.parquet"):
            with contextlib.suppress(ValueError):
                done.add(int(path.stem.split("-")[1]))
        return done

    def _remove_sweep(self) -> None:
        """The files of an earlier sweep here (only those)."""
        for name in (MANIFEST, TABLE, CSV):
            (self.path / name).unlink(missing_ok=True)
        for folder, pattern in ((self.runs_dir, "run-*.npz"), (self.chunks_dir, "chunk-*.parquet")):
            for path in folder.glob(pattern):
                path.unlink()
        self._remove_temporary()

    def _remove_temporary(self) -> None:
        """Half-written files of a sweep that was killed (we hold the lock)."""
        for folder in (self.path, self.runs_dir, self.chunks_dir):
            for path in folder.glob(".*.tmp-*"):
                path.unlink(missing_ok=True)

    # -- during and after -------------------------------------------------------------------

    def write_chunk(self, index: int, start: int, grid, ensemble) -> None:
        """Chunk ``index`` (runs ``start``...) of ``grid``: each run's trajectory, then the
        chunk's rows (which mark it done)."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        for c in range(ensemble.copies):
            k = int(ensemble.records[c])
            values = {key: grid.values[start + c, j] for j, key in enumerate(grid.keys)}
            arrays = {
                "t": ensemble.t[:k],
                "poses": ensemble.poses[c, :k],
                "velocities": ensemble.velocities[c, :k],
                "energy": ensemble.energy[c, :k],
                "body_names": np.array(ensemble.body_names),
                "varied_keys": np.array(list(values)),
                "varied_values": np.array(list(values.values()), dtype=float),
                "error": np.array(str(ensemble.failed[c])),
            }
            self._write(self.runs_dir / f"run-{start + c:06d}.npz", _npz(arrays))
        table = pa.table(rows(index, start, grid, ensemble))
        sink = pa.BufferOutputStream()
        pq.write_table(table, sink)
        self._write(self.chunks_dir / f"chunk-{index:05d}.parquet", sink.getvalue().to_pybytes())

    def finish(self) -> int:
        """The table of every chunk (sorted by run) as Parquet and CSV; returns its rows."""
        import pyarrow as pa
        import pyarrow.csv as csv
        import pyarrow.parquet as pq

        parts = [pq.read_table(p) for p in sorted(self.chunks_dir.glob("chunk-*.parquet"))]
        table = pa.concat_tables(parts).sort_by("run")
        for name, writer in ((TABLE, pq.write_table), (CSV, csv.write_csv)):
            sink = pa.BufferOutputStream()
            writer(table, sink)
            self._write(self.path / name, sink.getvalue().to_pybytes())
        return table.num_rows

    def close(self) -> None:
        self.lock.release()

    @staticmethod
    def _write(path: Path, data: bytes) -> None:
        """``data`` into ``path`` under a temporary name, then renamed: never half a file."""
        temporary = path.with_name(f".{path.name}.tmp-{os.getpid()}")
        try:
            with open(temporary, "wb") as f:
                f.write(data)
            os.replace(temporary, path)
        except BaseException:
            temporary.unlink(missing_ok=True)
            raise


def rows(index: int, start: int, grid, ensemble) -> dict[str, list]:
    """The table's columns for one chunk: run, chunk, the varied values, each moving body's
    last recorded state (centre of mass), t_end, max_penetration, energy_drift (last record
    less the first, J), wall_time (the chunk's time over its runs, s) and error."""
    n = ensemble.copies
    last = np.maximum(ensemble.records - 1, 0)
    has = ensemble.records > 0
    pick = np.arange(n)
    columns: dict[str, list] = {
        "run": list(range(start, start + n)),
        "chunk": [index] * n,
    }
    for j, key in enumerate(grid.keys):
        columns[key] = grid.values[start : start + n, j].tolist()
    moving = [i for i, fixed in enumerate(ensemble.fixed) if not fixed]
    for i in moving:
        state = np.concatenate(
            [ensemble.poses[pick, last, i], ensemble.velocities[pick, last, i]], axis=1
        )
        state[~has] = np.nan
        for column, name in enumerate(STATE):
            columns[f"{ensemble.body_names[i]}.{name}"] = state[:, column].tolist()
    columns["t_end"] = np.where(has, ensemble.t[last], np.nan).tolist()
    columns["max_penetration"] = ensemble.max_penetration.tolist()
    drift = ensemble.energy[pick, last] - ensemble.energy[:, 0]
    columns["energy_drift"] = np.where(has, drift, np.nan).tolist()
    columns["wall_time"] = [ensemble.wall_time / n] * n
    columns["error"] = [str(e) for e in ensemble.failed]
    return columns


def _npz(arrays: dict[str, np.ndarray]) -> bytes:
    import io

    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    return buffer.getvalue()


def _difference(old: dict, new: dict) -> str:
    """The first field where two sweep specs differ, in words ('' if none)."""
    for key in sorted(set(old) | set(new)):
        if key == "scene_file":
            continue
        if old.get(key) != new.get(key):
            return f"its {key} is {old.get(key)!r}, this one's {new.get(key)!r}"
    return ""
