"""FEniCSx reference: membrane tension and load on triangulated surfaces.

Runs ``reference/membrane_stress.py`` (a code independent of ``solver/``):
* uniformly inflated sphere, neo-Hookean and Skalak, isoparametric P1 and P2 surfaces:
  relative L2 error of the load q = div_s tau against q = -(2T/R) n, and its order;
* uniaxial stretch of a flat sheet (T2 = 0 solved for lambda2): T1 against the closed
  forms of MODEL.md and the digitised Barthes-Biesel et al. (2002) curves (Skalak C = 1).
"""
import json
from pathlib import Path

import numpy as np

from _bounds import Bound  # noqa: E402

DESCRIPTION = "FE reference: membrane load on an inflated sphere (orders) and uniaxial tension"

# Acceptance bounds (verification/studies/_bounds.py): run.py fails the study, naming the
# metric, when one breaks.
BOUNDS = [
    Bound(r"fe_membrane(_skalak)?_traction_order", ">=", 1.8, "P2 FE traction at second order"),
    Bound(r"fe_membrane_traction_order_P1", ">=", 0.9, "P1 FE traction at first order"),
    Bound(r"fe_uniaxial_.*_closed_form", "<=", 1e-10, "uniaxial FE equals the closed form"),
    Bound(r"fe_membrane_mpi2_max_rel_diff", "<=", 1e-10, "the same answer on 2 ranks"),
    Bound(r"fe_uniaxial_.*_data_rms_rel_dev", "<=", 0.05,
          "within the digitisation error of Barthes-Biesel et al. 2002 (a few %)"),
    Bound(r"fe_membrane_tangential_load_rel", "<=", 1e-3,
          "an inflated sphere carries no tangential load"),
]

LEVELS = {"ci": [1, 2, 3], "quick": [1, 2, 3, 4], "full": [1, 2, 3, 4, 5]}


def run(ctx):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    script = ctx.repo / "reference" / "membrane_stress.py"
    out = ctx.outdir
    levels = [str(v) for v in LEVELS[ctx.tier]]
    conv = {}
    for law in ("neo-hookean", "skalak"):
        for deg in (1, 2):
            ctx.run([ctx.python, script, "convergence", "--law", law, "--degree", deg,
                     "--stretch", 1.2, "--alpha", 1.0, "--levels", *levels, "--out", out])
            conv[(law, deg)] = json.loads((out / f"convergence_{law}_P{deg}.json").read_text())
    # the same study on 2 ranks must give the same numbers
    ctx.run([ctx.python, script, "convergence", "--degree", 2, "--levels", *levels,
             "--out", out / "mpi2"], ranks=2)
    mpi = json.loads((out / "mpi2" / "convergence_neo-hookean_P2.json").read_text())
    small = ["--small"] if ctx.tier == "ci" else []
    ctx.run([ctx.python, script, "uniaxial", "--alpha", 1.0, "--degree", 1, "--out", out, *small])
    uni = json.loads((out / "uniaxial.json").read_text())

    nh2 = conv[("neo-hookean", 2)]
    metrics = {
        "fe_membrane_traction_error": nh2["rows"][-1]["err_q"],
        "fe_membrane_traction_order": nh2["orders_q"][-1],
        "fe_membrane_traction_order_P1": conv[("neo-hookean", 1)]["orders_q"][-1],
        "fe_membrane_traction_error_P1": conv[("neo-hookean", 1)]["rows"][-1]["err_q"],
        "fe_membrane_skalak_traction_error": conv[("skalak", 2)]["rows"][-1]["err_q"],
        "fe_membrane_skalak_traction_order": conv[("skalak", 2)]["orders_q"][-1],
        "fe_membrane_tangential_load_rel": nh2["rows"][-1]["err_qt"],
        "fe_membrane_energy_error": nh2["rows"][-1]["err_energy"],
        "fe_membrane_mpi2_max_rel_diff": max(abs(a["err_q"] - b["err_q"]) / a["err_q"]
                                             for a, b in zip(nh2["rows"], mpi["rows"])),
        "fe_uniaxial_nh_T1_rel_err_closed_form": uni["neo-hookean"]["max_rel_err_T1_vs_closed_form"],
        "fe_uniaxial_sk_T1_rel_err_closed_form": uni["skalak"]["max_rel_err_T1_vs_closed_form"],
        "fe_uniaxial_nh_lambda2_err_closed_form": uni["neo-hookean"]["max_abs_err_lambda2_vs_closed_form"],
        "fe_uniaxial_sk_lambda2_err_closed_form": uni["skalak"]["max_abs_err_lambda2_vs_closed_form"],
        "fe_uniaxial_nh_data_rms_rel_dev": uni["neo-hookean"]["data_rms_rel_dev"],
        "fe_uniaxial_sk_data_rms_rel_dev": uni["skalak"]["data_rms_rel_dev"],
        "fe_uniaxial_nh_data_max_abs_dev_over_Gs": uni["neo-hookean"]["data_max_abs_dev_over_Gs"],
        "fe_uniaxial_sk_data_max_abs_dev_over_Gs": uni["skalak"]["data_max_abs_dev_over_Gs"],
    }

    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for (law, deg), c in conv.items():
        h = [r["h"] for r in c["rows"]]
        ax[0].loglog(h, [r["err_q"] for r in c["rows"]], "o-", label=f"{law} P{deg}")
    h = np.array([r["h"] for r in nh2["rows"]])
    for p in (1, 2):
        ax[0].loglog(h, nh2["rows"][-1]["err_q"] * (h / h[-1]) ** p, "k:", lw=0.8)
    ax[0].set_xlabel("edge length h / R0")
    ax[0].set_ylabel("relative L2 error of the load")
    ax[0].set_title("inflated sphere, s = 1.2")
    ax[0].legend()
    for law, mk in (("neo_hookean", "o"), ("skalak", "s")):
        d = np.loadtxt(Path(__file__).resolve().parents[1] / "data" / "uniaxial_stretch" / f"barthes_biesel2002_{law}.csv",
                       delimiter=",")
        t = np.loadtxt(out / f"uniaxial_{law.replace('_', '-')}.csv", delimiter=",")
        ax[1].plot(d[:, 0], d[:, 1], mk, mfc="none", label=f"Barthes-Biesel 2002 {law}")
        ax[1].plot(t[:, 1], t[:, 4], "-", label=f"FE {law}")
    ax[1].set_xlabel("e = (lambda1^2 - 1)/2")
    ax[1].set_ylabel("T1 / Gs")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    png = out / "membrane_convergence.png"
    fig.savefig(png, dpi=120)

    table = {f"{law}_P{deg}": [{k: r[k] for k in ("level", "cells", "h", "err_q", "err_qn",
                                                  "err_qt", "err_energy")} for r in c["rows"]]
             for (law, deg), c in conv.items()}
    notes = ("Load q from virtual work (mass-matrix projection of -tau:grad_s w) on the "
             "isoparametric P_k sphere. Expected order k in L2. Uniaxial data are "
             "digitised (reading error ~1-2% of full scale); Skalak with C = 1.")
    return {"metrics": metrics, "figures": [str(png)], "tables": table, "notes": notes}
