#include "membrane/reference_map.hpp"

#include "core/matrix3.hpp"
#include "interface/shapes.hpp"
#include "membrane/kinematics.hpp"

#include <algorithm>
#include <cmath>

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

Real3 onto_reference_surface(const Shape& shape, const Real3& X, int dim,
                             const std::array<bool, 3>& periodic, const Real3& period, real z2d) {
    Real3 y = X, shift{0, 0, 0};
    for (int d = 0; d < dim; ++d)
        if (periodic[d] && period[d] > 0) {
            shift[d] = period[d] * std::round((X[d] - shape.centre()[d]) / period[d]);
            y[d] -= shift[d];
        }
    if (dim == 3) {
        y = shape.closest_point(y);
    } else {
        // Newton steps in the plane z = z2d along the level's in-plane gradient.
        y[2] = z2d;
        const real scale = std::max(
            {std::abs(y[0] - shape.centre()[0]), std::abs(y[1] - shape.centre()[1]), real(1e-300)});
        y = newton_onto_zero_level([&shape](const Real3& p) { return shape.level(p); }, y, 2,
                                   scale);
        y[2] = X[2];
    }
    for (int d = 0; d < dim; ++d)
        y[d] += shift[d];
    return y;
}

} // namespace efsi
