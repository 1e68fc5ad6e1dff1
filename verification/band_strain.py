#!/usr/bin/python3
"""Do the level sets of a membrane's band carry the membrane's strain?

`band_strain.py RUN_DIR STEP [--eps EPS]` reads RUN_DIR/fields/fields_<STEP>.h5 of a 3D
capsule run (phi_capsule and the six capsule_Gs components on the uniform grid of
RUN_DIR/case.toml) and, along 72 rays in the shear plane z = z_c from the centroid, samples
the area ratio J = J(P Gs P) across the band (offsets s in [-3 eps, 3 eps] along the normal
of phi at the phi = 1/2 crossing, P of that normal). It prints, over the rays,
  centre_rms     rms of J_c - 1, J_c at the crossing (the strain the membrane carries),
  spread_rms     rms of the band-weighted (sech^2(s/eps)) rms of J - J_c along each ray,
  mean_offset    mean of the band-weighted mean of J minus J_c (what the force averages).
In a thin membrane every level set of the band has the surface's strain (spread 0).
docs/verification.md, "Where the rest comes from", uses it on the capsule_shear runs.
"""
import argparse
import tomllib
from pathlib import Path

import h5py
import numpy as np
from scipy.ndimage import map_coordinates

COMPONENTS = ("xx", "xy", "xz", "yy", "yz", "zz")


def band_strain(phi, gs, origin, h, eps, rays=72):
    """phi: (nz, ny, nx); gs: dict of the six Gs components, same shape; origin: the grid's
    lower corner (x, y, z); h: the cell size. Returns the dict of the three measures."""
    n = phi.shape
    axes = [origin[d] + (np.arange(n[2 - d]) + 0.5) * h for d in range(3)]
    z, y, x = np.meshgrid(axes[2], axes[1], axes[0], indexing="ij")
    vol = phi.sum()
    c = np.array([(phi * x).sum(), (phi * y).sum(), (phi * z).sum()]) / vol

    def sample(f, pts):
        idx = (pts - np.asarray(origin)) / h - 0.5
        return map_coordinates(f, [idx[:, 2], idx[:, 1], idx[:, 0]], order=1, mode="nearest")

    def comp(a, b):
        return gs["".join(sorted(a + b, key="xyz".index))]

    s = np.linspace(-3 * eps, 3 * eps, 61)
    w = 1 / np.cosh(s / eps) ** 2
    w /= w.sum()
    rr = np.linspace(0.05, 0.5 * min(n) * h, 600)
    centre, spread, offset = [], [], []
    for th in np.linspace(0, 2 * np.pi, rays, endpoint=False):
        d = np.array([np.cos(th), np.sin(th), 0.0])
        pp = sample(phi, c[None, :] + rr[:, None] * d[None, :])
        i = np.where((pp[:-1] >= 0.5) & (pp[1:] < 0.5))[0][-1]
        r0 = rr[i] + (pp[i] - 0.5) / (pp[i] - pp[i + 1]) * (rr[i + 1] - rr[i])
        x0 = c + r0 * d
        e = 0.25 * h
        grad = np.array([(sample(phi, (x0 + e * u)[None])[0] - sample(phi, (x0 - e * u)[None])[0])
                         for u in np.eye(3)])
        nrm = -grad / np.linalg.norm(grad)
        pts = x0[None, :] + s[:, None] * nrm[None, :]
        p = np.eye(3) - np.outer(nrm, nrm)
        m = np.empty((len(s), 3, 3))
        for a, ca in enumerate("xyz"):
            for b, cb in enumerate("xyz"):
                m[:, a, b] = sample(comp(ca, cb), pts)
        bs = p @ m @ p
        tr = np.trace(bs, axis1=1, axis2=2)
        tr2 = np.einsum("kij,kji->k", bs, bs)
        j = np.sqrt(np.maximum(0.5 * (tr ** 2 - tr2), 0.0))
        jc = j[len(s) // 2]
        centre.append(jc - 1)
        spread.append(np.sqrt(np.sum(w * (j - jc) ** 2)))
        offset.append(np.sum(w * j) - jc)
    rms = lambda v: float(np.sqrt(np.mean(np.square(v))))  # noqa: E731
    return {"centre_rms": rms(centre), "spread_rms": rms(spread),
            "mean_offset": float(np.mean(offset))}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", type=Path)
    ap.add_argument("step", type=int)
    ap.add_argument("--eps", type=float, help="eps of phi's profile [m] (default: from case)")
    a = ap.parse_args()
    case = tomllib.loads((a.run / "case.toml").read_text())
    cells, length, origin = (case["grid"][k] for k in ("cells", "length", "origin"))
    h = length[0] / cells[0]
    eps = a.eps or case["body"][0].get("smoothing_width", 1.0) * h
    f = h5py.File(a.run / "fields" / f"fields_{a.step:08d}.h5", "r")
    shape = (cells[2], cells[1], cells[0])
    phi = f["phi_capsule"][...].reshape(shape)
    gs = {k: f["capsule_Gs_" + k][...].reshape(shape) for k in COMPONENTS}
    r = band_strain(phi, gs, origin, h, eps)
    print(" ".join(f"{k} {v:+.4f}" for k, v in r.items()))


if __name__ == "__main__":
    main()
