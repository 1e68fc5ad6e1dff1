"""Membrane stress reference: closed forms, convergence, virtual work, serial vs MPI."""
import json

import numpy as np
import pytest
from mpi4py import MPI

from conftest import run_script

import membrane_laws as laws
import membrane_stress as ms
import surface_meshes as sm


def test_neo_hookean_generic_formula_matches_model_closed_form():
    # tau = (2/J)(W1 Bs + J^2 W2 P) must equal Es/(3J)(Bs - P/J^2) for the neo-Hookean law
    rng = np.random.default_rng(1)
    l1, l2 = rng.uniform(0.5, 2.0, 20), rng.uniform(0.5, 2.0, 20)
    T1, T2 = laws.principal_tensions("neo-hookean", l1, l2, Es=3.0)
    J = l1 * l2
    assert np.allclose(T1, 3.0 / (3 * J) * (l1 ** 2 - 1 / J ** 2), rtol=1e-13)
    assert np.allclose(T2, 3.0 / (3 * J) * (l2 ** 2 - 1 / J ** 2), rtol=1e-13)
    # Skalak in the seed's form with Es = 3Gs/2 equals Skalak's own T1 (isotropic case)
    lam = np.linspace(0.8, 1.5, 9)
    T, _ = laws.principal_tensions("skalak", lam, lam, Es=1.5, alpha=2.0)
    assert np.allclose(T, laws.isotropic_tension("skalak", lam, 1.5, 2.0), rtol=1e-13)
    assert np.allclose(T, (lam ** 2 - 1) + 2.0 * lam ** 2 * (lam ** 4 - 1), rtol=1e-13)


@pytest.mark.parametrize("degree,expected_order,bound", [(1, 1.0, 0.03), (2, 2.0, 4e-3)])
def test_inflated_sphere_load_converges(degree, expected_order, bound):
    rows = [ms.sphere_inflation_errors(MPI.COMM_WORLD, lev, degree, "neo-hookean", 1.0, 1.0,
                                       1.2)[0] for lev in (1, 2, 3)]
    orders = ms.observed_orders([r["h"] for r in rows], [r["err_q"] for r in rows])
    assert abs(orders[-1] - expected_order) < 0.25, orders
    assert rows[-1]["err_q"] < bound
    assert rows[-1]["err_qt"] < 0.25 * rows[-1]["err_q"]       # load is (nearly) normal


@pytest.mark.parametrize("law,shape", [("neo-hookean", "ellipsoid"), ("skalak", "rbc")])
def test_tension_is_energy_derivative(law, shape):
    nodes, cells, outward = sm.closed_surface(shape, 2, 2)
    mem = ms.Membrane(MPI.COMM_WORLD, nodes, cells, outward, 2, law, 2.0, 3.0)
    F = np.array([[1.1, 0.2, 0.0], [0.0, 0.9, 0.1], [0.05, 0.0, 1.2]])
    chk = ms.virtual_work_check(mem, lambda X: X @ F.T)
    assert chk["rel_diff"] < 1e-6, chk


def test_load_has_no_net_force_or_torque():
    nodes, cells, outward = sm.closed_surface("rbc", 2, 2)
    mem = ms.Membrane(MPI.COMM_WORLD, nodes, cells, outward, 2, "skalak", 1.0, 10.0)
    mem.deform(lambda X: np.c_[X[:, 0] * 1.2, X[:, 1] + 0.1 * X[:, 0], X[:, 2]])
    q, _, _ = mem.load()
    import dolfinx
    import ufl
    x = ufl.SpatialCoordinate(mem.mesh)
    scale = np.sqrt(dolfinx.fem.assemble_scalar(dolfinx.fem.form(ufl.dot(q, q) * mem.dx)))
    for expr in [q[i] for i in range(3)] + [ufl.cross(x, q)[i] for i in range(3)]:
        val = dolfinx.fem.assemble_scalar(dolfinx.fem.form(expr * mem.dx))
        assert abs(val) < 1e-8 * scale * 10


def test_uniaxial_matches_closed_forms_and_data():
    for law in laws.LAWS:
        r = ms.uniaxial(MPI.COMM_WORLD, law, Gs=1.0, C=1.0, degree=1, level=1, n_points=5)
        assert r["max_rel_err_T1_vs_closed_form"] < 1e-8
        assert r["max_abs_err_lambda2_vs_closed_form"] < 1e-8
        # digitised curve: a few percent reading error, so only a loose bound
        assert r["data_rms_rel_dev"] < 0.08


def test_file_map_equals_linear_map(outdir):
    run_script(["membrane_stress.py", "write-map", "--shape", "ellipsoid", "--level", "1",
                "--degree", "2", "--out", outdir / "map.txt"])
    res = run_script(["membrane_stress.py", "single", "--shape", "ellipsoid", "--level", "1",
                      "--degree", "2", "--map", f"file:{outdir / 'map.txt'}", "--out", outdir])
    info = json.loads((outdir / "ellipsoid_neo-hookean.json").read_text())
    assert info["virtual_work_check"]["rel_diff"] < 1e-6
    import meshio
    m = meshio.read(outdir / "ellipsoid_neo-hookean.vtu")
    X = np.loadtxt(outdir / "map.txt")
    # the written deformed points are exactly the file's displaced points
    d = np.min(np.linalg.norm(m.points[:, None, :] - X[None, :, 3:], axis=2), axis=1)
    assert d.max() < 1e-12


def test_serial_and_two_ranks_agree(outdir):
    for ranks in (1, 2):
        run_script(["membrane_stress.py", "convergence", "--small", "--degree", "2",
                    "--out", outdir / f"r{ranks}"], ranks=ranks)
    a, b = (json.loads((outdir / f"r{r}" / "convergence_neo-hookean_P2.json").read_text())
            for r in (1, 2))
    assert b["ranks"] == 2
    for ra, rb in zip(a["rows"], b["rows"]):
        assert ra["cells"] == rb["cells"]
        assert abs(ra["err_q"] - rb["err_q"]) < 1e-10 * ra["err_q"] + 1e-14
