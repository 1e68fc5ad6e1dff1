// Interface geometry from a volume fraction phi: normals and curvature.
//
// Convention (MODEL.md): n = grad phi / |grad phi| points into the body (phi = 1 inside);
// the curvature tensor is kappa = -grad n and the mean curvature kappa_m = -div(n) / 2
// (1/R for a sphere of radius R).
//
// The gradient is a central difference along d averaged over the transverse neighbours
// with weights w = (a, 1 - 2a, a) in each transverse direction:
//   central    a = 0     (no averaging)
//   youngs     a = 1/4   (1, 2, 1)/4, Youngs' stencil
//   isotropic  a = 1/6   (1, 4, 1)/6
// For phi = f(n.x) (a planar front), the O(h^2) error of the d-component is
// h^2 f''' n_d (n_d^2/6 + a (1 - n_d^2)) / ... ; only a = 1/6 makes it proportional to n_d,
// so the direction of the isotropic gradient is exact to O(h^4) for any tilt, while the
// other two leave an O(h^2 f'''/f') direction error, which is O(1) when phi is smoothed
// over a fixed number of cells.
//
//   distance   for a smoothed phi = (1 + tanh(psi / eps)) / 2 (the membrane's smoothed
//              VOF), the profile is inverted, psi = eps atanh(2 phi - 1), and the
//              isotropic stencil is applied to psi. psi is a distance-like function,
//              linear across the band, so its differences carry no 1/eps factors and the
//              normal is second order with the width fixed in cells. phi is clipped to
//              [1e-9, 1 - 1e-9] first (psi saturates ~10 eps away from the surface).
#pragma once

#include "grid/box.hpp"
#include "grid/field.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

namespace efsi {

enum class GradientStencil { Central, Youngs, Isotropic, Distance };

GradientStencil gradient_stencil_from_string(const std::string& s);

/// Signed distance to the surface (positive outside) read off a smoothed phi = (1 -
/// tanh(psi / eps)) / 2: psi = eps atanh(1 - 2 phi), the argument clamped to 1 - 1e-15 so
/// that empty and full cells give a finite psi (~17.6 eps).
/// Most cells of a patch are empty or full, so the two clamped ends are looked up, not
/// recomputed (the same values: atanh of the same clamped argument).
inline real profile_distance(real phi, real eps) {
    constexpr real lo = -1 + 1e-15, hi = 1 - 1e-15;
    static const real at_lo = std::atanh(lo), at_hi = std::atanh(hi);
    const real x = 1 - 2 * phi;
    if (x >= hi) return eps * at_hi;
    if (x <= lo) return eps * at_lo;
    return eps * std::atanh(x);
}

/// Central-difference gradient of a cell field at p (needs one halo layer).
inline Real3 central_gradient(const Field& f, const GlobalGrid& g, const Int3& p) {
    Real3 gp{0, 0, 0};
    for (int d = 0; d < g.dim; ++d) {
        Int3 lo = p, hi = p;
        --lo[d];
        ++hi[d];
        gp[d] = (f(hi) - f(lo)) / (2 * g.dx(d));
    }
    return gp;
}

/// The weighted central gradient at cell p of value(phi): the difference along d averaged
/// over the transverse neighbours with the weights (a, 1 - 2a, a) per direction. The points
/// are read through one base pointer and the field's strides, so that a loop calling it
/// with a fixed stencil gets constant weights and unrolled sums.
template <class Value>
Real3 weighted_gradient(const Field& phi, const GlobalGrid& g, const Int3& p, real a,
                        Value&& value) {
    const int dim = g.dim;
    const real w[3] = {a, 1 - 2 * a, a};
    const Int3& e = phi.extent();
    const std::ptrdiff_t stride[3] = {1, e[0], std::ptrdiff_t(e[0]) * e[1]};
    const real* const centre = phi.data().data() + phi.index(p[0], p[1], p[2]);
    Real3 grad{0, 0, 0};
    for (int d = 0; d < dim; ++d) {
        // The two transverse directions (the second is absent in 2D).
        const int t1 = (d + 1) % 3, t2 = (d + 2) % 3;
        const int r1 = t1 < dim ? 1 : 0, r2 = t2 < dim ? 1 : 0;
        real acc = 0;
        for (int o1 = -r1; o1 <= r1; ++o1)
            for (int o2 = -r2; o2 <= r2; ++o2) {
                const real* q = centre + o1 * stride[t1] + o2 * stride[t2];
                const real weight = (r1 ? w[o1 + 1] : 1.0) * (r2 ? w[o2 + 1] : 1.0);
                acc += weight * (value(q[stride[d]]) - value(q[-stride[d]]));
            }
        grad[d] = acc / (2 * g.dx(d));
    }
    return grad;
}

/// Gradient of a cell field at cell p with the chosen transverse weighting.
/// For `Distance`, `eps` is the smoothing width of phi's tanh profile: the isotropic
/// weights on psi = eps atanh(2 phi - 1).
inline Real3 gradient_at(const Field& phi, const GlobalGrid& g, const Int3& p, GradientStencil st,
                         real eps = 0) {
    if (st == GradientStencil::Distance)
        return weighted_gradient(phi, g, p, 1.0 / 6.0, [eps](real v) {
            const real c = std::clamp(v, 1e-9, 1 - 1e-9);
            return eps * std::atanh(2 * c - 1);
        });
    const real a = st == GradientStencil::Central  ? 0.0
                   : st == GradientStencil::Youngs ? 0.25
                                                   : 1.0 / 6.0;
    return weighted_gradient(phi, g, p, a, [](real v) { return v; });
}

/// Unit normals n = grad phi / |grad phi| on `box` (zero where |grad phi| < tiny).
void compute_normals(const Field& phi, const GlobalGrid& g, const Box& box, GradientStencil st,
                     std::array<Field, 3>& n, real eps = 0);

/// Mean curvature -div(n)/2 at cell p by central differences of the normal field.
real mean_curvature_at(const std::array<Field, 3>& n, const GlobalGrid& g, int dim, const Int3& p);

/// Curvature of the level set of a function L (negative inside the body) through a point,
/// from its gradient g and Hessian H there: kappa = -div(n) / (dim - 1) with the inward
/// n = -g / |g|, i.e. -div(n) = (tr H - g.H.g / |g|^2) / |g|. The mean of the principal curvatures
/// over the directions a surface can bend: two in 3D; one in 2D, where the z-invariant
/// cylinder surface has straight generators. 1/R on a sphere or circle of radius R. This
/// is the membrane's reference curvature kappa_R (docs/method.md, "Membrane bending").
real level_set_curvature(const Matrix3& H, const Real3& grad, int dim);

} // namespace efsi
