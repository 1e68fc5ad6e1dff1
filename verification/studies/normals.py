"""Normals and mean curvature from a smoothed volume fraction, against exact geometry
(sphere, ellipsoid, and the Evans-Fung biconcave disc through Lambda = L / |grad L|).

phi = (1 - tanh(Lambda / eps)) / 2 with eps = width * h, for a sphere (Lambda the signed
distance) and an ellipsoid (Lambda = a_min (sqrt(q) - 1), whose level sets are similar
ellipsoids with analytic normals and mean curvature). Errors are weighted by the smoothed
delta |grad phi|. Stencils: central, youngs (1,2,1), isotropic (1,4,1) and distance
(isotropic differences of the inverted profile psi = eps atanh(2 phi - 1)).
"""
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from _flowio import slope  # noqa: E402  (least-squares observed order)

from _bounds import Bound  # noqa: E402

DESCRIPTION = "normal and curvature error of smoothed-VOF geometry vs resolution (4 stencils)"

# Acceptance bounds (verification/studies/_bounds.py): run.py fails the study, naming the
# metric, when one breaks.
BOUNDS = [
    Bound(r"(normal|curvature)_order", ">=", 1.8,
          "normals and curvature of the distance stencil (the one in use) at second order"),
    Bound(r"(normal|curvature)_order_(sphere|ellipsoid)_distance_[23]d", ">=", 1.8,
          "normals and curvature of the distance stencil at second order on smooth shapes"),
]

TIERS = {
    "ci": {2: [32, 64, 128], 3: []},
    "quick": {2: [32, 64, 128, 256], 3: [16, 32, 64]},
    "full": {2: [16, 32, 64, 128, 256], 3: [16, 32, 64, 128]},
}
STENCILS = ["central", "youngs", "isotropic", "distance"]



def run(ctx):
    exe = ctx.efsi.parent / "efsi_geometry_study"
    metrics, rows, figures = {}, [], []
    for dim, grids in TIERS[ctx.tier].items():
        if not grids:
            continue
        fig, axes = plt.subplots(1, 2, figsize=(10, 4))
        for shape in ("sphere", "ellipsoid", "biconcave"):
            for st in STENCILS:
                en, ek = [], []
                for n in grids:
                    r = json.loads(ctx.run([exe, "--shape", shape, "--dim", dim, "--cells", n,
                                            "--stencil", st, "--width", 1.0]).stdout)
                    rows.append(r)
                    en.append(r["normal_error"])
                    ek.append(r["curvature_error"])
                # Orders from the finer half of the grids (the coarsest under-resolve the shape).
                h = [2.0 / n for n in grids]
                fine = slice(len(grids) // 2 - (1 if len(grids) % 2 == 0 else 0), None)
                pn, pk = slope(h[fine], en[fine]), slope(h[fine], ek[fine])
                tag = f"{shape}_{st}_{dim}d"
                metrics[f"normal_error_{tag}_{grids[-1]}"] = en[-1]
                metrics[f"curvature_error_{tag}_{grids[-1]}"] = ek[-1]
                metrics[f"normal_order_{tag}"] = pn
                metrics[f"curvature_order_{tag}"] = pk
                style = {"sphere": "--", "ellipsoid": "-", "biconcave": ":"}[shape]
                axes[0].loglog(h, en, "o" + style, label=f"{shape} {st} ({pn:.1f})")
                axes[1].loglog(h, ek, "o" + style, label=f"{shape} {st} ({pk:.1f})")
        for ax, what in zip(axes, ("normal", "mean curvature")):
            ax.set(xlabel="h (box 2)", ylabel=f"{what} error (delta-weighted)",
                   title=f"{what}, {dim}D, width 1 cell")
            ax.legend(fontsize=6)
        fig.tight_layout()
        png = ctx.outdir / f"normals_{dim}d.png"
        fig.savefig(png, dpi=110)
        figures.append(str(png))
    dim = 3 if TIERS[ctx.tier][3] else 2
    metrics["normal_order"] = metrics[f"normal_order_ellipsoid_distance_{dim}d"]
    metrics["curvature_order"] = metrics[f"curvature_order_ellipsoid_distance_{dim}d"]
    notes = ("With the smoothing width fixed in cells, the central and Youngs gradients of phi "
             "leave an O(1) direction error (their h^2 f'''/f' term is not parallel to n), so their "
             "normals do not converge; the isotropic (1,4,1) stencil removes that term and "
             "converges at first order; differencing the inverted profile psi = eps atanh(2 phi - 1), "
             "which is linear across the band, gives second-order normals and curvature. "
             "normal_order and curvature_order are those of the distance stencil on the ellipsoid.")
    return {"metrics": metrics, "tables": {"runs": rows}, "figures": figures, "notes": notes}
