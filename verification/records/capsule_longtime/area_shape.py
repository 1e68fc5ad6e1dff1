#!/usr/bin/python3
"""Is the capsule's area change that of its shape? (docs/method.md, "The area bound at Ca 0.05")

    /usr/bin/python3 verification/records/capsule_longtime/area_shape.py RUN_DIR [D_ref ...]

RUN_DIR is a capsule_shear run in the cases' box (8 x 8 x 8, origin -4) with field
snapshots. For each snapshot it fits the ellipsoid with the body's second moments (of phi and
of the body phi > 1/2), scaled to the body's volume, and prints its semi-axes, D in the shear
plane and the ellipsoid's area over the equal-volume sphere's, next to the run's own area
change (bodies.csv `area`, the integral of |grad phi|, what capsule_longtime bounds). Then,
for each D_ref (default 0.26, Ramanujan & Pozrikidis 1998 at Ca 0.05), the area change of
the ellipsoid with that D in the shear plane and the last snapshot's ratio of the vorticity
axis to the in-plane mean: the area a capsule with the published D would have gained, if its
shape is the same kind of ellipsoid.
"""
import csv
import sys
from pathlib import Path

import h5py
import numpy as np


def ellipsoid_area(a: float, b: float, c: float) -> float:
    """Surface area by quadrature of |r_theta x r_phi| (1e-6 relative on the unit sphere)."""
    th = np.linspace(0, np.pi, 801)
    ph = np.linspace(0, 2 * np.pi, 1601)
    T, P = np.meshgrid(th, ph, indexing="ij")
    st, ct = np.sin(T), np.cos(T)
    n = np.sqrt((b * c * st**2 * np.cos(P))**2 + (a * c * st**2 * np.sin(P))**2
                + (a * b * st * ct)**2)
    return float(np.trapz(np.trapz(n, ph, axis=1), th))


def moment_axes(w: np.ndarray, h: float):
    """Semi-axes (x-y plane long, x-y plane short, vorticity axis z) of the ellipsoid with
    the second moments of w, scaled to w's volume; and that volume."""
    n = w.shape[0]
    c = (np.arange(n) + 0.5) * h - 4.0
    Z, Y, X = np.meshgrid(c, c, c, indexing="ij")
    m = w.sum()
    x, y, z = (X - (w * X).sum() / m, Y - (w * Y).sum() / m, Z - (w * Z).sum() / m)
    V = m * h**3
    inplane = np.array([[(w * x * x).sum(), (w * x * y).sum()],
                        [(w * x * y).sum(), (w * y * y).sum()]]) * h**3
    lo, hi = np.linalg.eigvalsh(inplane)
    axes = np.sqrt(5 * np.array([hi, lo, (w * z * z).sum() * h**3]) / V)
    axes *= (3 * V / (4 * np.pi) / np.prod(axes))**(1 / 3)
    return axes, V


def main(argv):
    if not argv:
        print(__doc__)
        return 2
    run = Path(argv[0])
    refs = [float(a) for a in argv[1:]] or [0.26]
    with open(run / "bodies.csv") as f:
        rows = [r for r in csv.DictReader(f) if r["body"] == "capsule"]
    area0 = float(rows[0]["area"])
    times = np.array([float(r["time"]) for r in rows])
    gains = np.array([float(r["area"]) for r in rows]) / area0 - 1

    def area_at(t):
        """The run's area change in the bodies.csv row nearest t (rows every few steps)."""
        return float(gains[np.argmin(np.abs(times - t))])
    snaps = sorted((run / "fields").glob("fields_*.h5"))
    q = None
    print("| snapshot | measure | semi-axes L, B, W | D | ellipsoid area change | run's area change (grad phi) |")
    print("|---|---|---|---|---|---|")
    for fn in snaps:
        with h5py.File(fn, "r") as f:
            shape = f["faces_u"].shape
            phi = f["phi_capsule"][...].reshape(shape)
            t = float(f.attrs["time"]) if "time" in f.attrs else None
        h = 8.0 / shape[0]
        for name, w in (("phi", phi), ("phi > 1/2", (phi > 0.5).astype(float))):
            ax, V = moment_axes(w, h)
            r0 = (3 * V / (4 * np.pi))**(1 / 3)
            gain = ellipsoid_area(*ax) / (4 * np.pi * r0**2) - 1
            D = (ax[0] - ax[1]) / (ax[0] + ax[1])
            own = area_at(t) if t is not None else None
            print(f"| {fn.stem} | {name} | {ax[0]:.4f}, {ax[1]:.4f}, {ax[2]:.4f} | {D:.4f} | "
                  f"{gain:+.4f} | {'-' if own is None else f'{own:+.4f}'} |")
            if name == "phi":
                q = ax[2] / np.sqrt(ax[0] * ax[1])
    print(f"\nlast snapshot: W / sqrt(L B) = {q:.4f}; final area change (bodies.csv) "
          f"{float(rows[-1]['area']) / area0 - 1:+.4f}")
    for D in refs:
        r = (1 + D) / (1 - D)
        g = q**(-1 / 3)
        L, B, W = np.sqrt(r) * g, g / np.sqrt(r), q * g
        print(f"ellipsoid with D = {D:g} and that W / sqrt(L B), unit volume: area change "
              f"{ellipsoid_area(L, B, W) / (4 * np.pi) - 1:+.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
