"""Every verification study in its ci tier (tiny settings): `verification/run.py --tier ci`
with no study named runs them all; each must finish with status ok and write its
result.json and the report. Results go to build/verification-ci (EFSI_VERIFY_OUT) so that
the quick/full results in build/verification are left alone. Skipped when build/bin/efsi
has not been built."""
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
EFSI = Path(os.environ.get("EFSI_BIN", REPO / "build" / "bin" / "efsi"))
OUT = REPO / "build" / "verification-ci"

pytestmark = pytest.mark.skipif(not EFSI.exists(), reason=f"{EFSI} not built")


def test_every_study_runs_in_ci_tier():
    studies = sorted(p.stem for p in (REPO / "verification" / "studies").glob("*.py")
                     if not p.stem.startswith("_"))
    env = dict(os.environ, EFSI_VERIFY_OUT=str(OUT))
    res = subprocess.run([sys.executable, str(REPO / "verification" / "run.py"), "--tier", "ci"],
                         cwd=REPO, env=env, capture_output=True, text=True, timeout=1500)
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    for name in studies:
        r = json.loads((OUT / name / "result.json").read_text())
        assert r["tier"] == "ci", name
        assert r["status"] == "ok", (name, r.get("error", "")[-2000:])
        assert r["metrics"], f"{name}: no metrics"
    report = (OUT / "report.md").read_text()
    assert all(f"## {name}" in report for name in studies)
