#!/usr/bin/python3
"""Plot the diagnostics of one efsi run: `plot_run.py OUTPUT_DIR` writes OUTPUT_DIR/diagnostics.png."""
import csv
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv(path: Path) -> dict[str, list[float]]:
    with path.open() as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]} if rows else {}


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out = Path(sys.argv[1])
    d = read_csv(out / "diagnostics.csv")
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
    return 0


if __name__ == "__main__":
    sys.exit(main())
