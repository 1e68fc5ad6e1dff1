#!/usr/bin/python3
"""Lagrangian markers carried through an efsi run's velocity snapshots (docs/method.md,
"Material markers agree with the map").

Seeds an icosphere on the initial phi = 1/2 surface (radius r0), carries every vertex with
the staggered face velocity (trilinear in space, linear between snapshots, RK4), and at
each snapshot compares
  - the markers' own strain (flat triangles: B = F F^T from reference to current) with the
    Gs the run holds at the triangle's centroid (trilinear from cell centres),
  - phi at the markers (the material surface against the VOF surface),
  - D of the markers' polyhedron (second moments of its volume) with the run's D.
At the end it also compares the run's reference map (checkpoint.h5, X - x) at the markers
with the markers' own reference positions.

    efsi run cases/capsule_shear -o RUN --set 'body[0].elastic_modulus=5.0' \
        --set time.end_time=2.0 --set output.fields_interval=0.02   (d/16; d/32: 128 cells, 0.04)
    /usr/bin/python3 verification/records/capsule_longtime/markers.py RUN --level 5 --substeps 8
"""
import argparse
import os
import sys
from pathlib import Path

import h5py
import numpy as np
from scipy.ndimage import map_coordinates

sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "reference"))
from capsule_bi_3d import icosphere, shape  # noqa: E402  (the same mesh and D as the BI)


class Snap:
    def __init__(self, path, n, L, x0):
        g = h5py.File(path, 'r')
        self.t = float(g.attrs['time'])
        self.n, self.h, self.x0 = n, L / n, x0
        self.U = [np.transpose(g[k][:], (2, 1, 0)) for k in ('faces_u', 'faces_v', 'faces_w')]
        self.phi = np.transpose(g['phi_capsule'][:].reshape(n, n, n), (2, 1, 0))
        self.G = {k: np.transpose(g['capsule_Gs_' + k][:].reshape(n, n, n), (2, 1, 0))
                  for k in ('xx', 'xy', 'xz', 'yy', 'yz', 'zz')}

    def _interp(self, F, p, offset):
        # F sampled at x0 + (i + offset_d) h
        c = [(p[:, d] - self.x0[d]) / self.h - offset[d] for d in range(3)]
        return map_coordinates(F, c, order=1, mode='nearest')

    def vel(self, p):
        offs = [(0, .5, .5), (.5, 0, .5), (.5, .5, 0)]
        return np.stack([self._interp(self.U[d], p, offs[d]) for d in range(3)], 1)

    def centre(self, F, p):
        return self._interp(F, p, (.5, .5, .5))

    def Gs(self, p):
        g = {k: self.centre(v, p) for k, v in self.G.items()}
        M = np.empty((len(p), 3, 3))
        M[:, 0, 0], M[:, 1, 1], M[:, 2, 2] = g['xx'], g['yy'], g['zz']
        M[:, 0, 1] = M[:, 1, 0] = g['xy']; M[:, 0, 2] = M[:, 2, 0] = g['xz']; M[:, 1, 2] = M[:, 2, 1] = g['yz']
        return M


def tri_strain(X, x, f):
    E = np.stack([X[f[:, 1]] - X[f[:, 0]], X[f[:, 2]] - X[f[:, 0]]], 2)  # (T,3,2)
    e = np.stack([x[f[:, 1]] - x[f[:, 0]], x[f[:, 2]] - x[f[:, 0]]], 2)
    EtE = np.einsum('tdi,tdj->tij', E, E)
    B = np.einsum('tai,tij,tbj->tab', e, np.linalg.inv(EtE), e)
    Aref = 0.5 * np.linalg.norm(np.cross(E[:, :, 0], E[:, :, 1]), axis=1)
    Acur = 0.5 * np.linalg.norm(np.cross(e[:, :, 0], e[:, :, 1]), axis=1)
    return B, Acur / Aref


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('run'); ap.add_argument('--level', type=int, default=5)
    ap.add_argument('--L', type=float, default=8.0); ap.add_argument('--r0', type=float, default=1.0)
    ap.add_argument('--substeps', type=int, default=4)
    a = ap.parse_args()
    fdir = os.path.join(a.run, 'fields')
    files = [l.split()[2] for l in open(os.path.join(fdir, 'index.txt')) if l.strip()]
    n = round(h5py.File(os.path.join(fdir, files[0]), 'r')['phi_capsule'].shape[0] ** (1 / 3))
    x0 = np.array([-a.L / 2] * 3)
    V, F = icosphere(a.level)
    X = V * a.r0; x = X.copy()
    prev = Snap(os.path.join(fdir, files[0]), n, a.L, x0)
    print('t  D_markers  V_markers  phi@markers(mean,maxdev)  trB_markers-trGs(mean,rms)  J_markers/J_Gs-1(mean,rms)  nm.Gs.nm')
    for fn in files[1:]:
        cur = Snap(os.path.join(fdir, fn), n, a.L, x0)
        t0, t1 = prev.t, cur.t; dt = (t1 - t0) / a.substeps
        def vel(p, t):
            w = (t - t0) / (t1 - t0)
            return (1 - w) * prev.vel(p) + w * cur.vel(p)
        for s in range(a.substeps):
            t = t0 + s * dt
            k1 = vel(x, t); k2 = vel(x + dt / 2 * k1, t + dt / 2); k3 = vel(x + dt / 2 * k2, t + dt / 2)
            k4 = vel(x + dt * k3, t + dt)
            x = x + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        prev = cur
        if abs(round(t1 / 0.5) * 0.5 - t1) > 1e-6:
            continue
        B, Jm = tri_strain(X, x, F)
        cen = (x[F[:, 0]] + x[F[:, 1]] + x[F[:, 2]]) / 3
        G = cur.Gs(cen)
        trG = np.trace(G, axis1=1, axis2=2)
        IIG = (trG ** 2 - np.einsum('tij,tji->t', G, G)) / 2
        JG = np.sqrt(np.maximum(IIG, 1e-30))
        trB = np.trace(B, axis1=1, axis2=2)
        nm = np.cross(x[F[:, 1]] - x[F[:, 0]], x[F[:, 2]] - x[F[:, 0]]); nm /= np.linalg.norm(nm, axis=1)[:, None]
        nGn = np.einsum('ti,tij,tj->t', nm, G, nm)
        ph = cur.centre(cur.phi, x)
        D, _, _, Vol = shape(x, F)
        d1 = trB - trG; d2 = Jm / JG - 1
        print(f'{t1:.2f} {D:.4f} {Vol:.4f} {ph.mean():.4f} {np.abs(ph - .5).max():.4f}  {d1.mean():+.4f} {np.sqrt((d1**2).mean()):.4f}  '
              f'{d2.mean():+.4f} {np.sqrt((d2**2).mean()):.4f}  {np.abs(nGn).max():.3f}  trB[mean,max] {trB.mean():.3f} {trB.max():.3f} trG {trG.mean():.3f} {trG.max():.3f}', flush=True)
    c = h5py.File(os.path.join(a.run, 'checkpoint.h5'), 'r')
    R = [np.transpose(c['body_capsule_refmap_' + k][:], (2, 1, 0)) for k in 'xyz']
    co = [(x[:, d] - x0[d]) / (a.L / n) - 0.5 for d in range(3)]
    Xe = np.stack([x[:, d] + map_coordinates(R[d], co, order=3) for d in range(3)], 1)
    err = np.linalg.norm(Xe - X, axis=1)
    print(f"reference map at the markers (t = {float(c.attrs['time']):.2f}): |X_map - X_marker| "
          f"rms {np.sqrt((err ** 2).mean()):.4f}, max {err.max():.4f} (cell {a.L / n:.4f})")


if __name__ == '__main__':
    main()
