"""Membrane laws on a flat sheet in uniaxial stretch (T2 = 0) against closed forms and data.

Runs build/bin/efsi_membrane_constitutive_study, which drives the solver's own law objects
(solver/membrane/neo_hookean.hpp, skalak.hpp) through the kinematics Bs = P Gs P with
Gs = diag(lambda1^2, lambda2^2, 0), solves T2(lambda2) = 0 by bisection and compares
lambda2 and T1 with MODEL.md "Constitutive checks" (round-off expected), then compares
T1/Gs with the curves of Barthes-Biesel et al. (2002) digitised in
verification/data/uniaxial_stretch/ (Gs = 1: neo-Hookean Es = 3 Gs; Skalak Es/6 = Gs/4 and
alpha = C). The data's C is not stated; the FE reference (reference/membrane_stress.py)
chose C = 1 from a scan over {0.5, 1, 2, 10}; this study repeats the scan (C = 1 has
the smallest max deviation, C = 2 a marginally smaller RMS relative one).
"""
import json
import math
from pathlib import Path

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from _bounds import Bound  # noqa: E402

DESCRIPTION = "neo-Hookean and Skalak laws: uniaxial stretch vs closed forms and Barthes-Biesel 2002"

# Acceptance bounds (verification/studies/_bounds.py): run.py fails the study, naming the
# metric, when one breaks.
BOUNDS = [
    Bound(r"law_error(_.*)?", "<=", 1e-12, "the laws equal their closed forms to round-off"),
    Bound(r"uniaxial_solve_error_.*", "<=", 1e-10,
          "uniaxial stretch with T2 = 0 solved to round-off"),
    Bound(r"data_rms_rel_dev_(neo_hookean|skalak_C1)", "<=", 0.05,
          "within the digitisation error of Barthes-Biesel et al. 2002 (a few %)"),
]

DATA = Path(__file__).resolve().parents[1] / "data" / "uniaxial_stretch"
POINTS = {"ci": 100, "quick": 400, "full": 2000}
C_SCAN = (0.5, 1.0, 2.0, 10.0)


def data_deviation(curve, data):
    """RMS relative and max absolute deviation of the law's T1 at the digitised strains
    (points with T1 < 5% of the largest excluded from the relative measure: there the
    relative error of a digitised point is ill-posed); the FE reference uses the same."""
    t1 = np.interp(data[:, 0], curve["strain"], curve["T1"])
    big = data[:, 1] > 0.05 * data[:, 1].max()
    dev = np.abs(t1 - data[:, 1])
    return float(np.sqrt(np.mean((dev[big] / data[big, 1]) ** 2))), float(dev.max())


def run(ctx):
    exe = ctx.efsi.parent / "efsi_membrane_constitutive_study"
    metrics, notes = {}, []
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, (law, fname) in zip(axes, (("neo_hookean", "barthes_biesel2002_neo_hookean.csv"),
                                       ("skalak", "barthes_biesel2002_skalak.csv"))):
        data = np.loadtxt(DATA / fname, delimiter=",")
        data = data[np.argsort(data[:, 0])]
        lam_max = math.sqrt(1 + 2 * data[:, 0].max()) * 1.02
        alphas = C_SCAN if law == "skalak" else (1.0,)
        best_rms = best_max = None
        for C in alphas:
            out = ctx.run([exe, "--law", law, "--alpha", C, "--lambda-max", lam_max,
                           "--points", POINTS[ctx.tier]])
            r = json.loads(out.stdout)
            rms, dmax = data_deviation(r, data)
            tag = law if law == "neo_hookean" else f"skalak_C{C:g}"
            metrics[f"law_error_{tag}"] = max(r["max_rel_error_law"], r["max_rel_T2_law"])
            metrics[f"uniaxial_solve_error_{tag}"] = r["max_rel_error_solve"]
            metrics[f"data_rms_rel_dev_{tag}"] = rms
            metrics[f"data_max_abs_dev_{tag}"] = dmax
            if best_rms is None or rms < best_rms[1]:
                best_rms = (C, rms)
            if best_max is None or dmax < best_max[1]:
                best_max = (C, dmax)
            style = "-" if (law == "neo_hookean" or C == 1.0) else ":"
            ax.plot(r["strain"], r["T1"], style, label=f"efsi law{'' if law == 'neo_hookean' else f', C = {C:g}'}")
        ax.plot(data[:, 0], data[:, 1], "ko", ms=3, label="Barthes-Biesel 2002 (digitised)")
        ax.set(xlabel="e = (lambda1^2 - 1)/2", ylabel="T1 / Gs", title=law.replace("_", "-"))
        ax.legend(fontsize=8)
        if law == "skalak":
            metrics["skalak_best_C_max_abs"] = best_max[0]
            metrics["skalak_best_C_rms_rel"] = best_rms[0]
            notes.append(f"Skalak: the data's C is not stated. Among C in {C_SCAN} the "
                         f"smallest max absolute deviation is at C = {best_max[0]:g} "
                         f"({best_max[1]:.3f} Gs) and the smallest RMS relative deviation at "
                         f"C = {best_rms[0]:g} ({best_rms[1]:.3f}); C = 1 and C = 2 are within "
                         "the reading error of each other (2.8% vs 2.6% RMS). The FE reference "
                         "(reference/membrane_stress.py) chose C = 1; C = 1 is the value used "
                         "for the comparison here (law_error, figure).")
    metrics["law_error"] = max(metrics["law_error_neo_hookean"], metrics["law_error_skalak_C1"])
    fig.tight_layout()
    png = ctx.outdir / "membrane_constitutive.png"
    fig.savefig(png, dpi=110)
    notes.insert(0, "The law objects reproduce the closed forms to round-off (law_error, relative "
                 "to max(|T1|, Gs)); the deviation from the digitised curves is the reading "
                 "error of the figure (worst at small strain).")
    return {"metrics": metrics, "figures": [str(png)], "notes": " ".join(notes)}
