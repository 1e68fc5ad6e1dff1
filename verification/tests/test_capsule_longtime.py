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
