"""Shared helpers for the efsi flow studies: read snapshots and fit convergence orders.

Snapshot format (solver/io/field_output.hpp): ``fields/fields_<step>.h5`` with the staggered
components ``faces_u``, ``faces_v`` (``faces_w``) as [nz][ny][nx] arrays whose index i is the
LOW face of cell i, cell-centred ``pressure`` flattened x-fastest, attributes ``time`` and
``step``.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np


def last_snapshot(run_dir: Path) -> Path:
    """The snapshot with the highest step number in ``run_dir/fields``."""
    files = sorted((Path(run_dir) / "fields").glob("fields_*.h5"))
    if not files:
        raise FileNotFoundError(f"no snapshots in {run_dir}/fields")
    return files[-1]


def read_snapshot(path: Path) -> dict:
    """Faces and pressure as numpy arrays ([nz][ny][nx]) plus time and step."""
    import h5py

    with h5py.File(path, "r") as f:
        out = {"time": float(f.attrs["time"]), "step": int(f.attrs["step"])}
        shape = f["faces_u"].shape
        for c in ("u", "v", "w"):
            if f"faces_{c}" in f:
                out[c] = f[f"faces_{c}"][...]
        out["p"] = f["pressure"][...].reshape(shape)
    return out


def read_summary(run_dir: Path) -> dict:
    return json.loads((Path(run_dir) / "summary.json").read_text())


def cell_centres(n: int, length: float, origin: float = 0.0) -> np.ndarray:
    h = length / n
    return origin + (np.arange(n) + 0.5) * h


def low_faces(n: int, length: float, origin: float = 0.0) -> np.ndarray:
    h = length / n
    return origin + np.arange(n) * h


def slope(h, e) -> float:
    """Least-squares slope of log(e) against log(h): the observed order over all grids."""
    # An exactly zero error (e.g. a sphere's distance-stencil normals) must not give log(0).
    h, e = np.log(np.asarray(h, float)), np.log(np.maximum(np.asarray(e, float), 1e-300))
    return float(np.polyfit(h, e, 1)[0])


def pairwise_orders(h, e) -> list[float]:
    h, e = np.asarray(h, float), np.asarray(e, float)
    return [float(np.log(e[i] / e[i + 1]) / np.log(h[i] / h[i + 1])) for i in range(len(h) - 1)]


def fmt_list(v) -> str:
    return "[" + ",".join(repr(x) for x in v) + "]"


# --- Cached capsule runs (capsule_shear, capsule_bending, stability) -----------------------

def capsule_box_sets(dim: int, cells_per_diameter: int) -> dict:
    """Grid of cases/capsule_shear(_2d): box 8 x 8 (x 8) = 4 d around the capsule (a = 1);
    a 2D run is one cell thick in z."""
    cells = 4 * cells_per_diameter
    h = 8.0 / cells
    return {"grid.cells": f"[{cells},{cells},{cells if dim == 3 else 1}]",
            "grid.length": f"[8.0,8.0,{8.0 if dim == 3 else h!r}]",
            "grid.origin": f"[-4.0,-4.0,{-4.0 if dim == 3 else -h / 2!r}]"}


# Committed records of long runs (verification/records/<study>/<run key>/: bodies.csv,
# diagnostics.csv, summary.json, case.toml and record.json with the commit and command
# that made it). A session's build/ does not outlive it, and the full tier's 3D runs take
# longer than one; with EFSI_VERIFY_RECORDS=1 a run missing from the build cache is taken
# from its record (listed in the study's notes) instead of being recomputed. With
# EFSI_VERIFY_RECORDS=only a run that has neither raises RunNotMade instead of running: a
# study that can report a run as not made (capsule_longtime, whose area-stiff runs take days
# here) catches it; any other stops with its name. Written by `verification/record.py`.
RECORDS = Path(__file__).resolve().parents[1] / "records"
RECORD_FILES = ("bodies.csv", "diagnostics.csv", "adhesion.csv", "summary.json", "case.toml",
                "record.json")
USED_RECORDS: list[str] = []


class RunNotMade(RuntimeError):
    """EFSI_VERIFY_RECORDS=only and the run is neither in the cache nor recorded."""

    def __init__(self, out: Path):
        super().__init__(f"run {Path(out).name} is neither in {Path(out).parent} nor recorded "
                         f"in {record_dir(out).parent} (EFSI_VERIFY_RECORDS=only: not run)")
        self.out = Path(out)


def records_mode() -> str:
    """EFSI_VERIFY_RECORDS: "" (compute what the cache lacks), "1" (take a missing run from
    its record first), "only" (records, never a new run)."""
    import os

    return os.environ.get("EFSI_VERIFY_RECORDS", "")


def record_dir(out: Path, record: str | None = None) -> Path:
    """build/verification/<study>/runs/<key> -> verification/records/<study>/<key> (or
    <record> when the study names its record otherwise)."""
    out = Path(out)
    return RECORDS / out.parent.parent.name / (record or out.name)


def run_status(out: Path) -> dict | None:
    """The run's summary.json (status, time, ...) or None when it has none."""
    summary = Path(out) / "summary.json"
    return json.loads(summary.read_text()) if summary.exists() else None


def run_finished(out: Path, t_end: float | None, allow_unstable: bool = False) -> bool:
    """True when the run in ``out`` completed (at ``t_end``, if given) or, with
    ``allow_unstable``, stopped UNSTABLE: either way rerunning it would not change it."""
    s = run_status(out)
    if s is None:
        return False
    if allow_unstable and s.get("status") == "unstable":
        return True
    return s.get("status") == "completed" and (t_end is None or abs(s["time"] - t_end) < 1e-9)


def completed(out: Path, t_end: float | None = None, allow_unstable: bool = False,
              record: str | None = None) -> bool:
    """True when ``out`` holds a finished run (run_finished); with EFSI_VERIFY_RECORDS=1 (or
    only) a finished committed record of it (folder ``record``, default the run's name) is
    copied in first."""
    import shutil

    if run_finished(out, t_end, allow_unstable):
        return True
    rec = record_dir(out, record)
    if records_mode() not in ("1", "only") or not run_finished(rec, t_end, allow_unstable):
        return False
    Path(out).mkdir(parents=True, exist_ok=True)
    for name in RECORD_FILES:
        if (rec / name).exists():
            shutil.copy2(rec / name, Path(out) / name)
    meta = json.loads((rec / "record.json").read_text())
    commit = meta.get("git_at_record", "?")[:10]
    name = Path(out).name if rec.name == Path(out).name else f"{Path(out).name} (record {rec.name})"
    USED_RECORDS.append(f"{name} (recorded at commit {commit}, {meta.get('date', '?')})")
    return True


def cached_run(ctx, case: Path, out: Path, sets: dict, t_end: float | None = None,
               ranks: int = 1, allow_unstable: bool = False, record: str | None = None) -> Path:
    """Run ``case`` into ``out`` unless a finished run is there; a run cut short resumes
    from its last checkpoint. With ``allow_unstable`` a run that stops UNSTABLE (exit 3,
    summary status "unstable") is a result, not an error: the caller reports where it
    stopped. ``record`` names the run's record folder when it is not the run's name.
    Raises RunNotMade under EFSI_VERIFY_RECORDS=only when there is nothing to take."""
    if completed(out, t_end, allow_unstable, record):
        note = getattr(ctx, "note_kept_run", None)
        if note is not None:
            note(case, out, sets, ranks)
        return out
    if records_mode() == "only":
        raise RunNotMade(out)
    extra = ["--restart", str(out / "checkpoint.h5")] if (out / "checkpoint.h5").exists() else []
    res = ctx.run_efsi(case, out, sets=sets, extra=extra, ranks=ranks, check=not allow_unstable)
    if allow_unstable and not run_finished(out, t_end, allow_unstable=True):
        raise RuntimeError(f"run {out} neither completed nor stopped UNSTABLE: "
                           f"{(res or {}).get('status', 'no summary.json')}")
    return out


def body_series(out: Path, body: str = "capsule", columns=("taylor_deformation",
                "inclination_over_pi", "volume")):
    """Time and the given bodies.csv columns of one body, sorted by time (a restarted run
    repeats the rows after its checkpoint)."""
    import csv

    with open(Path(out) / "bodies.csv") as f:
        rows = [r for r in csv.DictReader(f) if r["body"] == body]
    t = np.array([float(r["time"]) for r in rows])
    order = np.argsort(t, kind="stable")
    return (t[order], *(np.array([float(r[k]) for r in rows])[order] for k in columns))
