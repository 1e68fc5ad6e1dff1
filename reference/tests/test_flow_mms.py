"""Taylor-Hood MMS: observed orders (u L2 ~ 3, p L2 ~ 2), serial and on 2 ranks; the
unsteady Taylor-Green vortex against its exact solution."""
import json

import pytest

from conftest import run_script


@pytest.mark.parametrize("equations,ranks", [("stokes", 1), ("stokes", 2), ("navier-stokes", 2)])
def test_taylor_hood_orders(equations, ranks, outdir):
    run_script(["flow_mms.py", "--small", "--equations", equations, "--out", outdir], ranks=ranks)
    res = json.loads((outdir / f"mms_{equations}.json").read_text())
    assert res["ranks"] == ranks
    assert abs(res["order_u_L2"][-1] - 3.0) < 0.3, res["order_u_L2"]
    assert abs(res["order_u_H1"][-1] - 2.0) < 0.3, res["order_u_H1"]
    assert abs(res["order_p_L2"][-1] - 2.0) < 0.3, res["order_p_L2"]
    # the discrete solution is only weakly divergence free, but |div u_h| must shrink
    divs = [r["div_u_L2"] for r in res["rows"]]
    assert divs[-1] < 0.3 * divs[0]


def test_taylor_green_unsteady_order(outdir):
    """Unsteady Taylor-Green (Crank-Nicolson/AB2, P2/P1) against the exact solution at t = 1:
    the velocity L2 error falls at least at the P2 rate 3 (measured 3.6, 3.9 on 8-16-32 and
    3.65 on 64-128: pre-asymptotic, see the script's docstring), and halving dt does not
    change it (the time error is negligible at the default cfl)."""
    run_script(["flow_mms.py", "--equations", "taylor-green", "--N", 8, 16, 32, "--out", outdir])
    res = json.loads((outdir / "mms_taylor-green.json").read_text())
    e = [r["err_u_L2"] for r in res["rows"]]
    assert e[0] > e[1] > e[2]
    assert 2.7 < res["order_u_L2"][-1] < 4.3, res["order_u_L2"]
    assert abs(res["rows"][-1]["t_end"] - 1.0) < 1e-12
    half = outdir / "half_dt"
    steps = 2 * res["rows"][-1]["steps"]
    run_script(["flow_mms.py", "--equations", "taylor-green", "--N", 32, "--steps", steps,
                "--out", half])
    e_half = json.loads((half / "mms_taylor-green.json").read_text())["rows"][0]["err_u_L2"]
    assert abs(e_half - e[2]) < 0.01 * e[2], (e_half, e[2])
