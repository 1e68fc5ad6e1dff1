// Membrane kinematics at a point, from the unit normal n and the surface tensor Gs.
//
// MODEL.md, "Membrane": Gs = F P_R F^T is carried on the grid; with n the unit normal of
// the current surface and P = I - n n the tangential projection,
//   Bs  = P Gs P                                (surface left Cauchy-Green tensor)
//   Is  = tr(Bs) - 2,  IIs = (tr(Bs)^2 - tr(Bs Bs)) / 2 - 1,  J = sqrt(IIs + 1)
// Bs has eigenvalues lambda1^2, lambda2^2 (the principal stretches) and 0 (along n), so
// Is = lambda1^2 + lambda2^2 - 2, IIs = lambda1^2 lambda2^2 - 1 and J = lambda1 lambda2 is
// the local area ratio. In 2D (z-invariant) runs n has no z component and Gs_zz = 1 is
// implicit (SymmetricTensorField::value), so the same 3D formulas apply: the z direction
// is a tangent with stretch 1 (the membrane is a cylinder surface).
#pragma once

#include "core/types.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace efsi {

struct MembraneKinematics {
    Matrix3 P{};  ///< I - n n
    Matrix3 Bs{}; ///< P Gs P
    real Is = 0;  ///< tr(Bs) - 2
    real IIs = 0; ///< det of Bs on the tangent plane, minus 1
    real J = 1;   ///< area ratio sqrt(IIs + 1)
};

/// Second invariant (tr(A)^2 - tr(A A)) / 2 of a 3 x 3 tensor: lambda1^2 lambda2^2 = J^2 for
/// a surface tensor (Bs, or Gs itself, whose third eigenvalue is 0).
inline real second_invariant(const Matrix3& A) {
    real tr = 0, tr2 = 0;
    for (int a = 0; a < 3; ++a) {
        tr += A[a][a];
        for (int b = 0; b < 3; ++b)
            tr2 += A[a][b] * A[b][a];
    }
    return 0.5 * (tr * tr - tr2);
}

/// P A P (P = I - n n) of a symmetric A, over the first `dim` rows and columns:
/// A - n (A n)^T - (A n) n^T + (n.A.n) n n^T.
inline Matrix3 tangential_part(const Matrix3& A, const Real3& n, int dim) {
    Real3 an{0, 0, 0};
    for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b)
            an[a] += A[a][b] * n[b];
    real n_an = 0;
    for (int a = 0; a < dim; ++a)
        n_an += n[a] * an[a];
    Matrix3 T{};
    for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b)
            T[a][b] = A[a][b] - n[a] * an[b] - an[a] * n[b] + n_an * n[a] * n[b];
    return T;
}

/// Kinematics from a unit normal n and the (symmetric) surface tensor Gs.
inline MembraneKinematics membrane_kinematics(const Real3& n, const Matrix3& Gs) {
    MembraneKinematics k;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            k.P[a][b] = (a == b ? 1.0 : 0.0) - n[a] * n[b];
    Matrix3 GP{}; // Gs P
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            for (int c = 0; c < 3; ++c)
                GP[a][b] += Gs[a][c] * k.P[c][b];
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            real s = 0;
            for (int c = 0; c < 3; ++c)
                s += k.P[a][c] * GP[c][b];
            k.Bs[a][b] = s;
        }
    k.Is = k.Bs[0][0] + k.Bs[1][1] + k.Bs[2][2] - 2;
    k.IIs = second_invariant(k.Bs) - 1;
    // IIs + 1 = lambda1^2 lambda2^2 > 0 for any admissible Gs; the clamp only guards
    // against a round-off negative value where Gs is degenerate (far outside the band).
    k.J = std::sqrt(std::max(k.IIs + 1, real(1e-300)));
    return k;
}

} // namespace efsi
