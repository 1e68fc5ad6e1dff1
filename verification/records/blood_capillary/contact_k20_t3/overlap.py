"""The overlap of the bodies' sharp equivalents (blood_capillary's max_body_overlap) per
snapshot of a capillary_coarse run, with the pair that sets it. The snapshots (fields/, 1.3
GB for this run) are not kept; rerun the case to regenerate them (README.md):

    /usr/bin/python3 verification/records/blood_capillary/contact_k20_t3/overlap.py RUN_DIR
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "studies"))
import blood_capillary as bc  # noqa: E402


def main(run: Path):
    widths = bc.smoothing_widths(run)
    print("| t [ms] | max_body_overlap | pair |")
    print("|---|---|---|")
    for p in bc.snapshots(run):
        best, pair = bc.worst_pair(p, widths)
        print(f"| {bc.snapshot_time(p):.2f} | {best:.4f} | {', '.join(pair) if pair else '-'} |")


if __name__ == "__main__":
    main(Path(sys.argv[1]))
