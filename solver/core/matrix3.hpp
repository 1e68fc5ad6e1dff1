// Small 3x3 algebra on Matrix3 (core/types.hpp): cross product, product with a vector, transpose,
// inverse and determinant by cofactors. Written out (no Eigen) so that every sum keeps the order
// the results were verified with (docs/method.md, "Small tensors").
#pragma once

#include "core/types.hpp"

namespace efsi {

inline Matrix3 identity_matrix() {
    return {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
}

/// M x.
inline Real3 mat_vec(const Matrix3& M, const Real3& x) {
    Real3 y{};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            y[a] += M[a][b] * x[b];
    return y;
}

/// a x b.
inline Real3 cross(const Real3& a, const Real3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

inline Matrix3 transpose(const Matrix3& M) {
    Matrix3 T{};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            T[a][b] = M[b][a];
    return T;
}

/// M^-1 as the transposed cofactor matrix over det M (expanded along the first row).
inline Matrix3 inverse(const Matrix3& M) {
    Matrix3 C{};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            const int a1 = (a + 1) % 3, a2 = (a + 2) % 3, b1 = (b + 1) % 3, b2 = (b + 2) % 3;
            C[b][a] = M[a1][b1] * M[a2][b2] - M[a1][b2] * M[a2][b1];
        }
    const real det = M[0][0] * C[0][0] + M[0][1] * C[1][0] + M[0][2] * C[2][0];
    for (auto& row : C)
        for (real& v : row)
            v /= det;
    return C;
}

inline real determinant(const Matrix3& M) {
    return M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
           M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
           M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
}

} // namespace efsi
