#!/usr/bin/python3
"""Verification harness: runs studies and collects their results.

Usage:
    /usr/bin/python3 verification/run.py [--tier quick|full|ci] [STUDY ...]

Each study is a module ``verification/studies/<name>.py`` that defines

    DESCRIPTION = "one line"
    def run(ctx) -> dict

    BOUNDS = [Bound(metric_regex, "<=" | ">=" | "==", limit, why, tiers=...), ...]

``run`` returns ``{"metrics": {name: number}, "tables": {...}, "figures": [paths],
"notes": "..."}`` (only ``metrics`` is required). ``BOUNDS`` (see studies/_bounds.py) are
the study's acceptance bounds: after the run each is checked against the metrics, the
verdicts go into result.json, and a broken bound (or one that matches no metric) makes the
study fail with status ``bounds_broken`` and the harness exit non-zero naming it. A study
without bounds fails.  The harness writes
``build/verification/<name>/result.json`` (the study's dict plus the tier, the commands
it ran, the software versions and the wall time) and ``build/verification/report.md``
collecting every result present.

Tiers: ``ci`` is the smallest (runs inside the test budget), ``quick`` is minutes,
``full`` is the real resolutions (hours allowed). A full-tier study that finishes is also
kept in ``verification/results/<name>/`` (committed; ``--no-store`` skips it), from which
``verification/publish.py`` writes docs/verification.md.
"""
from __future__ import annotations

import argparse
import importlib.util
import json
import os
import platform
import subprocess
import sys
import time
import traceback
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
STUDIES_DIR = REPO / "verification" / "studies"
sys.path.insert(0, str(STUDIES_DIR))
import _bounds  # noqa: E402
# EFSI_VERIFY_OUT moves the results (the CI test of every study's ci tier writes elsewhere, so
# that it does not overwrite the quick/full results a developer keeps in build/verification).
OUT_ROOT = Path(os.environ.get("EFSI_VERIFY_OUT", REPO / "build" / "verification"))
# Full-tier results that finished are kept here (committed; verification/publish.py builds
# docs/verification.md from them). EFSI_VERIFY_STORE moves it (tests).
STORE_ROOT = Path(os.environ.get("EFSI_VERIFY_STORE", REPO / "verification" / "results"))


class Context:
    """What a study gets: where to write, which tier, and helpers to run the codes."""

    def __init__(self, name: str, tier: str):
        self.name = name
        self.tier = tier
        self.repo = REPO
        self.outdir = OUT_ROOT / name
        self.outdir.mkdir(parents=True, exist_ok=True)
        # EFSI_BIN lets a study run against another build (e.g. a debug build).
        self.efsi = Path(os.environ.get("EFSI_BIN", REPO / "build" / "bin" / "efsi"))
        self.python = "/usr/bin/python3"
        # EFSI_VERIFY_RANKS: MPI ranks for the long cached runs (3D capsules); their results
        # do not depend on it (rank_agreement: 1e-14), their wall time does.
        self.long_ranks = int(os.environ.get("EFSI_VERIFY_RANKS", "1"))
        self.commands: list[str] = []

    def mpi_prefix(self, ranks: int) -> list[str]:
        """mpirun prefix that works as root and when ranks exceed cores."""
        if ranks <= 1:
            return []
        return ["mpirun", "--oversubscribe", "-np", str(ranks)]

    @staticmethod
    def env() -> dict:
        """The environment the studies' commands run in (MPI as root, oversubscription)."""
        env = dict(os.environ)
        env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
        env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        env.setdefault("OMPI_MCA_rmaps_base_oversubscribe", "1")
        # Yield instead of busy-waiting: on a machine shared with other jobs (or with more
        # ranks than cores) busy-polling ranks starve each other (2D capsule d/8, 2 ranks on
        # a loaded 2-core machine: 16.2 s busy-waiting, 5.1 s yielding).
        env.setdefault("OMPI_MCA_mpi_yield_when_idle", "1")
        return env

    def run(self, cmd: list[str], ranks: int = 1, cwd: Path | None = None,
            check: bool = True, timeout: float | None = None) -> subprocess.CompletedProcess:
        """Run a command (under mpirun when ranks > 1), record it, return the result."""
        full = self.mpi_prefix(ranks) + [str(c) for c in cmd]
        self.commands.append(" ".join(full))
        res = subprocess.run(full, cwd=cwd or REPO, env=self.env(), capture_output=True,
                             text=True, timeout=timeout)
        if check and res.returncode != 0:
            raise RuntimeError(f"command failed ({res.returncode}): {' '.join(full)}\n"
                               f"{res.stdout[-3000:]}\n{res.stderr[-3000:]}")
        return res

    def note_kept_run(self, case: str | Path, outdir: Path, sets: dict | None = None,
                      ranks: int = 1) -> None:
        """Record the command of a run taken as made from an earlier study run (cached_run),
        marked so, so that the result names every run it measured."""
        full = self.mpi_prefix(ranks) + [str(c) for c in self.efsi_command(case, outdir, sets)]
        self.commands.append(" ".join(full) + "  # made earlier, taken as made")

    def efsi_command(self, case: str | Path, outdir: Path, sets: dict | None = None,
                     extra: list[str] | None = None) -> list:
        """`efsi run` of a case into outdir with its --set options (no MPI prefix)."""
        cmd = [self.efsi, "run", case, "--output", outdir]
        for k, v in (sets or {}).items():
            cmd += ["--set", f"{k}={v}"]
        return cmd + (extra or [])

    def run_efsi(self, case: str | Path, outdir: Path, sets: dict | None = None,
                 ranks: int = 1, extra: list[str] | None = None,
                 check: bool = True) -> dict | None:
        """Run the C++ solver on a case and return its summary.json as a dict (None when
        an unchecked run wrote none)."""
        self.run(self.efsi_command(case, outdir, sets, extra), ranks=ranks, check=check)
        summary = Path(outdir) / "summary.json"
        return json.loads(summary.read_text()) if summary.exists() else None


def versions() -> dict:
    out = {"python": platform.python_version(), "platform": platform.platform()}
    try:
        out["git"] = subprocess.run(["git", "rev-parse", "HEAD"], cwd=REPO, text=True,
                                    capture_output=True).stdout.strip()
    except OSError:
        pass
    efsi = REPO / "build" / "bin" / "efsi"
    if efsi.exists():
        out["efsi"] = subprocess.run([str(efsi), "--version"], text=True,
                                     capture_output=True).stdout.strip()
    return out


def store_full_result(name: str, result: dict) -> Path:
    """Keep a full-tier result in verification/results/<name>/ (committed): result.json
    with its figures beside it, paths relative to the repository. The full tier takes
    longer than a working session on a 2-core machine, so docs/verification.md is
    assembled from these, each stored at the commit its versions name."""
    import shutil

    dest = STORE_ROOT / name
    if dest.exists():
        shutil.rmtree(dest)
    dest.mkdir(parents=True)
    stored = dict(result)
    stored["figures"] = []
    for fig in result.get("figures", []):
        src = Path(fig)
        if src.exists():
            shutil.copyfile(src, dest / src.name)
            stored["figures"].append(str((dest / src.name).relative_to(REPO)))
    stored["stored"] = time.strftime("%Y-%m-%d")
    (dest / "result.json").write_text(json.dumps(stored, indent=2, default=str) + "\n")
    return dest


def discover() -> dict[str, Path]:
    return {p.stem: p for p in sorted(STUDIES_DIR.glob("*.py")) if not p.stem.startswith("_")}


def load(path: Path):
    sys.path.insert(0, str(STUDIES_DIR))
    spec = importlib.util.spec_from_file_location(f"study_{path.stem}", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def write_report() -> Path:
    lines = ["# Verification report", ""]
    for res_file in sorted(OUT_ROOT.glob("*/result.json")):
        res = json.loads(res_file.read_text())
        name = res_file.parent.name
        lines += [f"## {name}", "", res.get("description", ""), "",
                  f"tier `{res.get('tier')}`, status **{res.get('status')}**, "
                  f"{res.get('wall_seconds', 0):.1f} s", ""]
        if res.get("metrics"):
            lines += ["| metric | value |", "|---|---|"]
            for k, v in res["metrics"].items():
                lines.append(f"| {k} | {v:.6g} |" if isinstance(v, (int, float))
                             else f"| {k} | {v} |")
            lines.append("")
        for fig in res.get("figures", []):
            rel = os.path.relpath(fig, OUT_ROOT)
            lines.append(f"![{name}]({rel})")
        if res.get("notes"):
            lines += ["", res["notes"]]
        if res.get("error"):
            lines += ["", "```", res["error"][-2000:], "```"]
        lines.append("")
    report = OUT_ROOT / "report.md"
    report.write_text("\n".join(lines))
    return report


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("studies", nargs="*", help="study names (default: all)")
    ap.add_argument("--tier", default="quick", choices=["ci", "quick", "full"])
    ap.add_argument("--list", action="store_true", help="list the studies and exit")
    ap.add_argument("--no-store", action="store_true",
                    help="full tier: do not keep the results in verification/results/")
    args = ap.parse_args()

    found = discover()
    if args.list:
        for name, path in found.items():
            print(f"{name:24s} {getattr(load(path), 'DESCRIPTION', '')}")
        return 0
    names = args.studies or list(found)
    unknown = [n for n in names if n not in found]
    if unknown:
        print(f"error: unknown study {unknown}; known: {list(found)}", file=sys.stderr)
        return 2

    failed = []
    for name in names:
        mod = load(found[name])
        ctx = Context(name, args.tier)
        print(f"== study {name} (tier {args.tier})", flush=True)
        t0 = time.time()
        result = {"study": name, "description": getattr(mod, "DESCRIPTION", ""),
                  "tier": args.tier, "loadavg_before": os.getloadavg()}
        try:
            result.update(mod.run(ctx))
            result["status"] = "ok"
        except Exception:  # a study failing must not hide the others
            result["status"] = "failed"
            result["error"] = traceback.format_exc()
            failed.append(name)
            print(result["error"], file=sys.stderr)
        result["wall_seconds"] = time.time() - t0
        result["loadavg_after"] = os.getloadavg()
        result.setdefault("metrics", {})
        if result["status"] == "ok":
            bounds = getattr(mod, "BOUNDS", None)
            if not bounds:
                result["status"] = "failed"
                result["error"] = f"study {name} declares no acceptance bounds (BOUNDS)"
                failed.append(name)
            else:
                result["bounds"] = _bounds.evaluate(bounds, result["metrics"], args.tier)
                bad = _bounds.broken(result["bounds"])
                if bad:
                    result["status"] = "bounds_broken"
                    failed.append(name)
                    for v in bad:
                        print(f"   BOUND BROKEN in {name}: {_bounds.describe(v)}",
                              file=sys.stderr, flush=True)
                else:
                    print(f"   {len(result['bounds'])} bound checks passed", flush=True)
        result["commands"] = ctx.commands
        result["versions"] = versions()
        (ctx.outdir / "result.json").write_text(json.dumps(result, indent=2, default=str))
        for k, v in result["metrics"].items():
            print(f"   {k} = {v}")
        # A full-tier result is kept whether or not it meets its bounds (a result that
        # misses is reported with its numbers); a study that crashed is not.
        if args.tier == "full" and result["status"] in ("ok", "bounds_broken") \
                and not args.no_store:
            print(f"   stored in {store_full_result(name, result)}")
        print(f"   -> {ctx.outdir / 'result.json'} ({result['wall_seconds']:.1f} s)",
              flush=True)
    print(f"report: {write_report()}")
    if failed:
        print(f"failed studies (crashed or broke a bound): {failed}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
