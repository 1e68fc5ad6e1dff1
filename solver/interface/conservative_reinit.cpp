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
    if (work_.data().empty() || work_.begin() != phi.begin() || work_.cells() != phi.cells() ||
        work_.extent() != phi.extent()) {
        // phi's own layout (its 2 halo layers), so that one linear index serves all.
        const int halo = phi.halo()[0];
        auto make = [&](const char* name) {
            return Field::on_patch(name, Location::Cell, phi.begin(), phi.cells(), dim, halo);
        };
        work_ = make("phi_reinit");
        psi_a_ = make("psi_a");
        expo_ = make("exp_psi_a");
        for (int t = 0; t < dim; ++t) {
            grad_[t] = make("grad_psi_a");
            change_[t] = make("face_change");
        }
        gain_limit_ = make("gain_limit");
        loss_limit_ = make("loss_limit");
    }
    const real h = g.dx(0);
    const real e = 0.5 * eps_cells_ * h;
    const real dtau = h * h / (4 * dim * e);
    const real dv = g.cell_volume();
    constexpr real empty_cut = 1e-8; // the VOF's empty / full threshold
    // All five fields share phi's layout (same begin, cells and 2 halo layers), so one
    // linear index serves them all; the loops below run unit-stride along i.
    const Int3 ext = phi.extent();
    const std::ptrdiff_t stride[3] = {1, std::ptrdiff_t(ext[0]),
                                      std::ptrdiff_t(ext[0]) * std::ptrdiff_t(ext[1])};
    const Box own = phi.owned();
    real* const ph = phi.data().data();
    real* const wk = work_.data().data();
    real* const pa = psi_a_.data().data();
    real* const ex = expo_.data().data();
    // Calls f(index of the row's first point, row length, j, k) for each row of b along i.
    auto for_rows = [&](const Box& b, auto&& f) {
        for (int k = b.lo[2]; k < b.hi[2]; ++k)
            for (int j = b.lo[1]; j < b.hi[1]; ++j)
                f(std::ptrdiff_t(phi.index(b.lo[0], j, k)), b.hi[0] - b.lo[0], j, k);
    };
    constexpr real arg_cut = 1 - 1e-15; // profile_distance's clamp of 1 - 2 phi
    const std::size_t n_stored = phi.data().size();
    // psi_a on owned cells and both halo layers; its fourth-order central gradient, each
    // component t on the owned box widened by 2 in every direction but t (where the faces'
    // interpolations reach), needs no more.
    auto widened = [&](int keep) {
        Box b = own;
        for (int d = 0; d < dim; ++d)
            if (d != keep) {
                b.lo[d] -= 2;
                b.hi[d] += 2;
            }
        return b;
    };
    const real den_grad = 12 * h, den_face = 24 * h;
    for (int it = 0; it < iterations_; ++it) {
        halos_.fill(phi, body.patch());
        // The stored box of phi is its whole array (owned cells and both halo layers).
        // With x = 1 - 2 phi clamped as in profile_distance and q = (1 - x) / (1 + x) (=
        // phi / (1 - phi)), psi_a = -eps atanh(x) = e ln q and exp(psi_a / 2e) = sqrt(q):
        // one log and one sqrt per cell serve both.
        for (std::size_t n = 0; n < n_stored; ++n) {
            const real x = std::clamp(1 - 2 * ph[n], -arg_cut, arg_cut);
            const real q = (1 - x) / (1 + x);
            pa[n] = e * std::log(q);
            ex[n] = std::sqrt(q);
        }
        for (int t = 0; t < dim; ++t) {
            real* const gt = grad_[t].data().data();
            const std::ptrdiff_t s = stride[t];
            for_rows(widened(t), [&](std::ptrdiff_t r, int ni, int, int) {
                for (int i = 0; i < ni; ++i) {
                    const std::ptrdiff_t n = r + i;
                    const real d1 = pa[n + s] - pa[n - s];
                    const real d2 = pa[n + 2 * s] - pa[n - 2 * s];
                    gt[n] = (8 * d1 - d2) / den_grad;
                }
            });
        }
        for_rows(own, [&](std::ptrdiff_t r, int ni, int, int) {
            std::copy(ph + r, ph + r + ni, wk + r);
        });
        for (int d = 0; d < dim; ++d) {
            // Faces p + 1/2 e_d of the owned cells and the one below the first.
            Box faces = own;
            --faces.lo[d];
            const std::ptrdiff_t s = stride[d];
            // The (up to two) tangential gradient components, in increasing t.
            const real* tg[2] = {nullptr, nullptr};
            int nt = 0;
            for (int t = 0; t < dim; ++t)
                if (t != d) tg[nt++] = grad_[t].data().data();
            real* const ch = change_[d].data().data();
            for_rows(faces, [&](std::ptrdiff_t r, int ni, int, int) {
                for (int i = 0; i < ni; ++i) {
                    const std::ptrdiff_t p = r + i, q = p + s;
                    const real f0 = ph[p], f1 = ph[q];
                    real flux = 0;
                    // No flux between two empty or two full cells: nothing leaves the patch.
                    if (!((f0 <= empty_cut && f1 <= empty_cut) ||
                          (f0 >= 1 - empty_cut && f1 >= 1 - empty_cut))) {
                        const real lo = pa[p], hi = pa[q];
                        // Fourth-order face derivative and tangential gradient, so that the
                        // flux vanishes where |grad psi_a| = 1 to the curvature's O(h^4).
                        const real gd = (27 * (hi - lo) - (pa[q + s] - pa[p - s])) / den_face;
                        real g2 = gd * gd;
                        for (int m = 0; m < nt; ++m) {
                            const real* gt = tg[m];
                            const real gf = (9 * (gt[p] + gt[q]) - (gt[p - s] + gt[q + s])) / 16;
                            g2 += gf * gf;
                        }
                        // (1/4)(1 - tanh^2(psi_f / 2e)) = w / (1 + w)^2, psi_f = (lo + hi) / 2,
                        // with w = exp(psi_f / e) the product of the two cells' exp(psi_a /
                        // 2e): no tanh per face.
                        const real w = ex[p] * ex[q];
                        if (g2 > 0) flux = w / ((1 + w) * (1 + w)) * gd * (1 - 1 / std::sqrt(g2));
                    }
                    // The flux along +d leaves p and enters q: p's value changes by
                    // +change, q's by -change.
                    ch[p] = dtau * flux / h;
                }
            });
        }
        // Limit the face changes where an owned cell would leave [0, 1] (Zalesak's
        // limiter with the bounds 0 and 1): a cell's gains are scaled by min(1, room /
        // gains), its losses by min(1, content / losses), and a face takes the smaller
        // factor of its receiving and its giving cell; both ranks of a face see the same
        // factors (exchanged), so the changes still telescope. Where nothing would leave
        // [0, 1] every factor is exactly 1 and nothing changes.
        std::fill(gain_limit_.data().begin(), gain_limit_.data().end(), 1.0);
        std::fill(loss_limit_.data().begin(), loss_limit_.data().end(), 1.0);
        real* const gl = gain_limit_.data().data();
        real* const ll = loss_limit_.data().data();
        for_rows(own, [&](std::ptrdiff_t r, int ni, int, int) {
            for (int i = 0; i < ni; ++i) {
                const std::ptrdiff_t n = r + i;
                real gains = 0, losses = 0;
                for (int d = 0; d < dim; ++d) {
                    const real* ch = change_[d].data().data();
                    const real up = ch[n], down = -ch[n - stride[d]];
                    gains += std::max(up, 0.0) + std::max(down, 0.0);
                    losses += std::max(-up, 0.0) + std::max(-down, 0.0);
                }
                if (gains > 1 - ph[n]) gl[n] = std::max(1 - ph[n], 0.0) / gains;
                if (losses > ph[n]) ll[n] = std::max(ph[n], 0.0) / losses;
            }
        });
        halos_.fill(gain_limit_, body.patch());
        halos_.fill(loss_limit_, body.patch());
        for (int d = 0; d < dim; ++d) {
            Box faces = own;
            --faces.lo[d];
            const std::ptrdiff_t s = stride[d];
            const real* ch = change_[d].data().data();
            for_rows(faces, [&](std::ptrdiff_t r, int ni, int j, int k) {
                const int jk[3] = {0, j, k};
                int i_p_first = 0, i_q_last = ni;
                bool p_owned = true, q_owned = true;
                if (d == 0) {
                    i_p_first = 1;
                    i_q_last = ni - 1;
                } else {
                    p_owned = jk[d] >= own.lo[d];
                    q_owned = jk[d] + 1 < own.hi[d];
                }
                for (int i = 0; i < ni; ++i) {
                    const std::ptrdiff_t p = r + i, q = p + s;
                    real change = ch[p];
                    change *= change > 0 ? std::min(gl[p], ll[q]) : std::min(ll[p], gl[q]);
                    if (p_owned && i >= i_p_first) wk[p] += change;
                    if (q_owned && i < i_q_last) wk[q] -= change;
                }
            });
        }
        for_rows(own, [&](std::ptrdiff_t r, int ni, int, int) {
            for (int i = 0; i < ni; ++i) {
                const real v = wk[r + i];
                const real c = std::clamp(v, 0.0, 1.0);
                stats.clipped_volume += std::abs(c - v) * dv;
                ph[r + i] = c;
            }
        });
    }
    halos_.fill(phi, body.patch());
    return stats;
}

} // namespace efsi
