"""The cross-code comparison machinery (verification/studies/_meshcompare.py) on analytic
fields: meshio reading of the C++-style and DOLFINx XDMF files, interpolation to common
points, the band-force line and smoothed tractions, and the FE script's point probe.
Every check compares against a closed form, so a wrong reader, ordering or interpolation
fails here before it can produce a plausible-looking cross-code number."""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "verification" / "studies"))

import _meshcompare as mc  # noqa: E402

EFSI = Path(os.environ.get("EFSI_BIN", REPO / "build" / "bin" / "efsi"))


def write_quad_series(path, nx, ny, L, fields_at, times):
    """A C++-style file: quadrilaterals, cell data, one temporal collection (meshio)."""
    import meshio
    xs, ys = np.linspace(0, L[0], nx + 1), np.linspace(0, L[1], ny + 1)
    X, Y = np.meshgrid(xs, ys)
    nodes = np.c_[X.ravel(), Y.ravel(), np.zeros(X.size)]
    ii, jj = np.meshgrid(np.arange(nx), np.arange(ny))
    n0 = (jj * (nx + 1) + ii).ravel()
    quads = np.c_[n0, n0 + 1, n0 + nx + 2, n0 + nx + 1]
    centres = nodes[quads].mean(axis=1)
    # shuffle the cells: the readers must not rely on x-fastest order
    perm = np.random.default_rng(0).permutation(len(quads))
    quads, centres = quads[perm], centres[perm]
    cwd = os.getcwd()
    os.chdir(path.parent)                     # meshio 5.0 writes the .h5 into the cwd
    try:
        with meshio.xdmf.TimeSeriesWriter(path.name) as w:
            w.write_points_cells(nodes, [("quad", quads)])
            for t in times:
                w.write_data(t, cell_data={k: [v] for k, v in fields_at(centres, t).items()})
    finally:
        os.chdir(cwd)
    return centres


def test_quad_series_read_centres_times_and_grid_interpolation(tmp_path):
    f = lambda c, t: {"p": 2 * c[:, 0] - 3 * c[:, 1] + t,  # noqa: E731
                      "velocity": np.c_[c[:, 1], -c[:, 0], 0 * c[:, 0]]}
    centres = write_quad_series(tmp_path / "s.xdmf", 16, 8, (2.0, 1.0), f, [0.0, 0.5, 1.0])
    pts, cells, steps = mc.read_series(tmp_path / "s.xdmf")
    xc = mc.cell_centres(pts, cells)
    assert np.abs(xc - centres).max() < 1e-14
    assert [s[0] for s in steps] == [0.0, 0.5, 1.0]
    (t, _, cd), dt = mc.at_time(steps, 0.52)
    assert t == 0.5 and abs(dt - 0.02) < 1e-12
    p = mc.cell_field(cd, "p")
    assert np.abs(p - (2 * xc[:, 0] - 3 * xc[:, 1] + 0.5)).max() < 1e-13
    grid = mc.CellGrid(xc, 2)
    assert grid.shape == (1, 8, 16) and abs(grid.h[0] - 0.125) < 1e-14
    arr = grid.reshape(p)                     # [nz][ny][nx], x fastest
    assert arr[0, 3, 5] == pytest.approx(2 * (5.5 * 0.125) - 3 * (3.5 * 0.125) + 0.5)
    q = np.random.default_rng(1).uniform([0.1, 0.1], [1.9, 0.9], size=(200, 2))
    vals = grid.interpolator(p)(q)            # linear field: bilinear interpolation exact
    assert np.abs(vals - (2 * q[:, 0] - 3 * q[:, 1] + 0.5)).max() < 1e-12
    assert np.isnan(grid.interpolator(p)(np.array([[2.5, 0.5]]))).all()


def test_cell_grid_3d_trilinear_is_second_order():
    errs = []
    for n in (8, 16):
        ax = (np.arange(n) + 0.5) / n
        Z, Y, X = np.meshgrid(ax, ax, ax, indexing="ij")
        c = np.c_[X.ravel(), Y.ravel(), Z.ravel()][::-1]          # reversed order
        g = mc.CellGrid(c, 3)
        f = np.c_[c[:, 0] ** 2, c[:, 1] * c[:, 2]]
        q = np.random.default_rng(2).uniform(0.1, 0.9, size=(300, 3))
        e = g.interpolator(f)(q) - np.c_[q[:, 0] ** 2, q[:, 1] * q[:, 2]]
        errs.append(np.abs(e).max())
    assert errs[1] < errs[0] / 3.2, errs               # order 2: ratio 4


def test_dolfinx_xdmf_read_and_p1_interpolation(tmp_path):
    from mpi4py import MPI
    import dolfinx
    import dolfinx.io

    errs = []
    for n in (8, 16):
        mesh = dolfinx.mesh.create_rectangle(MPI.COMM_SELF, [np.array([-1.0, -0.5]),
                                                             np.array([1.0, 0.5])], [2 * n, n])
        V = dolfinx.fem.FunctionSpace(mesh, ("Lagrange", 1))
        lin = dolfinx.fem.Function(V, name="lin")
        lin.interpolate(lambda x: 2 * x[0] - 3 * x[1] + 1)
        quad = dolfinx.fem.Function(V, name="quad")
        quad.interpolate(lambda x: x[0] ** 2 + x[0] * x[1])
        for f in (lin, quad):
            with dolfinx.io.XDMFFile(MPI.COMM_SELF, str(tmp_path / f"{f.name}{n}.xdmf"), "w") as xf:
                xf.write_mesh(mesh)
                xf.write_function(f, 0.0)
                xf.write_function(f, 1.0)
        q = np.random.default_rng(3).uniform([-0.95, -0.45], [0.95, 0.45], size=(300, 2))
        pts, cells, steps = mc.read_series(tmp_path / f"lin{n}.xdmf")
        assert [s[0] for s in steps] == [0.0, 1.0]
        interp = mc.P1Interpolant(pts, cells[0].data)
        v = interp(steps[1][1]["lin"], q[:, 0], q[:, 1])
        assert np.abs(v - (2 * q[:, 0] - 3 * q[:, 1] + 1)).max() < 1e-12
        assert np.isnan(interp(steps[1][1]["lin"], np.array([1.5]), np.array([0.0]))).all()
        pts, cells, steps = mc.read_series(tmp_path / f"quad{n}.xdmf")
        interp = mc.P1Interpolant(pts, cells[0].data)
        v = interp(steps[0][1]["quad"], q[:, 0], q[:, 1])
        errs.append(np.abs(v - (q[:, 0] ** 2 + q[:, 0] * q[:, 1])).max())
    assert errs[1] < errs[0] / 3.0, errs                 # P1 interpolation: order 2


def test_norms_and_surface_weights():
    sys.path.insert(0, str(REPO / "reference"))
    import meshio
    import surface_meshes as sm

    assert mc.rel_l2(np.array([[3.0, 4.0]]), np.array([[0.0, 10.0]])) == pytest.approx(0.5)
    assert mc.rel_l1(np.array([1.0, -1.0]), np.array([2.0, 2.0]), np.array([1.0, 3.0])) == \
        pytest.approx(0.5)
    for degree, ctype, tol in ((1, "triangle", 0.02), (2, "triangle6", 0.01)):
        nodes, cells, _ = sm.closed_surface("sphere", 3, degree, {"R0": 0.5})
        if degree == 2:                                     # DOLFINx -> VTK node order
            cells = cells[:, [0, 1, 2, 5, 3, 4]]
        w = mc.lumped_node_areas(nodes, [meshio.CellBlock(ctype, cells)])
        assert abs(w.sum() / (np.pi) - 1) < tol            # 4 pi R0^2 = pi
        assert (w > 0).all()


def planar_band(n, normal, g, eps_cells=1.0):
    """Cell centres of an n^3 unit box and the band force delta_eps(n.x - d) g."""
    h = 1.0 / n
    ax = (np.arange(n) + 0.5) * h
    Z, Y, X = np.meshgrid(ax, ax, ax, indexing="ij")
    c = np.c_[X.ravel(), Y.ravel(), Z.ravel()]
    d = c @ normal - 0.5 * normal.sum()
    eps = eps_cells * h
    delta = 0.5 / eps / np.cosh(d / eps) ** 2          # |grad phi| of (1 - tanh(d/eps))/2
    return c, h, delta[:, None] * g[None, :]


def test_line_and_smoothed_traction_recover_a_planar_load():
    normal = np.array([1.0, 2.0, 2.0]) / 3.0           # oblique to every grid axis
    g = np.array([0.3, -1.0, 0.7])
    c, h, F = planar_band(48, normal, g)
    grid = mc.CellGrid(c, 3)
    # points on the plane n.x = n.(0.5, 0.5, 0.5), near the box centre
    rng = np.random.default_rng(4)
    t1 = np.cross(normal, [1.0, 0, 0])
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(normal, t1)
    a, b = rng.uniform(-0.1, 0.1, (2, 40))
    p = 0.5 + a[:, None] * t1 + b[:, None] * t2
    nn = np.tile(normal, (len(p), 1))
    t = mc.line_traction(grid.interpolator(F), p, nn, 8 * h, 129)
    assert np.abs(t - g).max() < 0.02 * np.linalg.norm(g), np.abs(t - g).max()
    ts = mc.smoothed_traction_volume(c, F, h ** 3, p[:5], nn[:5], 2 * h, 8 * h)
    # the same kernel on a fine surface sampling of the plane with the constant load g
    s = np.arange(-0.3, 0.3, h / 4) + h / 8
    A_, B_ = np.meshgrid(s, s)
    surf = 0.5 + A_.ravel()[:, None] * t1 + B_.ravel()[:, None] * t2
    qs = mc.smoothed_traction_surface(surf, np.tile(g, (len(surf), 1)),
                                      np.full(len(surf), (h / 4) ** 2), p[:5], nn[:5], 2 * h)
    assert np.abs(qs - g).max() < 1e-3 * np.linalg.norm(g)
    assert np.abs(ts - g).max() < 0.01 * np.linalg.norm(g), np.abs(ts - g).max()


def run_fe_probe(tmp_path, ranks):
    env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1",
               OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    out = tmp_path / f"fe{ranks}"
    cmd = ([] if ranks == 1 else ["mpirun", "--oversubscribe", "-np", str(ranks)]) + [
        "/usr/bin/python3", str(REPO / "reference" / "vesicle_shear_2d.py"), "--Ca", "0.2",
        "--Lx", "8", "--Ly", "8", "--h-far", "1.0", "--refine", "1", "--t-end", "0.04",
        "--dt-max", "0.02", "--write-times", "0", "0.04", "--probe-grid", "16", "16",
        "--out", str(out)]
    res = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=900)
    assert res.returncode == 0, res.stdout[-2000:] + res.stderr[-2000:]
    return out


def test_fe_probe_file_is_the_fe_solution_at_the_cell_centres(tmp_path):
    out = run_fe_probe(tmp_path, 1)
    pts, cells, steps = mc.read_series(out / "capsule_ca0.2_r1_probe.xdmf")
    xc = mc.cell_centres(pts, cells)
    assert xc.shape == (256, 2) and abs(xc[:, 0].min() + 3.75) < 1e-12
    (t, _, cd), dt = mc.at_time(steps, 0.0)
    assert dt == 0
    # t = 0: shear flow (P2 holds it exactly) and phi = 1/(1 + exp((r - 1)/eps)), eps = h
    u = mc.cell_field(cd, "velocity")
    assert np.abs(u - np.c_[xc[:, 1], 0 * xc[:, 1]]).max() < 1e-10
    r = np.hypot(xc[:, 0], xc[:, 1])
    phi = mc.cell_field(cd, "phi")
    assert np.abs(phi - 1 / (1 + np.exp((r - 1) / 0.5))).max() < 0.02    # P2 of the tanh
    # the P1 XDMF written by DOLFINx, read by meshio and interpolated to the same centres:
    # the P1 interpolant of the P2 phi is further from the exact profile than the probe
    phi_ex = 1 / (1 + np.exp((r - 1) / 0.5))
    p1pts, p1cells, p1steps = mc.read_series(out / "capsule_ca0.2_r1_phi.xdmf")
    interp = mc.P1Interpolant(p1pts, p1cells[0].data)
    phi1 = interp(mc.at_time(p1steps, 0.0)[0][1]["phi"], xc[:, 0], xc[:, 1])
    assert np.abs(phi - phi_ex).max() < np.abs(phi1 - phi_ex).max() < 0.1
    # later: P1 path and probe are the same FE velocity up to P1 interpolation (a
    # misplaced point would cost ~ h x shear rate = 0.5 here)
    p1pts, p1cells, p1steps = mc.read_series(out / "capsule_ca0.2_r1_velocity.xdmf")
    (t1, pd, _), _ = mc.at_time(p1steps, 0.04)
    (t2, _, cd2), _ = mc.at_time(steps, 0.04)
    assert abs(t1 - t2) < 1e-12
    u1 = interp(pd["velocity"][:, :2], xc[:, 0], xc[:, 1])
    u2 = mc.cell_field(cd2, "velocity")
    assert np.abs(u1 - u2).max() < 0.01
    # two ranks write the same probe file
    out2 = run_fe_probe(tmp_path, 2)
    _, _, steps2 = mc.read_series(out2 / "capsule_ca0.2_r1_probe.xdmf")
    for (ta, _, a), (tb, _, b) in zip(steps, steps2):
        assert ta == tb
        for k in ("velocity", "pressure", "phi"):
            assert np.abs(mc.cell_field(a, k) - mc.cell_field(b, k)).max() < 1e-8, k


@pytest.mark.skipif(not EFSI.exists(), reason=f"{EFSI} not built")
def test_cpp_xdmf_centres_and_velocity_match_the_h5_snapshot(tmp_path):
    sys.path.insert(0, str(REPO / "verification" / "studies"))
    from _flowio import read_snapshot

    out = tmp_path / "capsule"
    res = subprocess.run([str(EFSI), "run", str(REPO / "cases" / "capsule_shear_2d"),
                          "--output", str(out), "--set", "grid.cells=[32,32,1]",
                          "--set", "grid.length=[8.0,8.0,0.25]",
                          "--set", "grid.origin=[-4.0,-4.0,-0.125]",
                          "--set", "time.end_time=0.05"],
                         capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stderr[-2000:]
    pts, cells, steps = mc.read_series(out / "fields" / "fields.xdmf")
    xc = mc.cell_centres(pts, cells)
    grid = mc.CellGrid(xc, 2)
    assert grid.shape == (1, 32, 32)
    assert np.allclose(grid.axes[0], -4 + 0.25 * (np.arange(32) + 0.5))
    assert np.allclose(grid.axes[1], grid.axes[0])
    snap = read_snapshot(sorted((out / "fields").glob("fields_*.h5"))[-1])
    u = grid.reshape(mc.cell_field(steps[-1][2], "velocity"))[0]
    uf = snap["u"][0]                                   # low x-faces, periodic in x
    assert np.abs(u[..., 0] - 0.5 * (uf + np.roll(uf, -1, axis=1))).max() < 1e-13
    p = grid.reshape(mc.cell_field(steps[-1][2], "pressure"))[0]
    assert np.abs(p - snap["p"][0]).max() == 0


def force_study_with_write():
    exe = Path(os.environ.get("EFSI_MEMBRANE_FORCE_BIN",
                              EFSI.parent / "efsi_membrane_force_study"))
    if not exe.exists():
        return None
    help_text = subprocess.run([str(exe), "--help"], capture_output=True, text=True).stdout
    return exe if "--write" in help_text else None


@pytest.mark.skipif(force_study_with_write() is None,
                    reason="no efsi_membrane_force_study with --write")
def test_written_membrane_force_carries_the_inflated_circle_load(tmp_path):
    """C++ --write output read through meshio: the band force of a circle inflated by
    s = 1.2 (2D, 32 cells across), integrated along the normals, averages to the exact
    load T/R; the net force vanishes."""
    import json
    exe = force_study_with_write()
    res = subprocess.run([str(exe), "--dim", "2", "--cells", "32", "--map", "inflate",
                          "--write", str(tmp_path / "m")], capture_output=True, text=True,
                         timeout=600)
    assert res.returncode == 0, res.stderr
    exact = json.loads(res.stdout)["exact_load"]              # T/R, R = 1.2 R0
    pts, cells, steps = mc.read_series(tmp_path / "m" / "fields" / "fields.xdmf")
    xc = mc.cell_centres(pts, cells)
    F = mc.cell_field(steps[0][2], "velocity")
    phi = mc.cell_field(steps[0][2], "phi_capsule")
    grid = mc.CellGrid(xc, 2)
    h = grid.h[0]
    assert abs(np.sum(phi) * h * h / (np.pi * 0.6 ** 2) - 1) < 0.01     # the inflated disc
    assert np.abs(F.sum(axis=0)).max() < 1e-12 * np.abs(F).sum()       # conservative form
    th = 2 * np.pi * (np.arange(64) + 0.5) / 64
    nn = np.c_[np.cos(th), np.sin(th), 0 * th]
    centre = np.array([0.013, 0.027, 0.0])                  # the driver's centre
    t = mc.line_traction(grid.interpolator(F), centre + 0.6 * nn, nn, 8 * h, 129)
    tn = np.sum(t * nn, axis=1)
    assert abs(tn.mean() / -exact - 1) < 0.01, (tn.mean(), exact)      # inward, T/R
