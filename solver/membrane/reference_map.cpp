#include "membrane/reference_map.hpp"

#include "core/matrix3.hpp"
#include "membrane/kinematics.hpp"

namespace efsi {

Matrix3 surface_tensor_from_map(const Matrix3& gx, const Real3& n, int dim) {
    // C = grad X^T grad X (dim x dim), then M = P C P.
    Matrix3 C{};
    for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b)
            for (int c = 0; c < dim; ++c)
                C[a][b] += gx[c][a] * gx[c][b];
    const Matrix3 T = tangential_part(C, n, dim);
    Matrix3 M = identity_matrix(); // the z row and column stay 1 in 2D (no z stretch)
    for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b)
            M[a][b] = T[a][b] + n[a] * n[b];
    Matrix3 G = inverse(M);
    for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b)
            G[a][b] -= n[a] * n[b];
    return G;
}

} // namespace efsi
