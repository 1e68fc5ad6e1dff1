"""FEniCSx reference: Taylor-Hood P2/P1 Stokes and steady Navier-Stokes on a manufactured
solution (``reference/flow_mms.py``), observed orders in L2 (expected u: 3, p: 2)."""
import json

import numpy as np

from _bounds import Bound  # noqa: E402

DESCRIPTION = "FE reference: Taylor-Hood MMS orders (Stokes and Navier-Stokes)"

# Acceptance bounds (verification/studies/_bounds.py): run.py fails the study, naming the
# metric, when one breaks.
BOUNDS = [
    Bound(r"fe(_ns)?_order_u_L2", ">=", 2.8, "Taylor-Hood P2 velocity at third order in L2"),
    Bound(r"fe(_ns)?_order_p_L2", ">=", 1.8, "P1 pressure at second order"),
    Bound(r"fe_order_u_H1", ">=", 1.8, "P2 velocity at second order in H1"),
]

MESHES = {"ci": [4, 8, 16], "quick": [8, 16, 32, 64], "full": [8, 16, 32, 64, 128]}


def run(ctx):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    script = ctx.repo / "reference" / "flow_mms.py"
    Ns = [str(n) for n in MESHES[ctx.tier]]
    res = {}
    for eq in ("stokes", "navier-stokes"):
        ctx.run([ctx.python, script, "--equations", eq, "--N", *Ns, "--out", ctx.outdir], ranks=2)
        res[eq] = json.loads((ctx.outdir / f"mms_{eq}.json").read_text())
    st, ns = res["stokes"], res["navier-stokes"]
    metrics = {"fe_order_u_L2": st["order_u_L2"][-1], "fe_order_p_L2": st["order_p_L2"][-1],
               "fe_order_u_H1": st["order_u_H1"][-1],
               "fe_err_u_L2_finest": st["rows"][-1]["err_u_L2"],
               "fe_err_p_L2_finest": st["rows"][-1]["err_p_L2"],
               "fe_ns_order_u_L2": ns["order_u_L2"][-1], "fe_ns_order_p_L2": ns["order_p_L2"][-1]}
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for eq, mk in (("stokes", "o"), ("navier-stokes", "s")):
        h = np.array([r["h"] for r in res[eq]["rows"]])
        for key, lab in (("err_u_L2", "u L2"), ("err_u_H1", "u H1"), ("err_p_L2", "p L2")):
            ax.loglog(h, [r[key] for r in res[eq]["rows"]], mk + "-", mfc="none",
                      label=f"{eq} {lab}")
    for p in (2, 3):
        ax.loglog(h, st["rows"][-1]["err_u_L2"] * (h / h[-1]) ** p, "k:", lw=0.8)
    ax.set_xlabel("h = 1/N")
    ax.set_ylabel("error")
    ax.legend(fontsize=7)
    ax.set_title("Taylor-Hood P2/P1 MMS (2 ranks)")
    fig.tight_layout()
    png = ctx.outdir / "mms_convergence.png"
    fig.savefig(png, dpi=120)
    tables = {eq: r["rows"] for eq, r in res.items()}
    return {"metrics": metrics, "figures": [str(png)], "tables": tables,
            "notes": "Dirichlet velocity on three sides, exact traction on x = 1; MUMPS LU; "
                     "Newton for Navier-Stokes (rho = 1, mu = 0.1)."}
