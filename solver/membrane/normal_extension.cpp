#include "membrane/normal_extension.hpp"

#include "bodies/symmetric_tensor.hpp"
#include "core/error.hpp"
#include "interface/geometry.hpp"
#include "operators/flow_operators.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace efsi {

real NormalExtension::default_reach(real eps_cells) {
    return std::atanh(1 - 2 * 1e-5) * eps_cells + 2;
}

NormalExtension::NormalExtension(const HaloFiller& halos, const std::string& body_name,
                                 real eps_cells, real core_cells, real reach_cells)
    : halos_(halos), eps_cells_(eps_cells), core_cells_(core_cells),
      reach_cells_(reach_cells > 0 ? reach_cells : default_reach(eps_cells)) {
    // The foot point is |y - x| = |psi| <= reach cells away (n is a unit vector), and the
    // trilinear stencil reads one cell beyond it (plus one for the cell-centre offset).
    const Decomposition& dec = halos.decomposition();
    wide_halo_ = int(std::ceil(reach_cells_)) + 2;
    for (int d = 0; d < dec.dim(); ++d) {
        const int thinnest = int(std::lround(dec.min(real(dec.block().cells[d]))));
        if (thinnest < wide_halo_)
            throw InputError(fmt::format(
                "body '{}': strain_extension = \"normal\" needs every rank's block to be at "
                "least {} cells wide, but one is {} cells wide along {} ({} ranks along it); "
                "run on fewer ranks, lay them out along wider directions (parallel.ranks) or set "
                "body.strain_extension = \"layers\"",
                body_name, wide_halo_, thinnest, "xyz"[d], dec.ranks_per_dim()[d]));
    }
}

void NormalExtension::apply(Body& body) {
    SymmetricTensorField& G = body.tensor();
    if (G.comp.empty()) return;
    const Decomposition& dec = halos_.decomposition();
    const GlobalGrid& g = dec.grid();
    const LocalBlock& block = dec.block();
    const int dim = g.dim;
    const int ncomp = int(G.comp.size());
    const bool empty = body.patch().empty();
    Field& phi = body.phi();
    const real h = g.dx(0);
    const real eps = eps_cells_ * h;
    if (!empty) {
        if (psi_.data().empty() || psi_.begin() != phi.begin() || psi_.cells() != phi.cells()) {
            psi_ = Field::on_patch("psi", Location::Cell, phi.begin(), phi.cells(), dim, 1);
            src_.clear();
            for (int s = 0; s < ncomp; ++s)
                src_.push_back(Field::on_patch("Gs_source", Location::Cell, phi.begin(),
                                               phi.cells(), dim, wide_halo_));
        }
        for_each_in(phi.owned(), [&](int i, int j, int k) {
            psi_(i, j, k) = profile_distance(phi(i, j, k), eps);
            for (int s = 0; s < ncomp; ++s)
                src_[s](i, j, k) = G.comp[s](i, j, k);
        });
    }
    // Collective: every rank with a part of the patch takes part (the patch's exchange
    // flags pair the ranks).
    if (empty) return;
    halos_.fill(psi_, body.patch());
    for (Field& f : src_)
        halos_.fill(f, body.patch());

    const real core = core_cells_ * h;
    const real reach = reach_cells_ * h;
    // Trilinear interpolation at x from cell centres: a convex combination, so the extension
    // makes no new extrema. (Tricubic Catmull-Rom, exact for quadratics, was tried: it moved
    // D(1) of the d/8 Ca 0.05 capsule by 1 % only, and the d/8 Ca 0.2 run that completes
    // t = 10 with trilinear stopped UNSTABLE at t = 1.9 with it; docs/method.md.)
    auto value = [&](const Field& f, const Real3& x) {
        Int3 base{0, 0, 0};
        std::array<real, 3> t{0, 0, 0};
        for (int d = 0; d < dim; ++d) {
            const real u = (x[d] - g.origin[d]) / g.dx(d) - block.offset[d] - 0.5;
            base[d] = int(std::floor(u));
            t[d] = u - base[d];
        }
        real r = 0;
        const int kz = dim == 3 ? 2 : 1;
        for (int c = 0; c < kz; ++c)
            for (int b = 0; b < 2; ++b)
                for (int a = 0; a < 2; ++a) {
                    const real w = (a ? t[0] : 1 - t[0]) * (b ? t[1] : 1 - t[1]) *
                                   (dim == 3 ? (c ? t[2] : 1 - t[2]) : 1.0);
                    r += w * f(base[0] + a, base[1] + b, base[2] + c);
                }
        return r;
    };
    for_each_in(phi.owned(), [&](int i, int j, int k) {
        const Int3 p{i, j, k};
        const real s = psi_(p);
        const Real3 gp = central_gradient(psi_, g, p);
        real g2 = 0;
        for (int d = 0; d < dim; ++d)
            g2 += gp[d] * gp[d];
        std::array<std::array<real, 3>, 3> T{};
        if (std::abs(s) > reach || g2 < 0.25) {
            for (int s2 = 0; s2 < ncomp; ++s2)
                G.comp[s2](p) = 0;
            for (int a = 0; a < dim; ++a)
                G.comp[SymmetricTensorField::slot(a, a, dim)](p) = 1;
            return;
        }
        Real3 n{0, 0, 0};
        for (int d = 0; d < dim; ++d)
            n[d] = gp[d] / std::sqrt(g2);
        if (std::abs(s) <= core) {
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    T[a][b] = G.value(a, b, p);
        } else {
            Real3 y = position(g, block, Location::Cell, i, j, k);
            for (int d = 0; d < dim; ++d)
                y[d] -= s * n[d];
            std::array<real, 6> v{};
            for (int s2 = 0; s2 < ncomp; ++s2)
                v[s2] = value(src_[s2], y);
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) {
                    const int sl = SymmetricTensorField::slot(a, b, dim);
                    T[a][b] = sl >= 0 ? v[sl] : (a == 2 && b == 2 ? G.zz_2d : 0.0);
                }
        }
        // P T P with P = I - n n: T - n (n.T) - (T.n) n + (n.T.n) n n.
        Real3 tn{0, 0, 0};
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                tn[a] += T[a][b] * n[b];
        real ntn = 0;
        for (int a = 0; a < 3; ++a)
            ntn += n[a] * tn[a];
        for (int a = 0; a < 3; ++a)
            for (int b = a; b < 3; ++b) {
                const int sl = SymmetricTensorField::slot(a, b, dim);
                if (sl < 0) continue;
                G.comp[sl](p) = T[a][b] - n[a] * tn[b] - tn[a] * n[b] + ntn * n[a] * n[b];
            }
    });
    for (Field& c : G.comp)
        halos_.fill(c, body.patch());
}

} // namespace efsi
