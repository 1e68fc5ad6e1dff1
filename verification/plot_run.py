#!/usr/bin/python3
"""Plot one efsi run: `plot_run.py OUTPUT_DIR` writes OUTPUT_DIR/diagnostics.png, and for a
run with a membrane in simple shear OUTPUT_DIR/capsule.png: the Taylor deformation D and
the inclination against shear-rate x time, with the published curves for the run's
capillary number Ca = mu * shear_rate * a / Es (verification/data/capsule_shear) when there
are some."""
import csv
import sys
import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

REPO = Path(__file__).resolve().parent.parent
DATA = REPO / "verification" / "data" / "capsule_shear"
SOURCES = {"pozrikidis1995": "Pozrikidis 1995 (BEM)",
           "ramanujan_pozrikidis1998": "Ramanujan & Pozrikidis 1998 (BEM)",
           "eggleton_popel1998": "Eggleton & Popel 1998 (IB)"}


def read_csv(path: Path) -> list[dict]:
    with path.open() as f:
        return list(csv.DictReader(f))


def columns(rows: list[dict]) -> dict[str, list]:
    return {k: [float(r[k]) if k != "body" else r[k] for r in rows] for k in rows[0]} if rows else {}


def shear_setup(case: dict):
    """(shear rate, name, radius, Es) of a membrane in a wall-driven shear, or None."""
    b = case.get("boundary", {})
    lo, hi = b.get("y_low", {}), b.get("y_high", {})
    if not isinstance(lo, dict) or not isinstance(hi, dict):
        return None
    ly = case["grid"]["length"][1]
    rate = (hi.get("velocity", [0])[0] - lo.get("velocity", [0])[0]) / ly
    for body in case.get("body", []):
        if body.get("kind") == "membrane" and rate > 0:
            return rate, body["name"], body.get("radius", 0.0), body.get("elastic_modulus", 0.0)
    return None


def reference_curves(ca: float) -> list[tuple[str, list, list]]:
    out = []
    for f in sorted(DATA.glob("*.csv")):
        stem, _, c = f.stem.rpartition("_ca")
        if abs(float(c) - ca) > 1e-9 * ca:
            continue
        pts = sorted(tuple(map(float, line.split(","))) for line in f.read_text().split())
        out.append((SOURCES.get(stem, stem), [p[0] for p in pts], [p[1] for p in pts]))
    return out


def plot_capsule(out: Path, case: dict) -> Path | None:
    setup = shear_setup(case)
    if not setup or not (out / "bodies.csv").exists():
        return None
    rate, name, radius, es = setup
    mu = case["fluid"]["viscosity"]
    ca = mu * rate * radius / es
    rows = [r for r in read_csv(out / "bodies.csv") if r["body"] == name]
    t = [float(r["time"]) * rate for r in rows]
    d = [float(r["taylor_deformation"]) for r in rows]
    th = [float(r["inclination_over_pi"]) for r in rows]
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    n = case["grid"]["cells"][0] * 2 * radius / case["grid"]["length"][0]
    dim = "2D" if case["grid"]["cells"][2] == 1 else "3D"
    for label, x, y in reference_curves(ca):
        ax[0].plot(x, y, "o", ms=3, alpha=0.6, label=label)
    ax[0].plot(t, d, "b-", lw=2, zorder=5, label=f"efsi {dim}, d/{n:.0f}")
    ax[0].set_xlim(0, max(2.0, 1.2 * t[-1]))
    ax[0].plot([0, 0.4], [0, 0.2], "k:", lw=0.8, label="D = t/2 (early time)")
    note = " (published curves are 3D)" if dim == "2D" else ""
    ax[0].set(xlabel="shear rate x t", ylabel="Taylor deformation D",
              title=f"capsule, Ca = {ca:g}{note}")
    ax[0].legend(fontsize=7)
    # The inclination of a sphere is undefined until it has deformed a little.
    shown = [i for i, v in enumerate(d) if v > 0.01]
    ax[1].plot([t[i] for i in shown], [th[i] for i in shown], "b-")
    ax[1].set(xlabel="shear rate x t", ylabel="inclination / pi")
    fig.tight_layout()
    png = out / "capsule.png"
    fig.savefig(png, dpi=110)
    return png


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out = Path(sys.argv[1])
    d = columns(read_csv(out / "diagnostics.csv"))
    if not d:
        print(f"{out}/diagnostics.csv has no rows", file=sys.stderr)
        return 1
    fig, ax = plt.subplots(1, 3, figsize=(13, 3.6))
    ax[0].plot(d["time"], d["kinetic_energy"])
    ax[0].set(xlabel="t [s]", ylabel="kinetic energy [J]")
    ax[1].semilogy(d["time"], [max(v, 1e-300) for v in d["max_divergence"]])
    ax[1].set(xlabel="t [s]", ylabel="max |div v| [1/s]")
    ax[2].plot(d["time"], d["pressure_iterations"], label="pressure")
    ax[2].plot(d["time"], d["viscous_iterations"], label="viscous")
    ax[2].set(xlabel="t [s]", ylabel="solver iterations")
    ax[2].legend()
    fig.tight_layout()
    fig.savefig(out / "diagnostics.png", dpi=110)
    print(f"plot: {out / 'diagnostics.png'}")
    case = tomllib.loads((out / "case.toml").read_text())
    png = plot_capsule(out, case)
    if png:
        print(f"plot: {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
