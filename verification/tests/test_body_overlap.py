"""blood_capillary's body overlap measure on synthetic fields: a sharp slab (the wall) and a
smoothed slab (a red cell's tanh profile, eps = 1 cell) a gap g apart along x. The stored
profiles 'overlap' at any gap (the smoothed tail inside the sharp body: per unit area
(eps / 2) ln(1 + exp(-2 g / eps)) in the continuum); the sharp equivalents do not, and a
real interpenetration of depth d counts d per unit area in both measures' sharp form."""
import math
import sys
from pathlib import Path

import h5py
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "studies"))
import blood_capillary as bc  # noqa: E402

NX, NY, NZ = 80, 4, 4
WALL_END = 20.0  # the sharp slab fills x < 20 cells
CELL_END = 60.0  # the smoothed slab's far surface


def write_case(tmp_path, gap: float, eps: float = 1.0) -> Path:
    x = np.arange(NX) + 0.5
    wall = (x < WALL_END).astype(float)
    near = WALL_END + gap
    dist = np.maximum(near - x, x - CELL_END)  # signed distance to the slab [near, CELL_END]
    cell = 0.5 * (1.0 - np.tanh(dist / eps))
    shape = (NZ, NY, NX)
    run = tmp_path / f"gap{gap}_eps{eps}"
    (run / "fields").mkdir(parents=True)
    with h5py.File(run / "fields" / "fields_00000000.h5", "w") as f:
        f["phi_wall"] = np.broadcast_to(wall, shape).ravel()
        f["phi_rbc_0"] = np.broadcast_to(cell, shape).ravel()
        f.attrs["time"] = 0.0
    (run / "case.toml").write_text(
        "[[body]]\nname = 'wall'\nkind = 'solid'\n\n"
        f"[[body]]\nname = 'rbc_0'\nkind = 'membrane'\ninterface = 'smoothed'\n"
        f"smoothing_width = {eps}\n")
    return run


def test_smoothed_widths_read_from_the_run(tmp_path):
    run = write_case(tmp_path, 1.0, eps=0.75)
    assert bc.smoothing_widths(run) == {"rbc_0": 0.75}


def test_sharp_equivalent_keeps_the_volume(tmp_path):
    run = write_case(tmp_path, 1.0)
    with h5py.File(run / "fields" / "fields_00000000.h5", "r") as f:
        sharp = bc.sharp_fraction(f["phi_rbc_0"][...], 1.0)
    # the slab [21, 60] is 39 cells long, NY * NZ cells across
    assert abs(sharp.sum() / (NY * NZ) - (CELL_END - WALL_END - 1.0)) < 1e-9


def test_profiles_overlap_at_a_gap_sharp_equivalents_do_not(tmp_path):
    # eps = 1 cell (the red cells' width): a gap of a third of a cell and of one cell
    for gap in (0.3, 1.0):
        run = write_case(tmp_path, gap)
        snap = run / "fields" / "fields_00000000.h5"
        assert bc.overlap(snap) > 1e-3
        assert bc.overlap(snap, bc.smoothing_widths(run)) == 0.0
    # a resolved profile (eps = 4 cells) against the continuum's tail inside the wall, per
    # unit area, over the smaller body (the wall)
    eps = 4.0
    for gap in (1.2, 4.0):
        run = write_case(tmp_path, gap, eps)
        stored = bc.overlap(run / "fields" / "fields_00000000.h5")
        tail = 0.5 * eps * math.log(1.0 + math.exp(-2.0 * gap / eps)) / WALL_END
        assert abs(stored / tail - 1.0) < 0.02  # the cell-centre sum: 0.6 and 0.9 % here


def test_sharp_equivalents_count_a_real_interpenetration(tmp_path):
    depth = 1.5
    run = write_case(tmp_path, -depth)
    got = bc.overlap(run / "fields" / "fields_00000000.h5", bc.smoothing_widths(run))
    assert abs(got - depth / WALL_END) < 1e-9
