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
    out = subprocess.run([sys.executable, str(REPO / "verification" / "publish.py"),
                          "--results", str(res), "--docs", str(docs)],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    page = (docs / "verification.md").read_text()
    assert page.startswith((REPO / "verification" / "summary.md").read_text().splitlines()[0])
    assert "### alpha" in page and "### beta" in page
    assert "| error_finest | 0.00125 |" in page and "| order | 2.01 |" in page
    assert "tier `full`, status **ok**" in page and "status **failed**" in page
    assert "Traceback: boom" in page and "efsi run x" in page and "| 32 | 0.0025 |" in page
    assert (docs / "images" / "verification" / "alpha_plot.png").read_bytes() == fig.read_bytes()
    assert "](images/verification/alpha_plot.png)" in page


def test_publish_without_results_is_an_error(tmp_path):
    out = subprocess.run([sys.executable, str(REPO / "verification" / "publish.py"),
                          "--results", str(tmp_path / "none"), "--docs", str(tmp_path)],
                         capture_output=True, text=True)
    assert out.returncode != 0 and "make verify-full" in out.stderr
