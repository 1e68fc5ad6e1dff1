"""Cross-code comparison machinery: read both codes' fields through meshio and bring them
to common points (used by ``cross_code.py``; tested in verification/tests/test_meshcompare.py).

* ``read_series(xdmf)``: an XDMF temporal collection (the C++ ``fields/fields.xdmf`` or one
  of the FE scripts' per-field files) via ``meshio.xdmf.TimeSeriesReader``: points, cells
  and a list of ``(time, point_data, cell_data)``.
* ``at_time(series, t)``: the snapshot whose time is nearest ``t`` (the time difference is
  returned so that a caller can refuse a mismatch).
* ``cell_centres(points, cells)``: the centre of every cell (mean of its nodes), in cell
  data order: for the C++ hexahedra/quadrilaterals these are the Cartesian cell centres.
* ``P1Interpolant``: a continuous piecewise-linear field on a triangle mesh (the FE P1 data)
  evaluated at arbitrary points with matplotlib.tri (exact P1 evaluation on the FE's own
  triangles; NaN outside the mesh).
* ``CellGrid``: cell data of the C++ Cartesian grid reshaped to (nz, ny, nx) with
  (tri)linear interpolation between cell centres (scipy RegularGridInterpolator).
* ``line_traction``: a volume force density integrated along straight lines through
  surface points (the surface traction an Eulerian band force carries).
* ``smoothed_traction_volume`` / ``smoothed_traction_surface``: the same traction smoothed
  with one Gaussian surface kernel, from a volume force (cell sum) or from a surface load
  (node sum), so that both codes are compared through the same functional.
* ``rel_l2``/``rel_l1``: weighted relative norms of a difference.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np


def read_series(path: Path):
    """(points, cells, [(t, point_data, cell_data), ...]) of an XDMF temporal collection."""
    import meshio

    reader = meshio.xdmf.TimeSeriesReader(str(path))
    points, cells = reader.read_points_cells()
    steps = []
    for k in range(reader.num_steps):
        t, pd, cd = reader.read_data(k)
        steps.append((float(t), pd, cd))
    return points, cells, steps


def at_time(steps, t: float):
    """(snapshot, |t_snapshot - t|) of the snapshot nearest t."""
    k = int(np.argmin([abs(s[0] - t) for s in steps]))
    return steps[k], abs(steps[k][0] - t)


def cell_centres(points: np.ndarray, cells) -> np.ndarray:
    """Centres (mean of the nodes) of all cells of all blocks, in cell-data order."""
    return np.concatenate([points[c.data].mean(axis=1) for c in cells])


def cell_field(cell_data: dict, name: str) -> np.ndarray:
    """One cell-data field as a single array (meshio keeps one array per cell block)."""
    return np.concatenate(cell_data[name])


class P1Interpolant:
    """Continuous P1 data on a triangle mesh, evaluated at points (x, y) by its own
    triangles (barycentric interpolation, matplotlib.tri)."""

    def __init__(self, points: np.ndarray, triangles: np.ndarray):
        import matplotlib.tri as mtri

        self.tri = mtri.Triangulation(points[:, 0], points[:, 1], triangles)
        self.finder = self.tri.get_trifinder()

    def __call__(self, values: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        import matplotlib.tri as mtri

        values = np.asarray(values, float)
        cols = values.reshape(len(values), -1)
        out = np.empty((len(x), cols.shape[1]))
        for c in range(cols.shape[1]):
            f = mtri.LinearTriInterpolator(self.tri, cols[:, c], trifinder=self.finder)
            out[:, c] = np.ma.filled(f(x, y).astype(float), np.nan)
        return out[:, 0] if cols.shape[1] == 1 else out


class CellGrid:
    """Cell data of a uniform Cartesian grid given as cell centres in any order, stored as
    [nz][ny][nx] arrays and interpolated (tri)linearly between the centres."""

    def __init__(self, centres: np.ndarray, dim: int):
        self.dim = dim
        self.axes = [np.unique(np.round(centres[:, d], 12)) for d in range(3)]
        self.h = [float(np.diff(a).mean()) if len(a) > 1 else 0.0 for a in self.axes]
        self.shape = tuple(len(a) for a in self.axes[::-1])      # (nz, ny, nx)
        idx = [np.rint((centres[:, d] - self.axes[d][0]) / self.h[d]).astype(int)
               if len(self.axes[d]) > 1 else np.zeros(len(centres), int) for d in range(3)]
        self.order = (idx[2] * self.shape[1] + idx[1]) * self.shape[2] + idx[0]
        if len(np.unique(self.order)) != len(centres) or np.prod(self.shape) != len(centres):
            raise ValueError("cell centres do not form a uniform Cartesian grid")

    def reshape(self, values: np.ndarray) -> np.ndarray:
        """values in the given cell order -> array of shape (nz, ny, nx[, ncomp])."""
        values = np.asarray(values, float)
        out = np.empty((int(np.prod(self.shape)),) + values.shape[1:])
        out[self.order] = values
        return out.reshape(self.shape + values.shape[1:])

    def interpolator(self, values: np.ndarray):
        """f(points (N, dim)) -> values, linear between cell centres, NaN outside."""
        from scipy.interpolate import RegularGridInterpolator

        arr = self.reshape(values)
        if self.dim == 2:
            arr = arr[0]                                          # (ny, nx[, c])
            axes = (self.axes[1], self.axes[0])
        else:
            axes = (self.axes[2], self.axes[1], self.axes[0])
        rgi = RegularGridInterpolator(axes, arr, bounds_error=False, fill_value=np.nan)
        return lambda p: rgi(np.asarray(p)[:, :self.dim][:, ::-1])


def rel_l2(diff: np.ndarray, ref: np.ndarray, weights=None) -> float:
    """sqrt(sum w |diff|^2 / sum w |ref|^2) (rows are points, columns components)."""
    d = np.asarray(diff, float).reshape(len(diff), -1)
    r = np.asarray(ref, float).reshape(len(ref), -1)
    w = np.ones(len(d)) if weights is None else np.asarray(weights, float)
    return float(np.sqrt(np.sum(w * np.sum(d ** 2, 1)) / np.sum(w * np.sum(r ** 2, 1))))


def rel_l1(diff: np.ndarray, ref: np.ndarray, weights=None) -> float:
    """sum w |diff| / sum w |ref| (scalars)."""
    w = np.ones(len(diff)) if weights is None else np.asarray(weights, float)
    return float(np.sum(w * np.abs(diff)) / np.sum(w * np.abs(ref)))


def lumped_node_areas(points: np.ndarray, cells) -> np.ndarray:
    """Area weights of the nodes of a surface triangulation (triangle or triangle6, the
    latter split into its four straight sub-triangles): each triangle gives a third of its
    area to each of its corners."""
    w = np.zeros(len(points))
    for block in cells:
        c = block.data
        if block.type == "triangle6":                 # VTK: v0 v1 v2 m01 m12 m20
            subs = [c[:, [0, 3, 5]], c[:, [3, 1, 4]], c[:, [5, 4, 2]], c[:, [3, 4, 5]]]
        elif block.type == "triangle":
            subs = [c]
        else:
            continue
        for t in subs:
            a = 0.5 * np.linalg.norm(np.cross(points[t[:, 1]] - points[t[:, 0]],
                                              points[t[:, 2]] - points[t[:, 0]]), axis=1)
            for k in range(3):
                np.add.at(w, t[:, k], a / 3)
    return w


def line_traction(force, points: np.ndarray, normals: np.ndarray, half_width: float,
                  samples: int = 161) -> np.ndarray:
    """int_{-W}^{W} F(x + s n) ds for every point x with unit normal n (trapezoid rule on
    ``samples`` points; ``force`` maps (N, 3) points to (N, 3) values)."""
    s = np.linspace(-half_width, half_width, samples)
    out = np.empty_like(points, dtype=float)
    chunk = max(1, 400000 // samples)
    for a in range(0, len(points), chunk):
        b = min(a + chunk, len(points))
        q = points[a:b, None, :] + s[None, :, None] * normals[a:b, None, :]
        vals = force(q.reshape(-1, 3)).reshape(b - a, samples, -1)
        out[a:b] = np.trapz(vals, s, axis=1)
    return out


def _kernel(d: np.ndarray, n0: np.ndarray, ell: float) -> np.ndarray:
    """exp(-|P0 d|^2 / ell^2) / (pi ell^2), P0 = I - n0 n0 (tangential distance)."""
    dn = d @ n0
    r2 = np.einsum("ij,ij->i", d, d) - dn ** 2
    return np.exp(-r2 / ell ** 2) / (np.pi * ell ** 2)


def smoothed_traction_volume(centres: np.ndarray, force: np.ndarray, dV: float,
                             points: np.ndarray, normals: np.ndarray, ell: float,
                             half_width: float) -> np.ndarray:
    """sum_cells F(x) K(x - x0) dV over the cells within ``half_width`` of the tangent
    plane of x0 (the band), K the Gaussian surface kernel of width ell."""
    from scipy.spatial import cKDTree

    keep = np.any(force != 0, axis=1)
    c, f = centres[keep], force[keep]
    tree = cKDTree(c)
    out = np.zeros((len(points), force.shape[1]))
    radius = np.hypot(3.5 * ell, half_width)
    for i, nb in enumerate(tree.query_ball_point(points, radius)):
        nb = np.asarray(nb, int)
        d = c[nb] - points[i]
        band = np.abs(d @ normals[i]) <= half_width
        out[i] = (f[nb][band] * _kernel(d[band], normals[i], ell)[:, None]).sum(0) * dV
    return out


def smoothed_traction_surface(nodes: np.ndarray, load: np.ndarray, weights: np.ndarray,
                              points: np.ndarray, normals: np.ndarray, ell: float) -> np.ndarray:
    """sum_nodes q(y) K(y - x0) w_y: the surface load smoothed by the same kernel."""
    from scipy.spatial import cKDTree

    tree = cKDTree(nodes)
    out = np.zeros((len(points), load.shape[1]))
    for i, nb in enumerate(tree.query_ball_point(points, 3.5 * ell)):
        nb = np.asarray(nb, int)
        k = _kernel(nodes[nb] - points[i], normals[i], ell) * weights[nb]
        out[i] = (load[nb] * k[:, None]).sum(0)
    return out
