#include "membrane/reference_map.hpp"

#include "core/matrix3.hpp"

namespace efsi {

Matrix3 surface_tensor_from_map(const Matrix3& gx, const Real3& n, int dim) {
    // C = grad X^T grad X (dim x dim), then M = P C P.
    Matrix3 C{};
    for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b)
            for (int c = 0; c < dim; ++c)
                C[a][b] += gx[c][a] * gx[c][b];
    Real3 cn{0, 0, 0};
    for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b)
            cn[a] += C[a][b] * n[b];
    real ncn = 0;
    for (int a = 0; a < dim; ++a)
        ncn += n[a] * cn[a];
    Matrix3 M = identity_matrix(); // the z row and column stay 1 in 2D (no z stretch)
    for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b)
            M[a][b] = C[a][b] - n[a] * cn[b] - cn[a] * n[b] + ncn * n[a] * n[b] + n[a] * n[b];
    Matrix3 G = inverse(M);
    for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b)
            G[a][b] -= n[a] * n[b];
    return G;
}

} // namespace efsi
