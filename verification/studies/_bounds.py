"""Acceptance bounds of a study: what its metrics must satisfy for the study to pass.

Each study declares, next to its metrics,

    BOUNDS = [Bound("order_u_L2", ">=", 1.8, "second order in space"), ...]

A bound names its metrics by a regular expression (matched in full against the metric
names, so one bound covers e.g. every `volume_drift_*` of a sweep), a comparison and a
limit, the reason (what the docs promise and why), and the tiers it applies to (default:
all). A bound that applies to a tier but matches no metric of that tier's result is broken
too: a bound must never pass by having nothing to check. A value that is not a finite
number breaks every bound it is compared with.

`verification/run.py` evaluates the bounds after each study, stores the verdicts in
result.json (`bounds`), marks the study `bounds_broken` and exits non-zero naming every
broken bound; `verification/publish.py` shows them in docs/verification.md.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

TIERS = ("ci", "quick", "full")
OPS = {"<=": lambda v, lim: v <= lim, ">=": lambda v, lim: v >= lim,
       "==": lambda v, lim: v == lim}
# "absent": no metric may match (e.g. `unstable_at_t_*`, written only when a run stopped).
ABSENT = "absent"


@dataclass(frozen=True)
class Bound:
    metric: str  # regular expression, matched in full against metric names
    op: str      # "<=", ">=", "==" or "absent"
    limit: float = 0.0
    why: str = ""
    tiers: tuple = field(default=TIERS)

    def __post_init__(self):
        if not self.why:
            raise ValueError(f"bound on {self.metric!r}: say why (what the docs promise)")
        if self.op not in OPS and self.op != ABSENT:
            raise ValueError(f"bound on {self.metric!r}: unknown comparison {self.op!r}")
        bad = [t for t in self.tiers if t not in TIERS]
        if bad:
            raise ValueError(f"bound on {self.metric!r}: unknown tier(s) {bad}")
        re.compile(self.metric)

    def text(self) -> str:
        if self.op == ABSENT:
            return f"no metric {self.metric}"
        return f"{self.metric} {self.op} {self.limit:g}"


def evaluate(bounds: list[Bound], metrics: dict, tier: str) -> list[dict]:
    """One verdict per (bound, matching metric), plus one per bound that matches nothing."""
    verdicts = []
    for b in bounds:
        if tier not in b.tiers:
            continue
        pattern = re.compile(b.metric)
        names = [k for k in metrics if pattern.fullmatch(k)]
        if b.op == ABSENT:
            verdicts += [{"bound": b.text(), "metric": k, "value": metrics[k], "ok": False,
                          "why": b.why, "problem": "present"} for k in names]
            if not names:
                verdicts.append({"bound": b.text(), "metric": None, "value": None, "ok": True,
                                 "why": b.why})
            continue
        if not names:
            verdicts.append({"bound": b.text(), "metric": None, "value": None, "ok": False,
                             "why": b.why, "problem": "no metric of this tier matches"})
            continue
        for k in names:
            v = metrics[k]
            finite = isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
            ok = bool(finite and OPS[b.op](float(v), b.limit))
            verdict = {"bound": b.text(), "metric": k, "value": v, "ok": ok, "why": b.why}
            if not finite:
                verdict["problem"] = "not a finite number"
            verdicts.append(verdict)
    return verdicts


def broken(verdicts: list[dict]) -> list[dict]:
    return [v for v in verdicts if not v["ok"]]


def describe(v: dict) -> str:
    if v.get("problem") == "present":
        return f"{v['metric']} = {v['value']!r} is present: {v['bound']} ({v['why']})"
    if v["metric"] is None:
        return f"{v['bound']}: {v['problem']} ({v['why']})"
    return f"{v['metric']} = {v['value']!r} breaks {v['bound']} ({v['why']})"
