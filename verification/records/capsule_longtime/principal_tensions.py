#!/usr/bin/python3
"""Principal tensions of a capsule's membrane from a run's checkpoint: the sign of each
principal tension's law bracket in the band cells near the surface (0.3 < phi < 0.7), from
the eigenvalues lambda_1^2 >= lambda_2^2 of the stored Gs (the third is the normal's, 0).
Skalak: T_1 ~ lambda_1^2 - 1 + C lambda_2^2 (J^2 - 1); neo-Hookean: T_1 ~ lambda_1^2 - 1/J^2
(positive factors dropped). Prints the fraction of cells with a compressed direction.

    /usr/bin/python3 verification/records/capsule_longtime/principal_tensions.py \\
        CHECKPOINT.h5 {skalak C | neo_hookean} [...]

Checkpoints stay in build/ (not recorded); docs/method.md quotes the session-24 figures."""
import sys

import h5py
import numpy as np


def analyse(path: str, law: str, c: float) -> None:
    with h5py.File(path, "r") as f:
        phi = f["body_capsule_phi"][...]
        near = (phi > 0.3) & (phi < 0.7)
        g = {k: f["body_capsule_Gs_" + k][...][near] for k in ("xx", "xy", "xz", "yy", "yz", "zz")}
        t = float(f.attrs["time"])
    m = np.zeros((int(near.sum()), 3, 3))
    m[:, 0, 0], m[:, 1, 1], m[:, 2, 2] = g["xx"], g["yy"], g["zz"]
    m[:, 0, 1] = m[:, 1, 0] = g["xy"]
    m[:, 0, 2] = m[:, 2, 0] = g["xz"]
    m[:, 1, 2] = m[:, 2, 1] = g["yz"]
    ev = np.linalg.eigvalsh(m)
    l1, l2 = ev[:, 2], ev[:, 1]
    j2 = l1 * l2
    if law == "skalak":
        b1, b2 = l1 - 1 + c * l2 * (j2 - 1), l2 - 1 + c * l1 * (j2 - 1)
    else:
        b1, b2 = l1 - 1 / j2, l2 - 1 / j2
    low = np.minimum(b1, b2)
    print(f"{path} t = {t:.2f}: {len(low)} cells, J in [{np.sqrt(j2).min():.4f}, "
          f"{np.sqrt(j2).max():.4f}], compressed direction in {np.mean(low < 0):.1%} of cells "
          f"(least bracket {low.min():+.4f})")


def main(argv: list[str]) -> int:
    i = 0
    while i < len(argv):
        if argv[i + 1] == "skalak":
            analyse(argv[i], "skalak", float(argv[i + 2]))
            i += 3
        else:
            analyse(argv[i], "neo_hookean", 0.0)
            i += 2
    return 0 if argv else 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
