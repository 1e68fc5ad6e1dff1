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
    auto normal = [&](const Int3& p) {
        Real3 gp = central_gradient(psi_a_, g, p);
        real g2 = 0;
        for (int d = 0; d < dim; ++d)
            g2 += gp[d] * gp[d];
        if (g2 > 0)
            for (int d = 0; d < dim; ++d)
                gp[d] /= std::sqrt(g2);
        return gp;
    };
    for (int it = 0; it < iterations_; ++it) {
        halos_.fill(phi, body.patch());
        for_each_in(stored, [&](int i, int j, int k) {
            psi_a_(i, j, k) = -profile_distance(phi(i, j, k), 2 * e);
        });
        for_each_in(phi.owned(), [&](int i, int j, int k) {
            const Int3 p{i, j, k};
            const real f0 = phi(p);
            const Real3 np = normal(p);
            real div = 0;
            for (int d = 0; d < dim; ++d)
                for (int side = 0; side < 2; ++side) {
                    const Int3 q = shifted(p, d, side ? 1 : -1);
                    const real f1 = phi(q);
                    // No flux between two empty or two full cells: nothing leaves the patch.
                    if ((f0 <= empty_cut && f1 <= empty_cut) ||
                        (f0 >= 1 - empty_cut && f1 >= 1 - empty_cut))
                        continue;
                    const Real3 nq = normal(q);
                    const real lo = side ? psi_a_(p) : psi_a_(q);
                    const real hi = side ? psi_a_(q) : psi_a_(p);
                    const real th = std::tanh(0.5 * (lo + hi) / (2 * e));
                    const real n_f = 0.5 * (np[d] + nq[d]);
                    // The flux along +d through the face: the divergence takes it with + on
                    // the cell's high face and - on its low face.
                    const real flux = 0.25 * (1 - th * th) * ((hi - lo) / h - n_f);
                    div += (side ? flux : -flux) / h;
                }
            work_(p) = f0 + dtau * div;
        });
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
