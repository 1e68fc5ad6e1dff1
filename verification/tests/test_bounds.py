"""Acceptance bounds (verification/studies/_bounds.py): they can fail, they cannot pass
vacuously, and every study declares them."""
import math
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "verification" / "studies"))
sys.path.insert(0, str(REPO / "verification"))
import _bounds  # noqa: E402
from _bounds import Bound  # noqa: E402


def test_a_bound_passes_and_breaks():
    b = [Bound("order_.*", ">=", 1.8, "second order")]
    assert not _bounds.broken(_bounds.evaluate(b, {"order_u": 1.99, "order_p": 1.95}, "ci"))
    bad = _bounds.broken(_bounds.evaluate(b, {"order_u": 1.99, "order_p": 1.2}, "ci"))
    assert [v["metric"] for v in bad] == ["order_p"]
    assert "order_p = 1.2 breaks order_.* >= 1.8" in _bounds.describe(bad[0])


def test_a_bound_that_matches_nothing_is_broken():
    v = _bounds.evaluate([Bound("order_u", ">=", 1.8, "x")], {"order_p": 2.0}, "quick")
    assert _bounds.broken(v) and "no metric" in v[0]["problem"]


def test_a_bound_for_another_tier_is_not_checked():
    v = _bounds.evaluate([Bound("order_u", ">=", 1.8, "x", tiers=("full",))], {}, "ci")
    assert v == []


@pytest.mark.parametrize("value", [math.nan, math.inf, "1.9", None, True])
def test_a_value_that_is_not_a_finite_number_breaks_the_bound(value):
    v = _bounds.evaluate([Bound("e", "<=", 1.0, "x")], {"e": value}, "ci")
    assert _bounds.broken(v)


def test_absent_means_no_metric_may_match():
    b = [Bound("unstable_at_t_.*", "absent", why="runs reach their end")]
    assert not _bounds.broken(_bounds.evaluate(b, {"D": 0.2}, "ci"))
    assert _bounds.broken(_bounds.evaluate(b, {"unstable_at_t_ca0.05": 3.6}, "ci"))


def test_bad_declarations_are_refused():
    with pytest.raises(ValueError):
        Bound("x", "<", 1.0, "x")
    with pytest.raises(ValueError):
        Bound("x", "<=", 1.0, "x", tiers=("nightly",))


def test_every_study_declares_bounds_for_every_tier():
    import run
    for name, path in run.discover().items():
        mod = run.load(path)
        bounds = getattr(mod, "BOUNDS", None)
        assert bounds, f"{name} declares no BOUNDS"
        for tier in _bounds.TIERS:
            assert any(tier in b.tiers for b in bounds), f"{name}: no bound for tier {tier}"


def test_committed_full_results_record_their_bound_verdicts():
    """A stored full-tier result is checked against the study's current bounds: its status
    says whether it meets them (a result that misses is kept and reported, not hidden)."""
    import json

    import run
    for name, path in run.discover().items():
        f = REPO / "verification" / "results" / name / "result.json"
        if not f.exists():
            continue
        res = json.loads(f.read_text())
        verdicts = _bounds.evaluate(run.load(path).BOUNDS, res["metrics"], "full")
        assert verdicts, name
        expected = "bounds_broken" if _bounds.broken(verdicts) else "ok"
        assert res.get("status") == expected, (name, res.get("status"), expected,
                                               [_bounds.describe(v)
                                                for v in _bounds.broken(verdicts)][:5])
