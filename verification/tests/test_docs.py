"""docs/case-reference.md is in step with the keys the solver actually reads."""
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
EFSI = REPO / "build" / "bin" / "efsi"


@pytest.mark.skipif(not EFSI.exists(), reason="solver not built")
def test_case_reference_matches_solver_keys():
    keys = subprocess.run([str(EFSI), "keys"], capture_output=True, text=True, check=True).stdout
    doc = (REPO / "docs" / "case-reference.md").read_text()
    missing = [line for line in keys.splitlines() if line.strip() and line not in doc]
    assert not missing, "docs/case-reference.md is stale (run `make docs`): " + "\n".join(missing[:5])


@pytest.mark.skipif(not EFSI.exists(), reason="solver not built")
def test_every_case_validates():
    for case in sorted((REPO / "cases").glob("*/case.toml")):
        res = subprocess.run([str(EFSI), "check", str(case.parent)], capture_output=True, text=True)
        assert res.returncode == 0, f"{case.parent.name}: {res.stderr}"
