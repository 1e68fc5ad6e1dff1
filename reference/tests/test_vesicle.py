"""2D capsule in shear: Eulerian FE (serial and 2 ranks) and the boundary-integral check."""
import json

import numpy as np

from conftest import run_script

import capsule_bi_2d as bi


def _run(outdir, ranks, Ca=0.2, extra=()):
    run_script(["vesicle_shear_2d.py", "--small", "--Ca", Ca, "--out", outdir, *extra],
               ranks=ranks)
    tag = f"ca{Ca:g}_r1"
    return (json.loads((outdir / f"capsule_{tag}.json").read_text()),
            np.genfromtxt(outdir / f"capsule_{tag}.csv", delimiter=",", names=True))


def test_fe_capsule_serial_vs_two_ranks_and_physics(outdir):
    s1, r1 = _run(outdir / "r1", 1)
    s2, r2 = _run(outdir / "r2", 2, extra=("--write-times", "0.3"))
    assert s2["ranks"] == 2
    assert abs(s1["D_final"] - s2["D_final"]) < 1e-6
    assert (outdir / "r2" / "capsule_ca0.2_r1.xdmf").exists()
    # early time: the membrane is unloaded, the circle follows the shear, D ~ t/2
    j = np.argmin(np.abs(r1["t"] - 0.1))
    assert abs(r1["D"][j] / (r1["t"][j] / 2) - 1) < 0.05
    # inclination starts at pi/4 and decreases; the enclosed amount of phi is conserved
    assert r1["theta_over_pi"][1] > r1["theta_over_pi"][-1] > 0.15
    assert abs(s1["area_drift"]) < 1e-3
    # the membrane is stretched and compressed but stays far from the lambda^2 floor
    assert 0.6 < s1["lambda_min_band"] < 1.0 < s1["lambda_max_band"] < 1.5


def test_fe_agrees_with_boundary_integral_early(outdir):
    s, rows = _run(outdir, 1, Ca=0.2)
    b, _, _ = bi.run(0.2, 64, 0.3)
    # coarse FE (h = d/8, box 4a x 3a half-widths, Re = 0.01) vs unbounded Stokes BI
    assert abs(s["D_final"] - b[-1, 2]) / b[-1, 2] < 0.03
    assert abs(s["theta_over_pi_final"] - b[-1, 3]) < 0.01


def test_boundary_integral_converges_and_conserves_area():
    r32, _, _ = bi.run(0.2, 32, 0.3)
    r64, _, _ = bi.run(0.2, 64, 0.3)
    assert abs(r32[-1, 2] - r64[-1, 2]) < 0.01 * r64[-1, 2]
    assert abs(r64[-1, 1] / r64[0, 1] - 1) < 1e-3      # enclosed area kept
    assert abs(r64[10, 2] / (r64[10, 0] / 2) - 1) < 0.05  # D ~ t/2 at early times


def test_boundary_integral_tension_is_the_laws_with_unit_z_stretch():
    """The z-invariant tensions of capsule_bi_2d (written out by hand) are the principal
    tension T1 of membrane_laws at (lambda, 1), for both laws."""
    import membrane_laws as ml
    lam = np.linspace(0.8, 1.6, 9)
    t1_nh, _ = ml.principal_tensions("neo-hookean", lam, np.ones_like(lam), 3.0)
    assert np.allclose(bi.tension(lam, 3.0), t1_nh, rtol=1e-13, atol=0)
    for C in (1.0, 10.0):
        t1_sk, _ = ml.principal_tensions("skalak", lam, np.ones_like(lam), 3.0, alpha=C)
        assert np.allclose(bi.tension(lam, 3.0, C), t1_sk, rtol=1e-13, atol=0)
