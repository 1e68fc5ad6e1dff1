"""The verification harness discovers studies, records failures and writes result.json."""
import json
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "verification"))

import run as harness  # noqa: E402


def test_every_study_declares_run_and_description():
    studies = harness.discover()
    assert studies, "no studies found"
    for name, path in studies.items():
        mod = harness.load(path)
        assert callable(getattr(mod, "run", None)), f"{name} has no run(ctx)"
        assert getattr(mod, "DESCRIPTION", ""), f"{name} has no DESCRIPTION"


def test_unknown_study_is_an_error():
    res = subprocess.run([sys.executable, str(REPO / "verification" / "run.py"),
                          "no_such_study"], capture_output=True, text=True)
    assert res.returncode == 2
    assert "unknown study" in res.stderr
