"""VOF advection with prescribed velocity (build/bin/efsi_vof_study): Zalesak's slotted
disc (one revolution), the single vortex (T = 8) and the 3D deformation test (T = 3) on
several grids. Shape error E = sum |phi(T) - phi(0)| dV, volume error, min/max of phi
(before clipping), observed orders, and a picture of phi = 0.5 at T against t = 0."""
import json

import numpy as np

from _bounds import Bound  # noqa: E402

DESCRIPTION = "VOF advection (MTHINC / THINC): Zalesak, single vortex, 3D deformation"

# Acceptance bounds (verification/studies/_bounds.py): run.py fails the study, naming the
# metric, when one breaks.
BOUNDS = [
    Bound(r"volume_error_max", "<=", 1e-12, "the VOF keeps the volume to round-off"),
    Bound(r"phi_min", ">=", -1e-12, "0 <= phi"),
    Bound(r"phi_max", "<=", 1.0 + 1e-12, "phi <= 1"),
    Bound(r"clipped_volume_max", "<=", 1e-12, "no volume is clipped away"),
    Bound(r"single_vortex_order", ">=", 1.5, "smooth shapes converge at second order"),
    Bound(r"zalesak_order", ">=", 0.9, "a slotted disc (corners) converges at first order"),
    Bound(r"deformation3d_order", ">=", 1.5, "3D deformation at second order", tiers=("full",)),
]

# (test, grids) per tier; the 3D runs dominate the cost (MTHINC ~ n^4).
TIERS = {
    "ci": [("zalesak", [32, 64]), ("single_vortex", [32, 64])],
    "quick": [("zalesak", [32, 64, 128]), ("single_vortex", [32, 64, 128]),
              ("deformation3d", [32, 64])],
    "full": [("zalesak", [32, 64, 128]), ("single_vortex", [32, 64, 128]),
             ("deformation3d", [32, 64, 128])],
}
# The 1D-THINC baseline is run on the 2D tests only (same grids).
BASELINE_TESTS = ("zalesak", "single_vortex")


def _binary(ctx):
    return ctx.efsi.parent / "efsi_vof_study"


def _run(ctx, test, n, scheme, h5=None):
    ranks = 2 if (test == "deformation3d" and n >= 64) else 1
    cmd = [_binary(ctx), test, "--n", str(n), "--scheme", scheme]
    if h5:
        cmd += ["--h5", h5]
    res = ctx.run(cmd, ranks=ranks)
    line = [ln for ln in res.stdout.splitlines() if ln.startswith("{")][-1]
    return json.loads(line)


def _orders(rows):
    out = []
    for a, b in zip(rows, rows[1:]):
        out.append(float(np.log(a["shape_error"] / b["shape_error"]) / np.log(b["n"] / a["n"])))
    return out


def _picture(ctx, files):
    import h5py
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(files), figsize=(4.2 * len(files), 4.2))
    axes = np.atleast_1d(axes)
    for ax, (test, n, path) in zip(axes, files):
        with h5py.File(path, "r") as f:
            p0, pT = np.array(f["phi0"]), np.array(f["phiT"])  # [nz][ny][nx]
        if p0.shape[0] > 1:  # 3D: the plane z = 0.35 through the sphere's centre
            kz = int(0.35 * p0.shape[0])
            p0, pT = p0[kz], pT[kz]
        else:
            p0, pT = p0[0], pT[0]
        x = (np.arange(p0.shape[1]) + 0.5) / p0.shape[1]
        y = (np.arange(p0.shape[0]) + 0.5) / p0.shape[0]
        ax.contour(x, y, p0, levels=[0.5], colors="k", linewidths=1.0)
        ax.contour(x, y, pT, levels=[0.5], colors="r", linewidths=1.0)
        ax.set_aspect("equal")
        ax.set_title(f"{test} n={n}: t=0 (black), T (red)", fontsize=9)
        if test == "deformation3d":
            ax.set_xlim(0.1, 0.6)
            ax.set_ylim(0.1, 0.6)
        elif test == "single_vortex":
            ax.set_xlim(0.25, 0.75)
            ax.set_ylim(0.5, 1.0)
        else:
            ax.set_xlim(0.3, 0.7)
            ax.set_ylim(0.55, 0.95)
    fig.tight_layout()
    png = ctx.outdir / "vof_final_shapes.png"
    fig.savefig(png, dpi=120)
    plt.close(fig)
    return png


def run(ctx):
    tables, metrics, files = {}, {}, []
    for test, grids in TIERS[ctx.tier]:
        schemes = ["mthinc"] + (["thinc"] if test in BASELINE_TESTS else [])
        for scheme in schemes:
            rows = []
            for n in grids:
                h5 = None
                if scheme == "mthinc" and n == grids[-1]:
                    h5 = ctx.outdir / f"{test}_{n}.h5"
                    files.append((test, n, h5))
                rows.append(_run(ctx, test, n, scheme, h5))
            orders = _orders(rows)
            for r, o in zip(rows[1:], orders):
                r["order"] = o
            tables[f"{test}_{scheme}"] = rows
            tag = test if scheme == "mthinc" else f"{test}_thinc"
            for r in rows:
                metrics[f"{tag}_error_{r['n']}"] = r["shape_error"]
            if orders:
                metrics[f"{tag}_order"] = orders[-1]
    allrows = [r for rows in tables.values() for r in rows]
    metrics["volume_error_max"] = max(max(r["volume_error"], r["volume_drift_max"])
                                      for r in allrows)
    metrics["phi_min"] = min(r["phi_min"] for r in allrows)
    metrics["phi_max"] = max(r["phi_max"] for r in allrows)
    metrics["clipped_volume_max"] = max(r["clipped_volume"] for r in allrows)
    png = _picture(ctx, files)
    notes = ("Directionally split THINC fluxes with the Weymouth-Yue divergence correction "
             "(exactly conservative for the discretely solenoidal velocity built from a "
             "vector potential); CFL 0.3; MTHINC beta 2 (planar, Youngs normal), THINC beta "
             "3.5. phi_min/phi_max are before the round-off clip. E = sum |phi(T)-phi(0)| dV "
             "(dV = cell area in 2D). See docs/method.md, 'VOF advection'.")
    return {"metrics": metrics, "tables": tables, "figures": [str(png)], "notes": notes}
