// The membrane's surface strain from a reference map (strain_model = "reference_map").
//
// X(x, t) is the reference position of the material point at x: D X/Dt = 0, no velocity
// gradient anywhere (the tensor form, D Gs/Dt = L Gs + Gs L^T, needs L at the membrane, where
// the tangential velocity has a kink). It is stored as its offset X - x, which is smooth and
// periodic where x is not: D (X - x)/Dt = -v (bodies/transport.hpp). The surface tensor is
// Gs = F P_R F^T. With the current normal n and the tangential part of the map's gradient,
// M = P (grad X)^T (grad X) P (P = I - n n), which is (F_s F_s^T)^+ on the tangent plane,
//   Gs = (M + n n)^-1 - n n,
// the pseudo-inverse of M: only tangential derivatives of X enter (a map extended along the
// normals has none across), Gs n = 0 exactly, and for X = A^-1 (x - c) around a sphere it is
// A P_R A^T (Milcent & Maitre 2016 form the same tensor as K - (K n)(K n)^T / (n K n),
// K = (grad X^T grad X)^-1, equal to it when grad X is invertible).
#pragma once

#include "core/types.hpp"

#include <array>

namespace efsi {

class Shape;

/// Gs from the map's gradient `gx` (gx[a][b] = d X_a / d x_b) and the unit normal `n`
/// (entries past `dim` are ignored; in 2D the z stretch is 1 and Gs_zz = 1).
Matrix3 surface_tensor_from_map(const Matrix3& gx, const Real3& n, int dim);

/// T turned so that the plane it lies in becomes the plane normal to n: R T R^T, R the
/// smallest rotation that takes T's null direction m (the normal of its own plane: for a
/// surface tensor mean over the cells at a foot point, the foot point's normal) onto n.
/// Unlike the projection P T P (P = I - n n), which shrinks the tilted direction by the
/// cosine of the tilt and with it the area, the rotation keeps T's trace and area ratio.
/// 3D: m is the cross product of two rows of T (they span its plane), the pair spanning the
/// most; 2D: the in-plane perpendicular of the longer row of the xy block (z untouched).
Matrix3 turned_into_plane(const Matrix3& T, const Real3& n, int dim);

/// The reference surface's point nearest to the map value X (map_projection): the reference
/// configuration of every surface point lies on the shape's surface, so a band cell's X (its
/// foot point's) does too. Along a periodic direction X may hold the body's image one period
/// away (the offset X - x is carried continuously while x wraps): the image nearest the
/// shape's centre is projected and shifted back. In 2D the surface is the shape's section
/// z = `z2d` (the plane the initial profile was computed in) and only x and y move.
Real3 onto_reference_surface(const Shape& shape, const Real3& X, int dim,
                             const std::array<bool, 3>& periodic, const Real3& period, real z2d);

} // namespace efsi
