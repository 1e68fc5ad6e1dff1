"""Triangulated closed and flat surfaces in 3D for the membrane reference.

A membrane is a 2D manifold embedded in 3D.  DOLFINx represents it as a mesh with
topological dimension 2 and geometric dimension 3; UFL's ``grad`` on such a mesh is the
*surface* gradient (the tangential part of the 3D gradient), which is exactly the
``P . grad`` of MODEL.md.

Shapes (all nodes lie exactly on the analytic surface; with ``degree=2`` the edge
midpoints are placed on the surface too, giving an isoparametric P2 surface):

* ``sphere``     radius R0:                       X = R0 xi,  xi on the unit sphere
* ``ellipsoid``  semi-axes (a, b, c):             X = (a xi_1, b xi_2, c xi_3)
* ``rbc``        Evans-Fung biconcave disc,
                 z = +-(R0/2) sqrt(1 - r^2) (C0 + C1 r^2 + C2 r^4),  r = rho / R0.
                 On the unit sphere sqrt(1 - rho_xi^2) = |xi_3|, so the map
                 X = R0 xi_1, Y = R0 xi_2, Z = (R0/2) xi_3 g(rho_xi^2)
                 with g(s) = C0 + C1 s + C2 s^2 > 0 is smooth and orientation
                 preserving (det = R0^3 g / 2 > 0).
* ``sheet``      flat rectangle [0, Lx] x [0, Ly] in the plane z = 0.

The unit sphere is a refined icosahedron: each refinement splits every triangle into
four and projects the new vertices radially onto the sphere.

Every builder returns ``(nodes, cells, outward)``: node coordinates (N x 3), cells in
DOLFINx node ordering (vertices v0 v1 v2 then, for P2, the midpoints of edges
(v1 v2), (v0 v2), (v0 v1)), and a function giving an outward direction at reference
points, used only to orient the cell normals consistently.
"""
from __future__ import annotations

import numpy as np
import ufl
from mpi4py import MPI
import dolfinx.mesh

# Evans-Fung parameters (MODEL.md, seed section 3.2)
RBC_R0, RBC_C0, RBC_C1, RBC_C2 = 3.91, 0.207161, 2.002558, -1.122762


def icosahedron():
    t = (1.0 + 5.0 ** 0.5) / 2.0
    v = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0],
                  [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
                  [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], dtype=float)
    f = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
                  [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
                  [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
                  [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]], dtype=np.int64)
    return v / np.linalg.norm(v, axis=1)[:, None], f


def _edge_midpoints(nodes, tri, project):
    """Add one node per edge (P2).  Returns nodes and 6-node cells in DOLFINx order."""
    edges = np.sort(np.concatenate([tri[:, [1, 2]], tri[:, [0, 2]], tri[:, [0, 1]]]), axis=1)
    uniq, inv = np.unique(edges, axis=0, return_inverse=True)
    mid = project(0.5 * (nodes[uniq[:, 0]] + nodes[uniq[:, 1]]))
    n_t = tri.shape[0]
    inv = inv.reshape(3, n_t).T + nodes.shape[0]
    return np.vstack([nodes, mid]), np.hstack([tri, inv])


def unit_sphere(level: int, degree: int = 1):
    """Refined icosahedron on the unit sphere, ``20 * 4**level`` triangles."""
    v, f = icosahedron()
    proj = lambda x: x / np.linalg.norm(x, axis=1)[:, None]  # noqa: E731
    for _ in range(level):
        n_v = v.shape[0]
        edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
        uniq, inv = np.unique(edges, axis=0, return_inverse=True)
        v = np.vstack([v, proj(0.5 * (v[uniq[:, 0]] + v[uniq[:, 1]]))])
        m = inv.reshape(3, f.shape[0]).T + n_v       # midpoints of (01), (12), (20)
        a, b, c = f[:, 0], f[:, 1], f[:, 2]
        f = np.vstack([np.c_[a, m[:, 0], m[:, 2]], np.c_[b, m[:, 1], m[:, 0]],
                       np.c_[c, m[:, 2], m[:, 1]], m])
    if degree == 2:
        v, f = _edge_midpoints(v, f, proj)
    return v, f


def shape_map(shape: str, params: dict | None = None):
    """Return (map from unit sphere, outward direction at reference points)."""
    p = dict(params or {})
    if shape == "sphere":
        R0 = p.get("R0", 1.0)
        return (lambda xi: R0 * xi), (lambda X: X)
    if shape == "ellipsoid":
        ax = np.array(p.get("axes", (1.0, 0.8, 0.6)))
        return (lambda xi: xi * ax), (lambda X: X / ax ** 2)
    if shape == "rbc":
        R0, C0, C1, C2 = (p.get(k, d) for k, d in
                          (("R0", RBC_R0), ("C0", RBC_C0), ("C1", RBC_C1), ("C2", RBC_C2)))

        def m(xi):
            s = xi[:, 0] ** 2 + xi[:, 1] ** 2
            return np.c_[R0 * xi[:, 0], R0 * xi[:, 1], 0.5 * R0 * xi[:, 2] * (C0 + C1 * s + C2 * s * s)]

        def outward(X):
            # gradient of Phi = (2Z/R0)^2 - (1 - r^2) g(r^2)^2, negative inside
            s = (X[:, 0] ** 2 + X[:, 1] ** 2) / R0 ** 2
            g = C0 + C1 * s + C2 * s * s
            dg = C1 + 2 * C2 * s
            dphi_ds = -(-g * g + (1 - s) * 2 * g * dg)            # d/ds of -(1-s) g^2
            return np.c_[dphi_ds * 2 * X[:, 0] / R0 ** 2, dphi_ds * 2 * X[:, 1] / R0 ** 2,
                         8 * X[:, 2] / R0 ** 2]
        return m, outward
    raise ValueError(f"unknown shape {shape!r}")


def closed_surface(shape: str, level: int, degree: int = 1, params: dict | None = None):
    xi, cells = unit_sphere(level, degree)
    m, outward = shape_map(shape, params)
    return m(xi), cells, outward


def flat_sheet(nx: int, ny: int, lx: float = 1.0, ly: float = 1.0, degree: int = 1):
    """Structured right-triangle mesh of [0,lx] x [0,ly] at z = 0 (normal +z)."""
    x, y = np.meshgrid(np.linspace(0, lx, nx + 1), np.linspace(0, ly, ny + 1), indexing="ij")
    nodes = np.c_[x.ravel(), y.ravel(), np.zeros(x.size)]
    idx = np.arange((nx + 1) * (ny + 1)).reshape(nx + 1, ny + 1)
    a, b = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel()
    c, d = idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    cells = np.vstack([np.c_[a, b, c], np.c_[a, c, d]])          # counter-clockwise
    if degree == 2:
        nodes, cells = _edge_midpoints(nodes, cells, lambda z: z)
    return nodes, cells, (lambda X: np.tile([0.0, 0.0, 1.0], (X.shape[0], 1)))


def create_surface_mesh(comm, nodes, cells, degree: int = 1):
    """DOLFINx mesh (tdim 2, gdim 3), data supplied on rank 0 and distributed."""
    cell = ufl.Cell("triangle", geometric_dimension=3)
    domain = ufl.Mesh(ufl.VectorElement("Lagrange", cell, degree))
    if comm.rank != 0:
        nodes = np.zeros((0, 3))
        cells = np.zeros((0, cells.shape[1]), dtype=np.int64)
    return dolfinx.mesh.create_mesh(comm, cells.astype(np.int64), nodes, domain)


def cell_orientation(mesh, outward):
    """+-1 per local cell so that sign * (x1 - x0) x (x2 - x0) points along ``outward``."""
    tdim = mesh.topology.dim
    n_local = mesh.topology.index_map(tdim).size_local + mesh.topology.index_map(tdim).num_ghosts
    gdofs = mesh.geometry.dofmap.array.reshape(n_local, -1)[:, :3]
    x = mesh.geometry.x[gdofs]                                   # (cells, 3 vertices, 3)
    nrm = np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    centroid = x.mean(axis=1)
    s = np.sign(np.einsum("ij,ij->i", nrm, outward(centroid)))
    s[s == 0] = 1.0
    return s
