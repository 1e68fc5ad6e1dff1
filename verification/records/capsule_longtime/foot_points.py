#!/usr/bin/python3
"""How far from the surface the band cells' foot points land: |psi(y)|, y = x - psi n.

    /usr/bin/python3 verification/records/capsule_longtime/foot_points.py RUN/fields/fields_NNNNNNNN.h5 CELLS

Reads a capsule_shear field snapshot (phi of body 'capsule', CELLS per direction, the cases'
smoothing width 0.75 cells), forms psi = eps atanh(1 - 2 phi) in cells, the normals from its
central differences, each band cell's foot point (1e-5 < phi < 1 - 1e-5, |psi| within the
extension's default reach, |grad psi| >= 1/2, as NormalExtension) and psi there (trilinear),
and prints the distribution of |psi(y)| in cells. Where psi is a distance the foot point lies
on the surface (|psi(y)| small); in a thin body's middle, where the two faces' profiles meet,
the normal turns and the foot lands inside. NormalExtension::kFootTolerance (0.5 cells)
separates the two (the figures quoted in normal_extension.hpp come from this script).
"""
import h5py, numpy as np, sys
f = h5py.File(sys.argv[1]); n = int(sys.argv[2]); eps = 0.75
phi = f['phi_capsule'][:].reshape(n, n, n)  # (z,y,x)
G = {c: f['capsule_Gs_'+c][:].reshape(n, n, n) for c in ['xx','yy','zz']}
psi = eps*np.arctanh(np.clip(1-2*phi, -1+1e-15, 1-1e-15))   # in cells
gz, gy, gx = np.gradient(psi)   # central differences, cells
g2 = gx**2+gy**2+gz**2
reach = np.arctanh(1-2e-5)*eps + 2
band = (np.abs(psi) <= reach) & (g2 >= 0.25) & (phi > 1e-5) & (phi < 1-1e-5)
def trilin(F, x, y, z):
    i0 = np.floor(x).astype(int); j0 = np.floor(y).astype(int); k0 = np.floor(z).astype(int)
    tx, ty, tz = x-i0, y-j0, z-k0
    out = 0
    for a in (0,1):
        for b in (0,1):
            for c in (0,1):
                w = (tx if a else 1-tx)*(ty if b else 1-ty)*(tz if c else 1-tz)
                out = out + w*F[np.clip(k0+c,0,n-1), np.clip(j0+b,0,n-1), np.clip(i0+a,0,n-1)]
    return out
K, J, I = np.nonzero(band)
s = psi[K,J,I]; gn = np.sqrt(g2[K,J,I])
nx, ny, nz = gx[K,J,I]/gn, gy[K,J,I]/gn, gz[K,J,I]/gn
fp = trilin(psi, I - s*nx, J - s*ny, K - s*nz)
a = np.abs(fp)
print('band cells (1e-5<phi<1-1e-5)', a.size, 'percentiles |psi(foot)| [cells] 50/99/99.9/max', np.percentile(a,[50,99,99.9]).round(3), a.max().round(3))
print('cells with |psi(foot)| > 0.5:', (a > 0.5).sum(), ' > 0.25:', (a>0.25).sum())
bad = a > 0.5
if bad.any():
    print('their phi:', np.round(phi[K,J,I][bad][:10],4), 'their s:', np.round(s[bad][:10],2))
