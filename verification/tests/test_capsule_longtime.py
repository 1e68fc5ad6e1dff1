"""capsule_longtime (issue 19): its acceptance bounds flag every broken target."""
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "verification"))
sys.path.insert(0, str(REPO / "verification" / "studies"))

import run as harness  # noqa: E402

longtime = harness.load(REPO / "verification" / "studies" / "capsule_longtime.py")

GOOD = {"t_end": 10.0, "max_trace_Gs": 3.2, "volume_drift": 1e-12, "max_area_change": 0.03}


def test_a_run_meeting_every_target_breaks_no_bound():
    assert longtime.broken_bounds(GOOD, 10.0, 0.05, "neo_hookean", None) == []


def test_each_broken_target_is_named():
    def broken(**change):
        return longtime.broken_bounds({**GOOD, **change}, 10.0, 0.05, "neo_hookean", None)
    assert "stopped at t" in broken(t_end=3.59)[0]
    assert "tr Gs" in broken(max_trace_Gs=45.0)[0]
    assert "volume drift" in broken(volume_drift=2e-10)[0]
    assert "area change" in broken(max_area_change=0.06)[0]
    # The area bound is for neo-Hookean membranes at Ca <= 0.05 and Skalak C = 100 only.
    assert longtime.broken_bounds({**GOOD, "max_area_change": 0.3}, 10.0, 0.2, "neo_hookean",
                                  None) == []
    assert longtime.broken_bounds({**GOOD, "max_area_change": 0.02}, 10.0, 0.025, "skalak",
                                  100.0)


def test_metric_tags_follow_the_issue():
    assert longtime.tag(0.05, 16, "neo_hookean", None, 0.0) == "ca0.05_n64"
    assert longtime.tag(0.025, 16, "skalak", 100.0, 0.0) == "ca0.025_n64_skalak_C100"
    assert abs(longtime.steady_reference(0.0125, "neo_hookean", None) - 0.078125) < 1e-12


def _write_run(out: Path, sharp_rows):
    """A run folder with bodies.csv (a `taylor_deformation_sharp` column filled from
    `sharp_rows`: None drops the column) and summary.json."""
    import json
    out.mkdir(parents=True)
    cols = ["step", "time", "body", "volume", "area", "taylor_deformation",
            "inclination_over_pi", "tensor_trace_max", "reference_area"]
    if sharp_rows is not None:
        cols.append("taylor_deformation_sharp")
    lines = [",".join(cols)]
    for i, t in enumerate([0.0, 1.0, 2.0, 3.0, 4.0]):
        row = [str(i), str(t), "capsule", "4.19", "12.6", str(0.1 * t / 4), "0.2", "2.0", "12.6"]
        if sharp_rows is not None:
            row.append(sharp_rows[i])
        lines.append(",".join(row))
    (out / "bodies.csv").write_text("\n".join(lines) + "\n")
    (out / "summary.json").write_text(json.dumps({"status": "completed", "bodies": []}))


def test_sharp_steady_d_is_the_last_quarters_mean_and_only_when_measured(tmp_path):
    _write_run(tmp_path / "a", ["0", "0.02", "0.05", "0.08", "0.12"])
    assert abs(longtime.measure(tmp_path / "a")["steady_D_sharp"] - 0.10) < 1e-12
    # Restarted by the version that added the column: the older rows hold nan. A last
    # quarter with nan is not a measurement.
    _write_run(tmp_path / "b", ["nan", "nan", "nan", "nan", "0.12"])
    assert longtime.measure(tmp_path / "b")["steady_D_sharp"] is None
    _write_run(tmp_path / "c", None)
    assert longtime.measure(tmp_path / "c")["steady_D_sharp"] is None


def test_a_run_neither_cached_nor_recorded_is_reported_as_not_made(tmp_path, monkeypatch):
    """EFSI_VERIFY_RECORDS=only with no record: the run is a "not run" row and counts in
    runs_not_made, whose bound breaks; the solver is never started."""
    import _bounds
    import _flowio

    class Ctx:
        tier, repo, outdir, long_ranks = "ci", REPO, tmp_path / "out", 1

        def run_efsi(self, *a, **k):
            raise AssertionError("records only: nothing may run")

    monkeypatch.setattr(_flowio, "RECORDS", tmp_path / "records")
    monkeypatch.setenv("EFSI_VERIFY_RECORDS", "only")
    result = longtime.run(Ctx())
    assert result["metrics"]["runs_not_made"] == 1
    assert result["tables"]["runs"][0]["status"] == "not run"
    assert "Not made" in result["notes"] and "ca0.2_n32" in result["notes"]
    bad = _bounds.broken(_bounds.evaluate(longtime.BOUNDS, result["metrics"], "ci"))
    assert any("runs_not_made" in str(v) for v in bad)


def test_a_curve_plateau_is_the_mean_over_the_last_quarter_of_its_time_range():
    import numpy as np
    t = np.linspace(2.0, 10.0, 81)
    d = np.where(t >= 8.0, 0.3, 0.1)
    assert abs(longtime.curve_plateau(np.column_stack([t, d])) - 0.3) < 1e-15
    d = np.where(t >= 8.0, 0.3, 0.1) + np.where(t > 9.0, 0.1, 0.0)
    expected = float(np.mean(d[t >= 8.0]))
    assert abs(longtime.curve_plateau(np.column_stack([t, d])) - expected) < 1e-15


def test_every_neo_hookean_ca_has_every_other_reference_stored():
    for ca in (0.0125, 0.025, 0.05, 0.1, 0.2):
        found = longtime.other_plateaus(ca)
        assert set(found) == set(longtime.OTHER_REFERENCES), ca
        assert all(0 < v < 1 for v in found.values())


def test_the_references_table_reports_differences_and_adds_no_bound():
    metrics = {"steady_D_ca0.05_n128": 0.30, "steady_D_sharp_ca0.05_n128": 0.31}
    rows = longtime.references_table(metrics)
    row = next(r for r in rows if r["Ca"] == 0.05)
    assert row["efsi d/32, moments"] == 0.30 and row["efsi d/16, moments"] == "-"
    others = longtime.other_plateaus(0.05)
    for ref, label in longtime.OTHER_REFERENCES.items():
        assert abs(metrics[f"steady_D_minus_{ref}_ca0.05_n128"] - (0.30 - others[ref])) < 1e-15
        assert row[f"efsi d/32 moments minus {label}"] == round(0.30 - others[ref], 4)
    assert "steady_D_minus_huet_ft_ca0.05_n64" not in metrics
    # the repository's own boundary integrals are reported beside, not counted as published
    assert row["BI 3D level"] == metrics["bi3d_level_ca0.05"] >= 3
    spread = metrics["published_steady_D_spread_ca0.05"]
    assert abs(spread - abs(others["doddi_bagchi2008"] - 0.26)) < 1e-15
    # 0.30 lies above both published plateaus (0.26 and Doddi & Bagchi's ~0.28).
    hi = max(0.26, others["doddi_bagchi2008"])
    assert abs(metrics["steady_D_outside_published_ca0.05_n128"] - (0.30 - hi)) < 1e-15
    inside = {"steady_D_ca0.05_n128": 0.5 * (0.26 + others["doddi_bagchi2008"])}
    longtime.references_table(inside)
    assert inside["steady_D_outside_published_ca0.05_n128"] == 0.0
    # Reported only: no bound names these metrics.
    import re
    for b in longtime.BOUNDS:
        assert not any(re.fullmatch(b.metric, k) for k in metrics
                       if k.startswith(("steady_D_minus_", "published_", "steady_D_doddi", "steady_D_outside",
                                        "steady_D_huet", "steady_D_bi3d", "bi3d_level"))), b.metric
