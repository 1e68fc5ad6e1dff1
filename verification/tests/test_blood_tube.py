"""blood_capillary's single-cell measures (rbc_in_tube) on synthetic fields: the cell's
length along the axis and its diameter from phi >= 1/2, also for a cell that straddles the
periodic end of the box, and the cell's velocity ratio from bodies.csv and the flow rate."""
import csv
import math
import sys
from pathlib import Path

import h5py
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "studies"))
import blood_capillary as bc  # noqa: E402

H = 0.25
NX, NY = 96, 48


def write_fields(path, centre_x, half_length, radius, time, u=1.0):
    """A cylinder of the given half-length and radius on the tube's axis (phi 1 inside, 0
    outside), a uniform axial velocity u in the lumen."""
    x = (np.arange(NX) + 0.5) * H
    yz = (np.arange(NY) + 0.5) * H
    z, y, xx = np.meshgrid(yz, yz, x, indexing="ij")
    dx = (xx - centre_x + bc.TUBE_LENGTH / 2) % bc.TUBE_LENGTH - bc.TUBE_LENGTH / 2
    r = np.hypot(y - bc.TUBE_AXIS, z - bc.TUBE_AXIS)
    phi = ((np.abs(dx) < half_length) & (r < radius)).astype(float)
    faces_u = np.where(r < bc.TUBE_R, u, 0.0)
    with h5py.File(path, "w") as f:
        f["faces_u"] = faces_u
        f["phi_rbc"] = phi.ravel()
        f.attrs["time"] = time


def test_shape_of_a_cell_inside_the_box_and_across_its_periodic_end(tmp_path):
    for centre in (12.0, 0.5, 23.9):
        p = tmp_path / f"fields_{centre}.h5"
        write_fields(p, centre, half_length=3.0, radius=3.6, time=0.0)
        length, diameter = bc.tube_shape(p, H)
        assert abs(length - 6.0) <= H, (centre, length)
        # The largest cell-centre radius inside a radius of 3.6 on a 0.25 grid.
        assert 2 * (3.6 - H * math.sqrt(2)) <= diameter < 7.2, (centre, diameter)


def test_velocity_ratio_from_the_centroid_and_the_flow_rate(tmp_path):
    out = tmp_path / "run"
    (out / "fields").mkdir(parents=True)
    v_cell, t_end = 1.5, 4.0
    with open(out / "bodies.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["step", "time", "body", "volume", "centroid_x", "area", "reference_area",
                    "tensor_trace_max"])
        for k, t in enumerate(np.linspace(0, t_end, 41)):
            x = (8.0 + v_cell * t) % bc.TUBE_LENGTH  # wraps past the periodic end
            w.writerow([k, t, "rbc", 94.0, x, 135.0, 135.0 * 1.01, 2.0])
    for k, t in enumerate((0.0, 2.0, 3.5, 4.0)):
        write_fields(out / "fields" / f"fields_{k:08d}.h5", 8.0 + v_cell * t, 3.0, 3.6, t)
    m, _ = bc.tube_metrics(out, {"time": t_end, "status": "completed"}, H)
    # The mean velocity is the lumen's u = 1 over the cells inside r < 5 (the grid's disc),
    # divided by the exact lumen area.
    nyz = (np.arange(NY) + 0.5) * H
    zz, yy = np.meshgrid(nyz, nyz, indexing="ij")
    disc = np.count_nonzero(np.hypot(yy - bc.TUBE_AXIS, zz - bc.TUBE_AXIS) < bc.TUBE_R) * H * H
    v_mean = disc / (math.pi * bc.TUBE_R ** 2)
    assert abs(m["rbc_in_tube_cell_velocity_um_per_ms"] - v_cell) < 1e-9
    assert abs(m["rbc_in_tube_velocity_ratio"] - v_cell / v_mean) < 1e-9
    assert abs(m["rbc_in_tube_reference_area_drift_max"] - 0.01) < 1e-12
    assert m["reached_end_tube"] == 1 and m["rbc_in_tube_volume_drift"] == 0.0
    assert abs(m["rbc_in_tube_length_um"] - 6.0) <= H


def test_cell_free_layer_beside_the_published_widths():
    """Each published width gives one metric, the measured width minus it."""
    m = bc.cell_free_layer_comparison(3.0)
    assert set(m) == {f"cell_free_layer_minus_{k}_um" for k in bc.CELL_FREE_LAYER_PUBLISHED}
    for k, v in bc.CELL_FREE_LAYER_PUBLISHED.items():
        assert math.isclose(m[f"cell_free_layer_minus_{k}_um"], 3.0 - v)
    assert all(math.isnan(v) for v in bc.cell_free_layer_comparison(float("nan")).values())
