#!/usr/bin/python3
"""Commit-ready record of completed long runs (verification/records/<study>/<key>/).

    /usr/bin/python3 verification/record.py build/verification/capsule_shear/runs/3d_n32_ca0.0125_t2 [...]

Copies the run's small files (bodies.csv, diagnostics.csv, adhesion.csv, summary.json, case.toml; no
fields, no checkpoint) and writes record.json: the commit the solver was built from (from
the run's summary.json), its rank count and machine load, the repository's HEAD when the
record was made, the efsi version and the date. A study run with
EFSI_VERIFY_RECORDS=1 takes a run missing from build/verification from its record
(studies/_flowio.py). Only finished runs are recorded: completed, or stopped UNSTABLE
(a result too: the study reports where it stopped).
"""
import datetime
import json
import shutil
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent / "studies"))
from _flowio import RECORD_FILES, record_dir, run_finished  # noqa: E402

REPO = Path(__file__).resolve().parents[1]


def main(argv: list[str]) -> int:
    if not argv:
        print(__doc__)
        return 2
    for arg in argv:
        out = Path(arg).resolve()
        if not run_finished(out, None, allow_unstable=True):
            print(f"{out}: not a finished run (summary.json status completed or unstable), "
                  "not recorded")
            return 1
        rec = record_dir(out)
        rec.mkdir(parents=True, exist_ok=True)
        for name in RECORD_FILES:
            if name != "record.json" and (out / name).exists():
                shutil.copy2(out / name, rec / name)
        efsi = REPO / "build" / "bin" / "efsi"
        summary = json.loads((out / "summary.json").read_text())
        meta = {
            # the commit the solver that made the run was built from (summary.json); runs
            # made before builds were stamped have none
            "efsi_commit": summary.get("efsi_commit", "unknown (run predates build stamping)"),
            "ranks": summary.get("ranks"),
            "load_before": summary.get("load_before"),
            "load_after": summary.get("load_after"),
            "git_at_record": subprocess.run(["git", "rev-parse", "HEAD"], cwd=REPO, text=True,
                                  capture_output=True).stdout.strip(),
            "efsi": subprocess.run([str(efsi), "--version"], text=True,
                                   capture_output=True).stdout.strip() if efsi.exists() else "",
            "date": datetime.date.today().isoformat(),
            "source": str(out.relative_to(REPO)) if out.is_relative_to(REPO) else str(out),
        }
        (rec / "record.json").write_text(json.dumps(meta, indent=1) + "\n")
        print(f"recorded {out.name} -> {rec.relative_to(REPO)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
