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
