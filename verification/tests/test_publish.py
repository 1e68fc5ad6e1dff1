"""verification/publish.py assembles docs/verification.md from result.json files."""
import json
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def test_publish_writes_sections_and_copies_figures(tmp_path):
    res = tmp_path / "results"
    (res / "alpha").mkdir(parents=True)
    fig = res / "alpha" / "plot.png"
    fig.write_bytes(b"\x89PNG fake")
    (res / "alpha" / "result.json").write_text(json.dumps({
        "description": "a study", "tier": "full", "status": "ok", "wall_seconds": 3.5,
        "metrics": {"error_finest": 1.25e-3, "order": 2.01},
        "tables": {"runs": [{"n": 16, "err": 0.01}, {"n": 32, "err": 0.0025}]},
        "figures": [str(fig)], "notes": "note text", "commands": ["efsi run x"]}))
    (res / "beta").mkdir()
    (res / "beta" / "result.json").write_text(json.dumps({
        "tier": "quick", "status": "failed", "error": "Traceback: boom", "metrics": {}}))
    docs = tmp_path / "docs"
    summary = tmp_path / "summary.md"
    summary.write_text("# Report\n\nintro\n\n## Headline\n\norder {{alpha:order:.2f}}, "
                       "error {{alpha:error_finest:.1e}}\n")
    out = subprocess.run([sys.executable, str(REPO / "verification" / "publish.py"),
                          "--results", str(res), "--docs", str(docs), "--summary", str(summary)],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    page = (docs / "verification.md").read_text()
    assert page.startswith("# Report")
    assert f"order 2.01, error {1.25e-3:.1e}" in page  # headline numbers come from result.json
    assert "### alpha" in page and "### beta" in page
    assert "| error_finest | 0.00125 |" in page and "| order | 2.01 |" in page
    assert "tier `full`, status **ok**" in page and "status **failed**" in page
    assert "Traceback: boom" in page and "efsi run x" in page and "| 32 | 0.0025 |" in page
    assert (docs / "images" / "verification" / "alpha_plot.png").read_bytes() == fig.read_bytes()
    assert "](images/verification/alpha_plot.png)" in page


def test_a_headline_number_without_a_stored_result_is_an_error(tmp_path):
    res = tmp_path / "results" / "alpha"
    res.mkdir(parents=True)
    (res / "result.json").write_text(json.dumps({"tier": "full", "status": "ok",
                                                 "metrics": {"order": 2.0}}))
    summary = tmp_path / "summary.md"
    summary.write_text("# R\n\nerror {{alpha:error_finest}}\n")
    out = subprocess.run([sys.executable, str(REPO / "verification" / "publish.py"),
                          "--results", str(tmp_path / "results"), "--docs", str(tmp_path / "d"),
                          "--summary", str(summary)], capture_output=True, text=True)
    assert out.returncode != 0 and "alpha:error_finest" in (out.stderr + out.stdout)


def test_published_page_is_up_to_date_with_the_stored_results(tmp_path):
    """docs/verification.md is what publish.py makes of the committed results (no number
    typed into it by hand, none left stale)."""
    import shutil
    results = tmp_path / "results"
    shutil.copytree(REPO / "verification" / "results", results)
    out = subprocess.run([sys.executable, str(REPO / "verification" / "publish.py"),
                          "--results", str(results), "--docs", str(tmp_path / "docs")],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    fresh = (tmp_path / "docs" / "verification.md").read_text()
    fresh = fresh.replace(str(results), "verification/results")
    committed = (REPO / "docs" / "verification.md").read_text()
    assert fresh.splitlines()[:60] == committed.splitlines()[:60]
    assert (tmp_path / "docs" / "performance.md").read_text() == \
        (REPO / "docs" / "performance.md").read_text()
    for name in [p.parent.name for p in results.glob("*/result.json")]:
        a = json.loads((results / name / "result.json").read_text())
        b = json.loads((REPO / "verification" / "results" / name / "result.json").read_text())
        assert a["status"] == b["status"] and a.get("bounds") == b.get("bounds"), name


def test_publish_without_results_is_an_error(tmp_path):
    out = subprocess.run([sys.executable, str(REPO / "verification" / "publish.py"),
                          "--results", str(tmp_path / "none"), "--docs", str(tmp_path)],
                         capture_output=True, text=True)
    assert out.returncode != 0 and "make verify-full" in out.stderr
