"""The stability study in its ci tier: the automatic dt is stable (margin >= 1) and runs that
go unstable stop cleanly without writing non-finite fields (runs the real solver; skipped
when build/bin/efsi has not been built)."""
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


def test_stability_ci():
    res = subprocess.run([sys.executable, str(REPO / "verification" / "run.py"), "--tier", "ci",
                          "stability"], cwd=REPO, capture_output=True, text=True, timeout=900)
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    r = json.loads((OUT / "stability" / "result.json").read_text())
    assert r["status"] == "ok" and r["tier"] == "ci"
    m = r["metrics"]
    assert m["stable_margin_capsule"] >= 1, m
    assert m["stable_margin_slab"] >= 1, m
    assert m["unstable_runs_with_nan_fields"] == 0, m
    assert m["nonfinite_field_runs"] == 0, m
    assert m["crashed_runs"] == 0, m
