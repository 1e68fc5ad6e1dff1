"""3D boundary-integral capsule: the membrane load, the single layer and the early flow."""
import numpy as np

import capsule_bi_3d as bi


def test_inflated_sphere_load_is_normal_and_two_tension_over_radius():
    # a sphere stretched uniformly by s: T = Es/(3 s^2) (s^2 - 1/s^4), load 2T/R inward
    X, tri = bi.icosphere(4)
    mem = bi.Membrane(X, tri, Es=1.0)
    s = 1.2
    F = mem.load(s * X)
    A, N = mem.nodal_area_normal(s * X)
    T = 1.0 / (3 * s ** 2) * (s ** 2 - 1 / s ** 4)
    fn = np.einsum("ni,ni->n", F / A[:, None], N)
    assert abs(np.mean(fn) / (-2 * T / s) - 1) < 0.01
    ft = F / A[:, None] - fn[:, None] * N
    assert np.abs(ft).max() < 0.02 * 2 * T / s
    assert np.abs(F.sum(0)).max() < 1e-12  # no net force


def test_unstrained_membrane_has_no_load():
    X, tri = bi.icosphere(3)
    mem = bi.Membrane(X, tri, Es=5.0)
    R = np.linalg.qr(np.random.default_rng(1).normal(size=(3, 3)))[0]
    assert np.abs(mem.load(X @ R.T + 0.3)).max() < 1e-12


def test_uniform_traction_moves_a_sphere_by_stokes_law():
    # a sphere under a uniform traction density g moves rigidly at u = 2 a g / (3 mu)
    # (total force 4 pi a^2 g = 6 pi mu a u); the single layer must reproduce it
    errs = []
    for level in (2, 3, 4):
        X, tri = bi.icosphere(level)

        class Uniform(bi.Membrane):
            def load(self, x):
                A, _ = self.nodal_area_normal(x)
                return A[:, None] * np.array([1.0, 0.0, 0.0])

        mem = Uniform(X, tri, Es=1.0)
        u = bi.velocity(X, mem, mu=1.0, gamma=0.0)
        errs.append(np.abs(u - np.array([2 / 3, 0, 0])).max() / (2 / 3))
    assert errs[-1] < 0.02
    assert errs[0] > errs[1] > errs[2]


def test_early_time_follows_the_shear():
    # unloaded at first, the sphere deforms as the shear does: D ~ t/2, inclination pi/4
    r = bi.run(0.2, 2, 0.1, 0.5, every=0.1)
    assert abs(r["D_final"] / 0.05 - 1) < 0.05
