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


def test_committed_records_fill_the_cache_only_when_asked(tmp_path, monkeypatch):
    """verification/record.py writes a run's small files and record.json; with
    EFSI_VERIFY_RECORDS=1 completed() copies a completed record into the build cache (and
    lists it), without it, or for a run that did not complete, it does not."""
    sys.path.insert(0, str(REPO / "verification" / "studies"))
    import _flowio

    monkeypatch.setattr(_flowio, "RECORDS", tmp_path / "records")
    run = tmp_path / "build" / "capsule_shear" / "runs" / "3d_n16_ca0.05_t2"
    run.mkdir(parents=True)
    (run / "bodies.csv").write_text("step,time,body,taylor_deformation\n0,0,capsule,0\n")
    summary = {"status": "completed", "time": 2.0}
    (run / "summary.json").write_text(json.dumps(summary))
    rec = _flowio.record_dir(run)
    assert rec == tmp_path / "records" / "capsule_shear" / "3d_n16_ca0.05_t2"
    rec.mkdir(parents=True)
    for name in ("bodies.csv", "summary.json"):
        (rec / name).write_text((run / name).read_text())
    (rec / "record.json").write_text(json.dumps({"git_at_record": "0123456789abcdef",
                                                 "date": "2026-11-23"}))
    fresh = tmp_path / "build2" / "capsule_shear" / "runs" / "3d_n16_ca0.05_t2"
    monkeypatch.delenv("EFSI_VERIFY_RECORDS", raising=False)
    assert not _flowio.completed(fresh, 2.0)
    monkeypatch.setenv("EFSI_VERIFY_RECORDS", "1")
    _flowio.USED_RECORDS.clear()
    assert not _flowio.completed(fresh, 4.0)  # the record ends at t = 2
    assert _flowio.completed(fresh, 2.0)
    assert (fresh / "bodies.csv").read_text() == (run / "bodies.csv").read_text()
    assert _flowio.USED_RECORDS and "0123456789" in _flowio.USED_RECORDS[0]
    (rec / "summary.json").write_text(json.dumps({"status": "unstable", "time": 2.0}))
    other = tmp_path / "build3" / "capsule_shear" / "runs" / "3d_n16_ca0.05_t2"
    assert not _flowio.completed(other, 2.0)
