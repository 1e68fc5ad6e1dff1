"""The overlap of bodies' volume fractions (docs/method.md, "Body overlap measure"), for the
blood studies: a smoothed body (a red cell) enters as its sharp equivalent, since its tanh
tail reaches into a sharp neighbour at any gap."""
import tomllib
from pathlib import Path

import h5py
import numpy as np


def smoothing_widths(run_dir) -> dict:
    """{body name: smoothing width in cells} of a run's smoothed bodies, from the case.toml
    efsi writes beside its output (the seeding expanded into [[body]] entries); sharp
    bodies are absent."""
    with open(Path(run_dir) / "case.toml", "rb") as f:
        case = tomllib.load(f)
    return {b["name"]: float(b.get("smoothing_width", 1.0)) for b in case.get("body", [])
            if b.get("interface") == "smoothed"}


def sharp_fraction(phi, width: float):
    """The volume fraction of a smoothed body's sharp equivalent (its surface phi = 1/2):
    each cell cut by the plane at the distance L = eps atanh(1 - 2 phi) (cells, positive
    outside) its tanh profile gives, normal to a grid axis: clip(1/2 - L, 0, 1)."""
    p = np.clip(phi, 1e-16, 1.0 - 1e-16)
    return np.clip(0.5 - width * np.arctanh(1.0 - 2.0 * p), 0.0, 1.0)


def worst_pair(path, widths=None):
    """(overlap, (body, body)) of the pair of bodies that overlap most in the snapshot at
    `path`: sum max(0, phi_i + phi_j - 1) / min(V_i, V_j), (0.0, None) if none does. With
    `widths` ({name: smoothing width in cells}) each smoothed body enters as its sharp
    equivalent (sharp_fraction); without, as its stored profile, whose tail reaches into
    a sharp neighbour at any gap (docs/method.md, "Body overlap measure")."""
    widths = widths or {}
    with h5py.File(path, "r") as f:
        names, phis = [], []
        for k in f.keys():
            if k.startswith("phi_"):
                names.append(k[len("phi_"):])
                w = widths.get(names[-1])
                phis.append(f[k][...] if w is None else sharp_fraction(f[k][...], w))
    worst, pair = 0.0, None
    vols = [p.sum() for p in phis]
    for a in range(len(phis)):
        for b in range(a + 1, len(phis)):
            small = min(vols[a], vols[b])
            if small > 0:
                o = float(np.maximum(phis[a] + phis[b] - 1, 0).sum() / small)
                if o > worst:
                    worst, pair = o, (names[a], names[b])
    return worst, pair


def overlap(path, widths=None) -> float:
    """The largest overlap of two bodies in the snapshot at `path` (worst_pair)."""
    return worst_pair(path, widths)[0]
