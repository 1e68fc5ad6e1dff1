"""The blood scene's cell-free layer beside the published widths (session 55).

The blood_capillary study measures the layer (`cell_free_layer_um`) from field snapshots,
which the records do not keep; its stored result (verification/results/blood_capillary,
full tier) predates the published widths the study now sets beside it
(CELL_FREE_LAYER_PUBLISHED in verification/studies/_blood_references.py, with their sources).
This applies the study's own comparison to the stored width and writes result.md beside
this file (or prints it with --print); the study's next full run puts the same metrics in
its result.

    /usr/bin/python3 verification/records/blood_capillary/cfl_published_s55/compare.py
"""
import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[3]
sys.path.insert(0, str(REPO / "verification" / "studies"))
import blood_capillary as bc  # noqa: E402

RESULT = REPO / "verification" / "results" / "blood_capillary" / "result.json"


def main(argv: list[str]) -> int:
    result = json.loads(RESULT.read_text())
    m = result["metrics"]
    width = m["cell_free_layer_um"]
    rows = ["| published width | value [um] | efsi minus it [um] |", "|---|---|---|"]
    for key, diff in bc.cell_free_layer_comparison(width).items():
        name = key.removeprefix("cell_free_layer_minus_").removesuffix("_um")
        rows.append(f"| {name} | {bc.CELL_FREE_LAYER_PUBLISHED[name]:g} | {diff:+.2f} |")
    text = "\n".join([
        "# The capillary's cell-free layer beside published widths",
        "",
        f"Made by `compare.py` (this folder) from `{RESULT.relative_to(REPO)}` "
        f"(tier {result['tier']}): efsi's layer {width:.2f} um, at tube Ht "
        f"{m['achieved_ht']:.3f} in the 20 um tube of cases/capillary_coarse (h = 0.34375 um). "
        "The published widths are in-vivo, rat cremaster arterioles of 20-40 um (30-40 um for "
        "the exclusion zone) at a systemic Ht of 20 %; their sources are in "
        "CELL_FREE_LAYER_PUBLISHED (verification/studies/_blood_references.py). The mean layer "
        "is the comparable measure; the exclusion zone is the gap to the cells nearest the "
        "wall, so a mean layer lies above it. Not a like-for-like comparison: in vivo the "
        "vessels are wider, the wall carries an endothelial surface layer, and a systemic Ht "
        "of 20 % is a higher Ht than a 20 um tube holds (Fahraeus effect).",
        "",
        *rows,
        "",
    ])
    if "--print" in argv:
        print(text)
    else:
        (HERE / "result.md").write_text(text)
        print(f"wrote {(HERE / 'result.md').relative_to(REPO)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
