"""Publish the verification results as docs/verification.md (+ docs/images/verification/).

    /usr/bin/python3 verification/publish.py [--results verification/results] [--docs docs]

Writes docs/verification.md from verification/summary.md (the hand-kept headline table:
what each check compares, the measured figure, the command), a generated status (which
studies have a stored full-tier result, and which do not yet), and one section per study
generated from its result.json (tier, status, run time, the commit and date it ran at,
every metric, tables, notes, the commands that produced it), and copies each study's
figures to docs/images/verification/<study>_<figure>. `make verify-full` calls it after
the studies; the results are the full-tier ones `verification/run.py --tier full` keeps in
verification/results/ (committed), so the page can be assembled study by study.
"""
from __future__ import annotations

import argparse
import json
import re
import shutil
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO / "verification"))
sys.path.insert(0, str(REPO / "verification" / "studies"))
import _bounds  # noqa: E402
import run as harness  # noqa: E402

# {{study:metric}} or {{study:metric:.3g}} in summary.md is replaced by the stored value.
# {{table:study:name}} is replaced by the stored table, {{notes:study}} by the notes.
TABLE = re.compile(r"\{\{table:([a-z0-9_]+):([A-Za-z0-9_]+)\}\}")
NOTES = re.compile(r"\{\{notes:([a-z0-9_]+)\}\}")
PLACEHOLDER = re.compile(r"\{\{([a-z0-9_]+):([A-Za-z0-9_.+-]+?)(?::([^}]+))?\}\}")


def fmt(v) -> str:
    if isinstance(v, bool):
        return str(v)
    if isinstance(v, (int, float)):
        return f"{v:.6g}"
    return str(v)


def table(rows: list[dict], limit: int = 40) -> list[str]:
    if not rows or not isinstance(rows, list) or not isinstance(rows[0], dict):
        return []
    cols = list(dict.fromkeys(k for r in rows for k in r
                              if not isinstance(r[k], (dict, list))))[:14]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for r in rows[:limit]:
        out.append("| " + " | ".join(fmt(r.get(c, "")).replace("|", "/")[:60]
                                    for c in cols) + " |")
    if len(rows) > limit:
        out.append(f"| ... {len(rows) - limit} more rows in result.json |")
    return out


def section(res: dict, name: str, images: Path, rel: str) -> list[str]:
    ver = res.get("versions") or {}
    when = f", commit {ver['git'][:10]}" if ver.get("git") else ""
    when += f", {res['stored']}" if res.get("stored") else ""
    lines = [f"### {name}", "", res.get("description", ""), "",
             f"tier `{res.get('tier')}`, status **{res.get('status')}**, "
             f"{res.get('wall_seconds', 0):.1f} s{when}", ""]
    if res.get("bounds"):
        bad = _bounds.broken(res["bounds"])
        lines += [f"Acceptance bounds: {len(res['bounds']) - len(bad)} of {len(res['bounds'])} "
                  "checks met" + (", **broken:**" if bad else "."), ""]
        lines += [f"- {_bounds.describe(v)}" for v in bad]
        lines.append("")
    if res.get("metrics"):
        lines += ["| metric | value |", "|---|---|"]
        lines += [f"| {k} | {fmt(v)} |" for k, v in res["metrics"].items()]
        lines.append("")
    for fig in res.get("figures", []):
        src = Path(fig) if Path(fig).is_absolute() else REPO / fig
        if src.exists():
            dst = images / f"{name}_{src.name}"
            shutil.copyfile(src, dst)
            lines += [f"![{name}: {src.stem}]({rel}/{dst.name})", ""]
    if res.get("notes"):
        lines += [res["notes"], ""]
    for tname, rows in (res.get("tables") or {}).items():
        t = table(rows)
        if t:
            lines += [f"<details><summary>table {tname}</summary>", "", *t, "", "</details>", ""]
    if res.get("error"):
        lines += ["```", res["error"][-1500:], "```", ""]
    cmds = res.get("commands") or []
    if cmds:
        lines += ["<details><summary>commands</summary>", "", "```"]
        lines += [c for c in cmds[:30]] + ([f"... {len(cmds) - 30} more"] if len(cmds) > 30 else [])
        lines += ["```", "", "</details>", ""]
    return lines


def status(results: Path, found: list[Path]) -> list[str]:
    """Which studies have a full-tier result, which do not (yet), which are incomplete."""
    studies = sorted(p.stem for p in (REPO / "verification" / "studies").glob("*.py")
                     if not p.stem.startswith("_"))
    have = {f.parent.name: json.loads(f.read_text()) for f in found}
    full = [s for s in studies if s in have and have[s].get("tier") == "full"
            and have[s].get("status") in ("ok", "bounds_broken")]
    partial = [s for s in full if have[s].get("tables", {}).get("not_run")]
    missing = [s for s in studies if s not in full]
    if not missing and not partial:
        head = f"**Status: complete.** Every study ({len(studies)}) has a full-tier result."
    else:
        head = (f"**Status: partial.** {len(full)} of {len(studies)} studies have a full-tier "
                "result" + (f"; not yet: {', '.join(missing)}" if missing else "") +
                (f"; with runs still missing (their `not_run` table): {', '.join(partial)}"
                 if partial else "") + ".")
    return ["## Status", "", head, "",
            f"Generated by `verification/publish.py` from `{rel_to_repo(results)}/*/result.json`"
            " (kept by `verification/run.py --tier full`); each section below names its tier, "
            "the commit it ran at and the date.", ""]


def recheck(found: list[Path]) -> dict[str, dict]:
    """Evaluate each stored result against its study's current BOUNDS (bounds may be
    declared or changed after a result was kept) and store the verdicts and the status."""
    studies = harness.discover()
    out = {}
    for f in found:
        res = json.loads(f.read_text())
        name = f.parent.name
        if name in studies and res.get("status") in ("ok", "bounds_broken"):
            bounds = getattr(harness.load(studies[name]), "BOUNDS", None) or []
            res["bounds"] = _bounds.evaluate(bounds, res.get("metrics", {}), res.get("tier"))
            res["status"] = "bounds_broken" if _bounds.broken(res["bounds"]) else "ok"
            f.write_text(json.dumps(res, indent=2, default=str) + "\n")
        out[name] = res
    return out


def bounds_table(results: dict[str, dict]) -> list[str]:
    """The headline table: every acceptance bound with the measured value that decides it
    (the worst over the metrics it covers), generated from the stored results."""
    lines = ["## Acceptance bounds (generated from result.json)", "",
             "Every study declares its bounds next to its metrics (`BOUNDS` in "
             "`verification/studies/<study>.py`); `make verify` fails naming each broken one. "
             "Below: each bound of the full tier, the measured value that decides it (the worst "
             "of the metrics it covers) and the verdict.", "",
             "| study | bound | measured (worst) | met | why |", "|---|---|---|---|---|"]
    for name, res in sorted(results.items()):
        groups: dict[str, list] = {}
        for v in res.get("bounds") or []:
            groups.setdefault(v["bound"], []).append(v)
        for bound, vs in groups.items():
            bad = [v for v in vs if not v["ok"]]
            worst = (bad or vs)[0]
            if not bad and worst["metric"] is not None:
                op = bound.split()[-2] if len(bound.split()) >= 3 else ""
                nums = [v for v in vs if isinstance(v["value"], (int, float))]
                if nums and op in ("<=", ">="):
                    worst = (max if op == "<=" else min)(nums, key=lambda v: v["value"])
            shown = ("(none)" if worst["metric"] is None
                     else f"{worst['metric']} = {fmt(worst['value'])}")
            n = f" ({len(vs)} metrics)" if len(vs) > 1 else ""
            lines.append(f"| {name} | `{bound.replace('|', '&#124;')}` | {shown}{n} | "
                         f"{'yes' if not bad else '**NO**'} | {worst['why']} |")
    return lines + [""]


def fill(text: str, results: dict[str, dict]) -> str:
    """Replace {{study:metric[:format]}} by the stored value; a study without a stored result
    reads "(no full-tier result yet)"; a metric its stored result lacks is an error."""
    def value(m):
        study, metric, spec = m.group(1), m.group(2), m.group(3) or ".3g"
        if study not in results:
            return "(no full-tier result yet)"
        try:
            v = results[study]["metrics"][metric]
        except KeyError:
            raise SystemExit(f"summary.md names {{{{{study}:{metric}}}}}, "
                             "which no stored result has")
        return format(v, spec) if isinstance(v, (int, float)) else str(v)
    def table_of(m):
        res = results.get(m.group(1))
        if res is None:
            return "(no full-tier result yet)"
        rows = (res.get("tables") or {}).get(m.group(2))
        if not rows:
            raise SystemExit(f"a page names the table {m.group(0)}, which the stored result lacks")
        return "\n".join(table(rows, limit=60))

    def notes_of(m):
        res = results.get(m.group(1))
        return res.get("notes", "") if res else "(no full-tier result yet)"

    text = TABLE.sub(table_of, text)
    text = NOTES.sub(notes_of, text)
    return PLACEHOLDER.sub(value, text)


def rel_to_repo(p: Path) -> str:
    p = p.resolve()
    return str(p.relative_to(REPO)) if p.is_relative_to(REPO) else str(p)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--results", default=str(REPO / "verification" / "results"))
    ap.add_argument("--docs", default=str(REPO / "docs"))
    ap.add_argument("--summary", default=str(REPO / "verification" / "summary.md"),
                    help="the hand-written text with {{study:metric}} placeholders")
    ap.add_argument("--performance", default=str(REPO / "verification" / "performance.md"),
                    help="the text of docs/performance.md, with placeholders")
    args = ap.parse_args()
    results, docs = Path(args.results), Path(args.docs)
    images = docs / "images" / "verification"
    images.mkdir(parents=True, exist_ok=True)
    found = sorted(results.glob("*/result.json"))
    if not found:
        raise SystemExit(f"no results under {results}: run `make verify-full` first")
    stored = recheck(found)
    summary = fill(Path(args.summary).read_text(), stored)
    # The status goes after the summary's introduction, before its first section.
    cut = summary.find("\n## ")
    intro, rest = (summary, "") if cut < 0 else (summary[:cut], summary[cut + 1:])
    lines = [intro.rstrip(), "", *status(results, found), *bounds_table(stored), rest.rstrip(), "",
             "## Study by study (generated from result.json)", ""]
    for f in found:
        lines += section(json.loads(f.read_text()), f.parent.name, images, "images/verification")
    (docs / "verification.md").write_text("\n".join(lines) + "\n")
    print(f"wrote {docs / 'verification.md'} ({len(found)} studies)")
    perf = Path(args.performance)
    if perf.exists():
        (docs / "performance.md").write_text(fill(perf.read_text(), stored).rstrip() + "\n")
        print(f"wrote {docs / 'performance.md'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
