"""The verification harness discovers studies, records failures and writes result.json."""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

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
    assert _flowio.completed(other, 2.0, allow_unstable=True)  # stopped UNSTABLE: a result


class _FakeCtx:
    """Stands in for run.Context: run_efsi writes the summary.json a solver run would."""

    def __init__(self, status: str | None):
        self.status, self.calls = status, []

    def run_efsi(self, case, out, sets=None, ranks=1, extra=None, check=True):
        self.calls.append((check, list(extra or [])))
        out.mkdir(parents=True, exist_ok=True)
        if self.status is None:
            return None
        (out / "summary.json").write_text(json.dumps({"status": self.status, "time": 0.7}))
        return {"status": self.status}


def test_cached_run_takes_an_unstable_stop_as_a_result_only_when_allowed(tmp_path):
    sys.path.insert(0, str(REPO / "verification" / "studies"))
    import _flowio

    out = tmp_path / "runs" / "a"
    ctx = _FakeCtx("unstable")
    assert _flowio.cached_run(ctx, Path("case"), out, {}, 2.0, allow_unstable=True) == out
    assert ctx.calls == [(False, [])]  # the solver's exit 3 is not an error here
    _flowio.cached_run(ctx, Path("case"), out, {}, 2.0, allow_unstable=True)
    assert len(ctx.calls) == 1  # finished: not rerun
    # Without allow_unstable the run is not finished (it would rerun, checked).
    _flowio.cached_run(ctx, Path("case"), out, {}, 2.0)
    assert ctx.calls[-1][0] is True
    # A run that wrote no summary (crashed) is an error even when unstable stops are allowed.
    (out / "checkpoint.h5").write_text("")
    crashed = _FakeCtx(None)
    import pytest

    with pytest.raises(RuntimeError, match="neither completed nor stopped UNSTABLE"):
        _flowio.cached_run(crashed, Path("case"), tmp_path / "runs" / "b", {}, 2.0,
                           allow_unstable=True)



def test_records_only_takes_a_named_record_and_never_runs(tmp_path, monkeypatch):
    """EFSI_VERIFY_RECORDS=only: a run is taken from its record (here a folder named other
    than the run, as capsule_longtime's `_foot` records) or raises RunNotMade; the solver is
    never started."""
    sys.path.insert(0, str(REPO / "verification" / "studies"))
    import _flowio
    import pytest

    monkeypatch.setattr(_flowio, "RECORDS", tmp_path / "records")
    monkeypatch.setenv("EFSI_VERIFY_RECORDS", "only")
    rec = tmp_path / "records" / "capsule_longtime" / "ca0.05_n64_t20_foot"
    rec.mkdir(parents=True)
    (rec / "summary.json").write_text(json.dumps({"status": "completed", "time": 20.0}))
    (rec / "record.json").write_text(json.dumps({"git_at_record": "abcdef0123"}))
    runs = tmp_path / "build" / "capsule_longtime" / "runs"
    ctx = _FakeCtx("completed")
    _flowio.USED_RECORDS.clear()
    out = _flowio.cached_run(ctx, Path("case"), runs / "ca0.05_n64_t20", {}, 20.0,
                             record="ca0.05_n64_t20_foot")
    assert (out / "summary.json").exists() and ctx.calls == []
    assert "record ca0.05_n64_t20_foot" in _flowio.USED_RECORDS[0]
    # The plain name is not the record asked for: nothing is taken, nothing runs.
    with pytest.raises(_flowio.RunNotMade, match="not run"):
        _flowio.cached_run(ctx, Path("case"), runs / "ca0.1_n64_t20", {}, 20.0,
                           record="ca0.1_n64_t20_foot")
    assert ctx.calls == []
    # Without "only" the same missing run is made.
    monkeypatch.setenv("EFSI_VERIFY_RECORDS", "1")
    _flowio.cached_run(ctx, Path("case"), runs / "ca0.1_n64_t20", {}, 0.7)
    assert len(ctx.calls) == 1

def test_full_tier_results_are_stored_and_published_with_a_status(tmp_path, monkeypatch):
    """run.py keeps a finished full-tier result (figures beside it, repository-relative
    paths); publish.py writes the page from the stored results and names the studies that
    have none yet."""
    store = tmp_path / "store"
    monkeypatch.setattr(harness, "STORE_ROOT", store)
    monkeypatch.setattr(harness, "REPO", tmp_path)
    fig = tmp_path / "build" / "flow_mms" / "conv.png"
    fig.parent.mkdir(parents=True)
    fig.write_bytes(b"\x89PNG fake")
    dest = harness.store_full_result("flow_mms", {
        "tier": "full", "status": "ok", "metrics": {"order_u_L2": 1.99},
        "figures": [str(fig)], "versions": {"git": "abcdef0123456789"}})
    stored = json.loads((dest / "result.json").read_text())
    assert stored["figures"] == ["store/flow_mms/conv.png"]
    assert (dest / "conv.png").read_bytes() == fig.read_bytes() and stored["stored"]
    # publish resolves figures against the real repository: give it an absolute path.
    stored["figures"] = [str(dest / "conv.png")]
    (dest / "result.json").write_text(json.dumps(stored))
    docs = tmp_path / "docs"
    summary = tmp_path / "summary.md"
    summary.write_text("# Verification report\n\nintro\n\n## Headline figures\n\n"
                       "u order {{flow_mms:order_u_L2:.2f}}, VOF {{vof_advection:phi_min}}\n")
    out = subprocess.run([sys.executable, str(REPO / "verification" / "publish.py"),
                          "--results", str(store), "--docs", str(docs), "--summary", str(summary)],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    page = (docs / "verification.md").read_text()
    assert "u order 1.99, VOF (no full-tier result yet)" in page
    n = len(harness.discover())
    assert f"**Status: partial.** 1 of {n} studies have a full-tier result" in page
    assert "capsule_shear" in page.split("not yet:")[1].split("\n")[0]
    assert "commit abcdef0123" in page and "| order_u_L2 | 1.99 |" in page
    assert page.index("## Status") < page.index("## Headline figures")


def _fake_capsule_run(out: Path, d_of_t, t_stop: float, status: str):
    out.mkdir(parents=True)
    t = np.linspace(0.0, t_stop, int(round(t_stop / 0.05)) + 1)
    lines = ["step,time,body,taylor_deformation,inclination_over_pi,volume,tensor_trace_max"]
    lines += [f"{i},{ti!r},capsule,{d_of_t(ti)!r},0.25,4.2,3.0" for i, ti in enumerate(t)]
    (out / "bodies.csv").write_text("\n".join(lines) + "\n")
    (out / "summary.json").write_text(json.dumps({"status": status, "time": float(t[-1]),
                                                  "wall_seconds": 1.0}))


def test_width_sweep_reports_a_run_that_stopped_unstable_without_values_past_its_stop(
        tmp_path, monkeypatch):
    """Three widths at ratio 2 on one grid: D = D0 + c eps^2 t gives order 2 in eps at
    t = 0.5 and 1. The widest run stops UNSTABLE at t = 1.4, so nothing is extrapolated at
    t = 2 (its last D must not stand in for D(2)), and its row says where it stopped."""

    sys.path.insert(0, str(REPO / "verification" / "studies"))
    import capsule_shear as cs

    monkeypatch.setattr(cs, "WIDTH_SWEEP", {"full": [(0.05, [(8, 2.0), (8, 1.0), (8, 0.5)])]})

    class Ctx:
        tier, outdir, repo, long_ranks = "full", tmp_path, REPO, 1

    for w, t_stop, status in ((2.0, 1.4, "unstable"), (1.0, 2.0, "completed"),
                              (0.5, 2.0, "completed")):
        eps = w * 2.0 / 8
        _fake_capsule_run(cs.run_dir(Ctx, 3, 8, 0.05, 2.0, None, w),
                          lambda t, e=eps: 0.2 + 0.1 * e * e * t, t_stop, status)
    data = REPO / "verification" / "data" / "capsule_shear"
    skipped, metrics, figures = [], {}, []
    rows = cs.width_sweep(Ctx, data, 2.0, True, skipped, metrics, figures)
    assert skipped == []  # an UNSTABLE stop is a cached result, not a missing run
    wide = next(r for r in rows if r["w"] == 2.0)
    assert wide["stopped"] == "UNSTABLE at t = 1.4" and wide["t_end"] == 1.4
    assert metrics["unstable_at_t_ca0.05_n32_w2"] == 1.4
    for tq in ("0.5", "1"):
        assert metrics[f"D_eps_order_ca0.05_n32_t{tq}"] == pytest.approx(2.0, rel=1e-9)
        assert metrics[f"D_eps_extrapolated_ca0.05_n32_t{tq}"] == pytest.approx(0.2, abs=1e-12)
    assert "D_eps_order_ca0.05_n32_t2" not in metrics


def test_a_completed_run_past_the_tensor_bound_is_flagged_from_where_it_crossed(tmp_path):
    """Runs recorded before stability.max_tensor_trace existed could "complete" with tr Gs in
    the 10^5: the row must say from when the run is not valid."""
    sys.path.insert(0, str(REPO / "verification" / "studies"))
    import capsule_shear as cs

    out = tmp_path / "run"
    _fake_capsule_run(out, lambda t: 0.1 * t, 2.0, "completed")
    lines = (out / "bodies.csv").read_text().splitlines()
    # tr Gs 3 until t = 1.2, then 3 * 10^(t - 1.2) * 60: over 100 from the first row past 1.2
    body = []
    for line in lines[1:]:
        f = line.split(",")
        t = float(f[1])
        f[-1] = repr(3.0 if t <= 1.2 + 1e-12 else 180.0 * 10 ** (t - 1.2))
        body.append(",".join(f))
    (out / "bodies.csv").write_text("\n".join([lines[0]] + body) + "\n")
    note, after, max_tr = cs.stop_note(out)
    assert after == pytest.approx(1.25) and max_tr == pytest.approx(180.0 * 10 ** 0.8)
    assert note.startswith("completed, but tr Gs > 100") and "invalid after" in note
    _fake_capsule_run(tmp_path / "ok", lambda t: 0.1 * t, 2.0, "completed")
    assert cs.stop_note(tmp_path / "ok") == ("completed", None, 3.0)


def test_the_studys_tensor_bound_is_the_solvers_default():
    sys.path.insert(0, str(REPO / "verification" / "studies"))
    import capsule_shear as cs

    ref = (REPO / "docs" / "case-reference.md").read_text()
    row = next(line for line in ref.splitlines() if "`stability.max_tensor_trace`" in line)
    assert float(row.split("|")[4]) == cs.MAX_TENSOR_TRACE


def test_long_capsule_run_that_stops_unstable_is_reported_up_to_its_stop(tmp_path):
    """stability's long 3D run: an UNSTABLE stop (e.g. on the tensor bound) gives the drift up
    to the stop and where it stopped, never a capsule_volume_drift_t10."""
    sys.path.insert(0, str(REPO / "verification" / "studies"))
    import stability

    class Ctx:
        outdir, repo, long_ranks = tmp_path, REPO, 2

        def __init__(self, t_stop, status):
            self.t_stop, self.status, self.sets = t_stop, status, []

        def run_efsi(self, case, out, sets=None, ranks=1, extra=None, check=True):
            assert not check  # an UNSTABLE stop is allowed here
            self.sets.append(dict(sets))
            out.mkdir(parents=True, exist_ok=True)
            t = np.linspace(0.0, self.t_stop, 11)
            lines = ["step,time,body,volume,area,taylor_deformation,tensor_trace_max"]
            lines += [f"{i},{ti!r},capsule,{4.0 + 1e-12 * i!r},{12.0 + 0.1 * ti!r},0.4,"
                      f"{3.0 + ti!r}" for i, ti in enumerate(t)]
            (out / "bodies.csv").write_text("\n".join(lines) + "\n")
            (out / "summary.json").write_text(json.dumps({
                "status": self.status, "time": self.t_stop, "wall_seconds": 1.0, "steps": 10,
                "message": "UNSTABLE ..." if self.status == "unstable" else None}))
            return {"status": self.status}

    metrics = {}
    ctx = Ctx(7.4, "unstable")
    row, _ = stability.long_capsule(ctx, 16, 10.0, 5.0, metrics)
    assert row["status"] == "unstable" and row["t_end"] == 7.4
    assert "capsule_volume_drift_t10" not in metrics
    assert metrics["capsule_long_run_unstable_at_t"] == 7.4
    assert metrics["capsule_volume_drift_to_stop"] == pytest.approx(1e-11 / 4.0, rel=1e-3)
    assert metrics["capsule_long_run_max_trace_Gs"] == pytest.approx(10.4)
    ok = Ctx(10.0, "completed")
    row, _ = stability.long_capsule(ok, 16, 10.0, 1.5, metrics)
    assert ok.sets[0]["body[0].surface_velocity_reach"] == "1.5"
    assert metrics["capsule_volume_drift_t10_reach1.5"] == pytest.approx(1e-11 / 4.0, rel=1e-3)
    assert "capsule_long_run_unstable_at_t_reach1.5" not in metrics


def test_stability_sweeps_a_case_unstable_with_the_automatic_dt_with_the_named_remedy(
        tmp_path, monkeypatch):
    """A stiff capsule whose run with the automatic dt stops UNSTABLE (Gs growth of the
    default reach, whatever dt) has no dt margin: it is reported where it stopped, and the
    sweep is made with surface_velocity_reach = 1.5, the remedy the message names."""
    sys.path.insert(0, str(REPO / "verification" / "studies"))
    import stability

    calls = []

    def fake_one_run(ctx, case, out, sets):
        calls.append((out.parent.name, out.name, dict(sets)))
        stiff = "1.5" != sets.get("body[0].surface_velocity_reach") and \
            sets.get("body[0].elastic_modulus") == repr(1 / 0.002)
        if stiff:
            return {"exit_code": 3, "status": "unstable", "message": "UNSTABLE at ...",
                    "stop_time": 0.557, "dt_typical": 5e-4}
        k = float(out.name[1:]) if out.name.startswith("k") else 1.0
        ok = k <= 2.0
        return {"exit_code": 0 if ok else 3, "status": "completed" if ok else "unstable",
                "message": "" if ok else "UNSTABLE", "stop_time": 2.0, "dt_typical": 1e-3,
                "nonfinite_in_fields": 0}

    monkeypatch.setattr(stability, "one_run", fake_one_run)
    monkeypatch.setitem(stability.TIERS, "ci", {"n": 8, "cas": [0.002, 0.2],
                                                 "ks": [1.0, 2.0, 4.0], "t_end": 0.25,
                                                 "res": [], "grids": [], "long": None})

    class Ctx:
        tier, outdir, repo = "ci", tmp_path, REPO

    res = stability.run(Ctx)
    m = res["metrics"]
    assert m["unstable_with_automatic_dt_at_t_capsule_ca0.002"] == 0.557
    assert "stable_margin_capsule_ca0.002" not in m
    assert m["stable_margin_capsule_ca0.002_reach1.5"] == 2.0
    assert m["stable_margin_capsule"] == 2.0
    assert any(c[0] == "capsule_ca0.002_reach1.5" for c in calls)
    assert not any(c[0] == "capsule_ca0.2_reach1.5" for c in calls)  # only where needed
