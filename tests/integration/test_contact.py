"""Contact between bodies (contact.stiffness, docs/method.md "Contact between bodies"): two
discs pushed together by the converging axis of a 2D Taylor-Green flow (the stagnation
point at (pi, pi): v ~ -U (y - pi)). Their separation is the smallest distance, in cells,
between a cell at least half full of one disc and a cell at least half full of the other
(1: adjacent cells, nothing between them). Without contact the flow squeezes the gap below
a cell and the discs touch (separation <= 1); with the repulsion they keep at least one
cell between them (separation >= 2) to the end. Run on 1 and 2 ranks (the same result)."""
import glob
import math
import os

import h5py
import numpy as np

from efsi_harness import check, parse_args, run

N = 64
CASE = """
[case]
name = "contact"
[grid]
cells = [{n}, {n}, 1]
length = [{L!r}, {L!r}, {h!r}]
[fluid]
density = 1.0
viscosity = 0.01
[initial]
type = "taylor_green"
amplitude = 1.0
[time]
end_time = 4.0
cfl = 0.4
[contact]
stiffness = {k}
[[body]]
name = "a"
shape = "cylinder"
centre = [{c!r}, {ya!r}, 0.0]
radius = 0.4
[[body]]
name = "b"
shape = "cylinder"
centre = [{c!r}, {yb!r}, 0.0]
radius = 0.4
[output]
diagnostics_every = 20
progress_every = 100000
fields_interval = 0.5
"""


def separation(path):
    """min distance (cells) between cells with phi_a >= 1/2 and cells with phi_b >= 1/2."""
    with h5py.File(path, "r") as f:
        a = f["phi_a"][...].reshape(N, N) >= 0.5
        b = f["phi_b"][...].reshape(N, N) >= 0.5
    ia, ib = np.argwhere(a), np.argwhere(b)
    d = np.sqrt(((ia[:, None, :] - ib[None, :, :]) ** 2).sum(axis=2))
    return d.min()


args = parse_args()
L = 2 * math.pi
seps = {}
for k, ranks in ((0.0, 1), (300.0, 1), (300.0, 2)):
    path = os.path.join(args.output, f"contact_{k:g}_np{ranks}.toml")
    with open(path, "w") as f:
        f.write(CASE.format(n=N, L=L, h=L / N, k=k, c=math.pi, ya=math.pi - 0.6,
                            yb=math.pi + 0.6))
    out = os.path.join(args.output, f"k{k:g}_np{ranks}")
    run(args, path, out, ranks=ranks)
    files = sorted(glob.glob(os.path.join(out, "fields", "fields_*.h5")))
    seps[(k, ranks)] = [separation(p) for p in files]
    print(f"stiffness {k:g}, {ranks} rank(s): separation in cells at each snapshot",
          " ".join(f"{s:.2f}" for s in seps[(k, ranks)]))
check(min(seps[(0.0, 1)]) <= 1.0,
      f"without contact the discs touch (min separation {min(seps[(0.0, 1)]):.2f} cells <= 1)")
for ranks in (1, 2):
    s = seps[(300.0, ranks)]
    check(min(s) >= 2.0, f"with contact.stiffness = 300, {ranks} rank(s): at least one cell "
          f"between the discs throughout (min separation {min(s):.2f} cells >= 2)")
check(seps[(300.0, 1)] == seps[(300.0, 2)], "1 and 2 ranks give the same separations")
