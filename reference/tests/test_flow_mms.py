"""Taylor-Hood MMS: observed orders (u L2 ~ 3, p L2 ~ 2), serial and on 2 ranks."""
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
