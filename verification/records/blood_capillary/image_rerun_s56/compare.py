"""blood_capillary's full tier before and after session 55's shapes drawn at their nearest
periodic images (and patches across the seam): the stored result.json of commit 7b05057
(made before that change) against the one stored now. Writes result.md beside this file.

    /usr/bin/python3 verification/records/blood_capillary/image_rerun_s56/compare.py [--print]
"""
import json
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[3]
RESULT = "verification/results/blood_capillary/result.json"
BEFORE = "7b05057"


def load_before():
    text = subprocess.run(["git", "show", f"{BEFORE}:{RESULT}"], cwd=REPO, text=True,
                          capture_output=True, check=True).stdout
    return json.loads(text)


def main():
    old, new = load_before(), json.loads((REPO / RESULT).read_text())
    rows = []
    for k, v in new["metrics"].items():
        if k not in old["metrics"] or not isinstance(v, (int, float)):
            continue
        a = old["metrics"][k]
        rel = abs(v - a) / abs(a) if a else abs(v - a)  # absolute where before is 0
        rows.append((k, a, v, rel))
    lines = ["# blood_capillary's full tier before and after the shapes at their nearest images",
             "", f"Made by `compare.py` (this folder): result.json of {BEFORE} "
             f"(efsi {old['versions']['efsi']}) against the stored one "
             f"(efsi {new['versions']['efsi']}, stored {new.get('stored')}).", "",
             "| metric | before | after | relative change (absolute where before is 0) |", "|---|---|---|---|"]
    lines += [f"| {k} | {a:.6g} | {v:.6g} | {r:.2e} |" for k, a, v, r in rows]
    physics = [r for k, _, _, r in rows
               if not k.startswith(("rate_", "seconds_per_ms"))]
    lines += ["", f"Largest relative change outside the timing and memory rates: "
              f"{max(physics):.2e} (over {len(physics)} metrics).", ""]
    lines += ["Runs (wall seconds, before / after; the plasma runs, which no change since "
              "touched, show how much faster the machine ran):", ""]
    before = {r["run"]: r for r in old["tables"]["runs"]}
    for r in new["tables"]["runs"]:
        b = before.get(r["run"], {})
        lines.append(f"- {r['run']}: {b.get('wall [s]')} / {r['wall [s]']} s "
                     f"(load before {b.get('load before')} / {r['load before']})")
    text = "\n".join(lines) + "\n"
    (HERE / "result.md").write_text(text)
    if "--print" in sys.argv:
        print(text)


if __name__ == "__main__":
    main()
