#include "interface/conservative_reinit.hpp"

#include "interface/geometry.hpp"
#include "operators/flow_operators.hpp"

#include <algorithm>
#include <cmath>

namespace efsi {

ConservativeReinit::ConservativeReinit(const HaloFiller& halos, real eps_cells, int iterations)
    : halos_(halos), eps_cells_(eps_cells), iterations_(iterations) {}

ReinitStats ConservativeReinit::apply(Body& body) {
    ReinitStats stats;
    if (iterations_ <= 0) return stats;
    const Decomposition& dec = halos_.decomposition();
    const GlobalGrid& g = dec.grid();
    const int dim = g.dim;
    Field& phi = body.phi();
    const bool empty = body.patch().empty();
    if (empty) return stats; // the patch's exchanges pair only the ranks that hold a part
    if (work_.data().empty() || work_.begin() != phi.begin() || work_.cells() != phi.cells()) {
        work_ = Field::on_patch("phi_reinit", Location::Cell, phi.begin(), phi.cells(), dim, 2);
        psi_a_ = Field::on_patch("psi_a", Location::Cell, phi.begin(), phi.cells(), dim, 2);
        for (int t = 0; t < dim; ++t)
            grad_[t] =
                Field::on_patch("grad_psi_a", Location::Cell, phi.begin(), phi.cells(), dim, 2);
    }
    const real h = g.dx(0);
    const real e = 0.5 * eps_cells_ * h;
    const real dtau = h * h / (4 * dim * e);
    const real dv = g.cell_volume();
    constexpr real empty_cut = 1e-8; // the VOF's empty / full threshold
    // The stored box of phi (owned cells and both halo layers).
    Box stored = phi.owned();
    for (int d = 0; d < dim; ++d) {
        stored.lo[d] -= 2;
        stored.hi[d] += 2;
    }
    // psi_a on owned cells and both halo layers; its fourth-order central gradient, each
    // component t on the owned box widened by 2 in every direction but t (where the faces'
    // interpolations reach), needs no more.
    auto widened = [&](int keep) {
        Box b = phi.owned();
        for (int d = 0; d < dim; ++d)
            if (d != keep) {
                b.lo[d] -= 2;
                b.hi[d] += 2;
            }
        return b;
    };
    for (int it = 0; it < iterations_; ++it) {
        halos_.fill(phi, body.patch());
        for_each_in(stored, [&](int i, int j, int k) {
            psi_a_(i, j, k) = -profile_distance(phi(i, j, k), 2 * e);
        });
        for (int t = 0; t < dim; ++t) {
            Field& gt = grad_[t];
            for_each_in(widened(t), [&](int i, int j, int k) {
                const Int3 p{i, j, k};
                const real d1 = psi_a_(shifted(p, t, 1)) - psi_a_(shifted(p, t, -1));
                const real d2 = psi_a_(shifted(p, t, 2)) - psi_a_(shifted(p, t, -2));
                gt(p) = (8 * d1 - d2) / (12 * h);
            });
        }
        for_each_in(phi.owned(), [&](int i, int j, int k) { work_(i, j, k) = phi(i, j, k); });
        for (int d = 0; d < dim; ++d) {
            // Faces p + 1/2 e_d of the owned cells and the one below the first.
            Box faces = phi.owned();
            --faces.lo[d];
            for_each_in(faces, [&](int i, int j, int k) {
                const Int3 p{i, j, k};
                const Int3 q = shifted(p, d, 1);
                const real f0 = phi(p), f1 = phi(q);
                real flux = 0;
                // No flux between two empty or two full cells: nothing leaves the patch.
                if (!((f0 <= empty_cut && f1 <= empty_cut) ||
                      (f0 >= 1 - empty_cut && f1 >= 1 - empty_cut))) {
                    const real lo = psi_a_(p), hi = psi_a_(q);
                    // Fourth-order face derivative and tangential gradient, so that the
                    // flux vanishes where |grad psi_a| = 1 to the curvature's O(h^4).
                    const real gd =
                        (27 * (hi - lo) - (psi_a_(shifted(q, d, 1)) - psi_a_(shifted(p, d, -1)))) /
                        (24 * h);
                    real g2 = gd * gd;
                    for (int t = 0; t < dim; ++t) {
                        if (t == d) continue;
                        const Field& gt = grad_[t];
                        const real gf =
                            (9 * (gt(p) + gt(q)) - (gt(shifted(p, d, -1)) + gt(shifted(q, d, 1)))) /
                            16;
                        g2 += gf * gf;
                    }
                    const real th = std::tanh(0.5 * (lo + hi) / (2 * e));
                    if (g2 > 0) flux = 0.25 * (1 - th * th) * gd * (1 - 1 / std::sqrt(g2));
                }
                // The flux along +d leaves p and enters q.
                const real change = dtau * flux / h;
                if (p[d] >= phi.owned().lo[d]) work_(p) += change;
                if (q[d] < phi.owned().hi[d]) work_(q) -= change;
            });
        }
        for_each_in(phi.owned(), [&](int i, int j, int k) {
            const real v = work_(i, j, k);
            const real c = std::clamp(v, 0.0, 1.0);
            stats.clipped_volume += std::abs(c - v) * dv;
            phi(i, j, k) = c;
        });
    }
    halos_.fill(phi, body.patch());
    return stats;
}

} // namespace efsi
