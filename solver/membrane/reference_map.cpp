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

Matrix3 turned_into_plane(const Matrix3& T, const Real3& n, int dim) {
    auto dot = [](const Real3& a, const Real3& b) {
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    };
    auto cross = [](const Real3& a, const Real3& b) {
        return Real3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]};
    };
    Real3 m{0, 0, 0};
    if (dim == 3) {
        real best = 0;
        for (int a = 0; a < 3; ++a)
            for (int b = a + 1; b < 3; ++b) {
                const Real3 c = cross(T[a], T[b]);
                if (dot(c, c) > best) {
                    best = dot(c, c);
                    m = c;
                }
            }
    } else {
        const Real3& r =
            T[0][0] * T[0][0] + T[0][1] * T[0][1] >= T[1][0] * T[1][0] + T[1][1] * T[1][1] ? T[0]
                                                                                           : T[1];
        m = Real3{-r[1], r[0], 0};
    }
    const real norm = std::sqrt(dot(m, m));
    if (!(norm > 0)) return T;
    for (real& c : m)
        c /= norm;
    if (dot(m, n) < 0)
        for (real& c : m)
            c = -c;
    // Rodrigues: R = I + [v]x + [v]x^2 / (1 + c), v = m x n, c = m . n >= 0.
    const Real3 v = cross(m, n);
    const real c = dot(m, n);
    const Matrix3 K{Real3{0, -v[2], v[1]}, Real3{v[2], 0, -v[0]}, Real3{-v[1], v[0], 0}};
    Matrix3 R = identity_matrix();
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            real kk = 0;
            for (int e = 0; e < 3; ++e)
                kk += K[a][e] * K[e][b];
            R[a][b] += K[a][b] + kk / (1 + c);
        }
    Matrix3 RT{}, out{};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            for (int e = 0; e < 3; ++e)
                RT[a][b] += R[a][e] * T[e][b];
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            for (int e = 0; e < 3; ++e)
                out[a][b] += RT[a][e] * R[b][e];
    return out;
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
