#include "membrane/membrane_force.hpp"

#include <algorithm>
#include <cmath>

namespace efsi {

namespace {

bool inside(const Box& b, const Int3& p) {
    for (int d = 0; d < 3; ++d)
        if (p[d] < b.lo[d] || p[d] >= b.hi[d]) return false;
    return true;
}

} // namespace

Tensor33 membrane_stress_at(const Field& phi, const SymmetricTensorField& Gs,
                            const MembraneLaw& law, const GlobalGrid& g,
                            const MembraneForceSettings& s, const Int3& p, bool& in_band) {
    const real eps = s.smoothing_width * g.dx(0);
    in_band = false;
    const int r2 = g.dim == 3 ? 1 : 0;
    for (int c = -r2; c <= r2; ++c)
        for (int b = -1; b <= 1; ++b)
            for (int a = -1; a <= 1; ++a) {
                const real v = phi(p[0] + a, p[1] + b, p[2] + c);
                if (!(v > s.band_cutoff && v < 1 - s.band_cutoff)) return Tensor33{};
            }
    const Real3 gr = gradient_at(phi, g, p, s.stencil, eps);
    const real mag = std::sqrt(gr[0] * gr[0] + gr[1] * gr[1] + gr[2] * gr[2]);
    // The smoothed delta |grad phi|. With the distance stencil gr = grad psi and, since
    // phi = (1 + tanh(psi/eps))/2, grad phi = phi'(psi) grad psi with
    // phi'(psi) = (1 - tanh^2)/(2 eps) = 2 phi (1 - phi) / eps: the profile is evaluated
    // exactly and only the (linear) psi is differenced.
    real delta = mag;
    if (s.stencil == GradientStencil::Distance) {
        const real c = std::clamp(phi(p), 1e-9, 1 - 1e-9);
        delta = 2 * c * (1 - c) / eps * mag;
    }
    in_band = mag > 0;
    Tensor33 S{};
    if (!in_band) return S;
    const Real3 n{gr[0] / mag, gr[1] / mag, gr[2] / mag};
    Tensor33 G{};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            G[a][b] = Gs.value(a, b, p);
    const Tensor33 tau = law.tension(membrane_kinematics(n, G));
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            S[a][b] = delta * tau[a][b];
    return S;
}

MembraneForce::MembraneForce(const GlobalGrid& g, const HaloFiller& halos,
                             MembraneForceSettings settings)
    : g_(g), halos_(halos), settings_(settings) {}

void MembraneForce::allocate(const Patch& patch) {
    const int dim = g_.dim;
    stress_ = SymmetricTensorField{};
    stress_.dim = dim;
    stress_.zz_2d = 0; // S_zz of a 2D run is never used (no z derivative, no z force)
    for (int c = 0; c < SymmetricTensorField::count(dim); ++c)
        stress_.comp.push_back(Field::on_patch(SymmetricTensorField::component_name("S", c, dim),
                                               Location::Cell, patch.local.lo, patch.local.size(),
                                               dim, 1));
    stress_box_ = patch.local;
    band_.clear();
}

void MembraneForce::add(Body& body, const MembraneLaw& law, VelocityField& force) {
    const Patch& patch = body.patch();
    const int dim = g_.dim;
    if (patch.empty()) return;
    halos_.fill(body.phi(), patch);
    for (Field& c : body.tensor().comp)
        halos_.fill(c, patch);

    if (stress_.comp.empty() || !(stress_box_ == patch.local)) allocate(patch);
    for (const Int3& q : band_) // clear the previous band only
        for (Field& c : stress_.comp)
            c(q) = 0;
    band_.clear();

    // Pass 1: S = |grad phi| tau_s on the owned cells and one halo layer, band only.
    Box grown = patch.local;
    for (int d = 0; d < dim; ++d) {
        grown.lo[d] -= 1;
        grown.hi[d] += 1;
    }
    for_each_in(grown, [&](int i, int j, int k) {
        const Int3 q{i, j, k};
        bool in_band = false;
        const Tensor33 S =
            membrane_stress_at(body.phi(), body.tensor(), law, g_, settings_, q, in_band);
        if (!in_band) return;
        for (int a = 0; a < dim; ++a)
            for (int b = a; b < dim; ++b)
                stress_.comp[SymmetricTensorField::slot(a, b, dim)](q) = S[a][b];
        band_.push_back(q);
    });

    // Pass 2: scatter the staggered divergence of S from each band cell q to the faces
    // whose stencil contains q (the transpose of the gather formula in the header), on the
    // faces of the patch's owned cells.
    const Box& faces = patch.local;
    auto add_to = [&](int d, const Int3& p, real v) {
        if (inside(faces, p)) force[d](p) += v;
    };
    for (const Int3& q : band_)
        for (int d = 0; d < dim; ++d) {
            const Int3 ed = unit(d);
            const real Sdd = stress_.value(d, d, q) / g_.dx(d);
            add_to(d, q, Sdd);
            add_to(d, {q[0] + ed[0], q[1] + ed[1], q[2] + ed[2]}, -Sdd);
            for (int k = 0; k < dim; ++k) {
                if (k == d) continue;
                const Int3 ek = unit(k);
                const real v = stress_.value(d, k, q) / (4 * g_.dx(k));
                Int3 p = q; // q = p + e_k and q = p + e_k - e_d
                for (int a = 0; a < 3; ++a)
                    p[a] -= ek[a];
                add_to(d, p, v);
                add_to(d, {p[0] + ed[0], p[1] + ed[1], p[2] + ed[2]}, v);
                p = q; // q = p - e_k and q = p - e_k - e_d
                for (int a = 0; a < 3; ++a)
                    p[a] += ek[a];
                add_to(d, p, -v);
                add_to(d, {p[0] + ed[0], p[1] + ed[1], p[2] + ed[2]}, -v);
            }
        }
}

} // namespace efsi
