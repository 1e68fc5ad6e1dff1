"""verification/band_strain.py on synthetic bands: a sphere whose every level set carries
P_R (no strain) or one common stretch gives no spread; layers stretched in proportion to
their offset give the spread put in."""
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from band_strain import band_strain  # noqa: E402

N, H, EPS = 48, 4.0 / 48, 4.0 / 48
ORIGIN = (-2.0, -2.0, -2.0)


def sphere(layer_stretch):
    ax = ORIGIN[0] + (np.arange(N) + 0.5) * H
    z, y, x = np.meshgrid(ax, ax, ax, indexing="ij")
    r = np.sqrt(x ** 2 + y ** 2 + z ** 2)
    phi = 0.5 * (1 - np.tanh((r - 1) / EPS))
    n = [x / r, y / r, z / r]
    lam2 = layer_stretch(r - 1) ** 2  # isotropic in-plane stretch of each layer
    gs = {}
    for a, b in ("xx", "xy", "xz", "yy", "yz", "zz"):
        i, j = "xyz".index(a), "xyz".index(b)
        gs[a + b] = lam2 * ((1.0 if i == j else 0.0) - n[i] * n[j])
    return phi, gs


def test_unstrained_and_uniformly_stretched_bands_have_no_spread():
    # The sampling is trilinear: on a curved P_R it is low by O((h/R)^2), 2e-3 relative here.
    for s in (1.0, 1.1):
        r = band_strain(*sphere(lambda d, s=s: s + 0 * d), ORIGIN, H, EPS)
        assert abs(r["centre_rms"] - (s * s - 1)) < 4e-3 * s * s
        assert r["spread_rms"] < 2e-3 and abs(r["mean_offset"]) < 2e-3


def test_layer_dependent_stretch_shows_as_spread():
    # J = lambda^2 = 1 + 0.2 s / eps: the band-weighted rms of J - J_c is 0.2 <(s/eps)^2>^1/2
    # (~0.18 over [-3 eps, 3 eps] with the sech^2 weight), its mean ~0 (odd in s).
    r = band_strain(*sphere(lambda d: np.sqrt(np.maximum(1 + 0.2 * d / EPS, 0.01))), ORIGIN, H, EPS)
    assert 0.12 < r["spread_rms"] < 0.25
    assert abs(r["mean_offset"]) < 0.02
