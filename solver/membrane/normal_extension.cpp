#include "membrane/normal_extension.hpp"

#include "bodies/symmetric_tensor.hpp"
#include "core/error.hpp"
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
    // cubic stencil reads two cells beyond it (plus one for the cell-centre offset).
    const Decomposition& dec = halos.decomposition();
    wide_halo_ = int(std::ceil(reach_cells_)) + 3;
    for (int d = 0; d < dec.dim(); ++d) {
        const int thinnest = int(std::lround(dec.min(real(dec.block().cells[d]))));
        if (thinnest < wide_halo_)
            throw InputError(fmt::format(
                "body '{}': strain_extension = \"normal\" needs every rank's block to be at "
                "least {} cells wide, but one is {} cells wide along {} ({} ranks along it); "
                "run on fewer ranks or set body.strain_extension = \"layers\"",
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
            const real v = std::clamp(1 - 2 * phi(i, j, k), -1 + 1e-15, 1 - 1e-15);
            psi_(i, j, k) = eps * std::atanh(v);
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
    // Tricubic Catmull-Rom interpolation at x from cell centres (exact for quadratics;
    // trilinear, tried first, smooths a field that varies along the surface by O(h^2) at
    // every step, though at d/8 it moved D by only 1 %: docs/method.md).
    auto value = [&](const Field& f, const Real3& x) {
        Int3 base{0, 0, 0};
        std::array<std::array<real, 4>, 3> w{};
        for (int d = 0; d < 3; ++d) {
            if (d >= dim) {
                w[d] = {0, 1, 0, 0};
                continue;
            }
            const real u = (x[d] - g.origin[d]) / g.dx(d) - block.offset[d] - 0.5;
            base[d] = int(std::floor(u));
            const real t = u - base[d];
            const real t2 = t * t, t3 = t2 * t;
            w[d] = {0.5 * (-t3 + 2 * t2 - t), 0.5 * (3 * t3 - 5 * t2 + 2),
                    0.5 * (-3 * t3 + 4 * t2 + t), 0.5 * (t3 - t2)};
        }
        real r = 0;
        const int k0 = dim == 3 ? 0 : 1, k1 = dim == 3 ? 4 : 2;
        for (int c = k0; c < k1; ++c)
            for (int b = 0; b < 4; ++b)
                for (int a = 0; a < 4; ++a) {
                    const real wt = w[0][a] * w[1][b] * w[2][c];
                    if (wt == 0) continue;
                    r += wt * f(base[0] - 1 + a, base[1] - 1 + b, dim == 3 ? base[2] - 1 + c : 0);
                }
        return r;
    };
    for_each_in(phi.owned(), [&](int i, int j, int k) {
        const Int3 p{i, j, k};
        const real s = psi_(p);
        Real3 gp{0, 0, 0};
        real g2 = 0;
        for (int d = 0; d < dim; ++d) {
            gp[d] = (psi_(shifted(p, d, 1)) - psi_(shifted(p, d, -1))) / (2 * g.dx(d));
            g2 += gp[d] * gp[d];
        }
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
