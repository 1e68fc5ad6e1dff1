#include "interface/geometry.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>

namespace efsi {

GradientStencil gradient_stencil_from_string(const std::string& s) {
    if (s == "central") return GradientStencil::Central;
    if (s == "youngs") return GradientStencil::Youngs;
    if (s == "isotropic") return GradientStencil::Isotropic;
    if (s == "distance") return GradientStencil::Distance;
    throw InputError("normal stencil '" + s +
                     "' is unknown (central, youngs, isotropic, distance)");
}

void compute_normals(const Field& phi, const GlobalGrid& g, const Box& box, GradientStencil st,
                     std::array<Field, 3>& n, real eps) {
    for_each_in(box, [&](int i, int j, int k) {
        const Real3 gr = gradient_at(phi, g, {i, j, k}, st, eps);
        const real mag = std::sqrt(gr[0] * gr[0] + gr[1] * gr[1] + gr[2] * gr[2]);
        for (int d = 0; d < g.dim; ++d)
            n[d](i, j, k) = mag > 1e-12 / g.dx(0) ? gr[d] / mag : 0.0;
    });
}

real mean_curvature_at(const std::array<Field, 3>& n, const GlobalGrid& g, int dim, const Int3& p) {
    real div = 0;
    for (int d = 0; d < dim; ++d) {
        Int3 qp = p, qm = p;
        qp[d] += 1;
        qm[d] -= 1;
        div += (n[d](qp) - n[d](qm)) / (2 * g.dx(d));
    }
    return -0.5 * div;
}

real level_set_curvature(const Matrix3& H, const Real3& grad, int dim) {
    real g2 = 0;
    for (int a = 0; a < dim; ++a)
        g2 += grad[a] * grad[a];
    if (!(g2 > 0)) return 0;
    const real mag = std::sqrt(g2);
    real tr = 0, nhn = 0;
    for (int a = 0; a < dim; ++a) {
        tr += H[a][a];
        for (int b = 0; b < dim; ++b)
            nhn += grad[a] * H[a][b] * grad[b] / g2;
    }
    return (tr - nhn) / (mag * (dim - 1));
}

} // namespace efsi
