"""The flow-core verification studies in their ci tier: Taylor-Green orders and the channel
profiles (runs the real solver; skipped when build/bin/efsi has not been built)."""
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
EFSI = Path(os.environ.get("EFSI_BIN", REPO / "build" / "bin" / "efsi"))
OUT = REPO / "build" / "verification"

pytestmark = pytest.mark.skipif(not EFSI.exists(), reason=f"{EFSI} not built")


@pytest.fixture(scope="module")
def results():
    res = subprocess.run([sys.executable, str(REPO / "verification" / "run.py"), "--tier", "ci",
                          "flow_mms", "channel_flows"], cwd=REPO, capture_output=True,
                         text=True, timeout=900)
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    out = {}
    for name in ("flow_mms", "channel_flows"):
        r = json.loads((OUT / name / "result.json").read_text())
        assert r["status"] == "ok" and r["tier"] == "ci"
        out[name] = r["metrics"]
    return out


def test_taylor_green_orders(results):
    m = results["flow_mms"]
    assert 1.8 <= m["order_u_L2"] <= 2.3, m
    assert 1.8 <= m["order_p_L2"] <= 2.3, m


def test_couette_round_off(results):
    m = results["channel_flows"]
    assert m["couette_max_error"] < 1e-8, m
    assert m["couette_stationary_max_error"] < 1e-8, m


def test_poiseuille_order(results):
    m = results["channel_flows"]
    assert 1.8 <= m["poiseuille_order"] <= 2.3, m
