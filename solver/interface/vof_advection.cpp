#include "interface/vof_advection.hpp"

#include "core/error.hpp"
#include "interface/thinc.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace efsi {

VofScheme parse_vof_scheme(const std::string& name) {
    if (name == "thinc") return VofScheme::Thinc1D;
    if (name == "mthinc") return VofScheme::Mthinc;
    throw InputError(fmt::format("vof scheme: unknown '{}' (expected thinc or mthinc)", name));
}

std::string to_string(VofScheme s) {
    return s == VofScheme::Thinc1D ? "thinc" : "mthinc";
}

namespace {

Int3 offset(Int3 p, int d, int by) {
    p[d] += by;
    return p;
}

/// Parker-Youngs gradient of phi at cell p in unit-cell coordinates: the central
/// difference along d, averaged over the neighbouring rows with weights (1, 2, 1) in each
/// transverse direction (the gradient at the 2^dim cell corners, averaged). Reads the
/// 3^dim block around p.
Real3 youngs_gradient(const Field& phi, const Int3& p, int dim) {
    Real3 g{0, 0, 0};
    int npts = 1;
    for (int e = 0; e < dim; ++e)
        npts *= 3;
    for (int q = 0; q < npts; ++q) {
        Int3 o{0, 0, 0};
        int code = q;
        for (int e = 0; e < dim; ++e, code /= 3)
            o[e] = code % 3 - 1;
        const real v = phi(p + o);
        for (int d = 0; d < dim; ++d) {
            if (o[d] == 0) continue;
            real w = 0.5 * o[d]; // central difference (phi_{+1} - phi_{-1}) / 2
            for (int e = 0; e < dim; ++e)
                if (e != d) w *= (o[e] == 0 ? 0.5 : 0.25);
            g[d] += w * v;
        }
    }
    return g;
}

/// Signed volume fraction G crossing the low d-face of cell p in +d during dt, as a
/// fraction of a cell; c = u_d dt / dx_d is the face Courant number. The region that
/// crosses is the slab of width |c| of the upwind cell next to the face.
real face_flux(const Field& phi, const VofOptions& opt, int dim, int d, const Int3& p, real c) {
    if (c == 0) return 0;
    const bool positive = c > 0;
    const Int3 up = positive ? offset(p, d, -1) : p;
    const real f = phi(up);
    const real a = std::abs(c);
    // A residue phi <= eps is not transported (zero flux): it stays where it is, so a
    // body's support cannot creep through round-off tails, and a body's patch can hold
    // every cell with phi > 0 (no volume is ever dropped when the patch moves).
    if (f <= opt.epsilon) return 0;
    if (f >= 1 - opt.epsilon) return c * f;
    if (opt.scheme == VofScheme::Thinc1D) {
        const real fm = phi(offset(up, d, -1)), fp = phi(offset(up, d, 1));
        // THINC only where phi is monotone across the cell (an interface); else upwind.
        if ((fp - f) * (f - fm) <= 0) return c * f;
        const Thinc1D h = thinc1d_reconstruct(f, fp > fm ? 1.0 : -1.0, opt.beta_thinc);
        const real v = positive ? thinc1d_integral(h, 1 - a, 1) : thinc1d_integral(h, 0, a);
        return positive ? v : -v;
    }
    const Real3 grad = youngs_gradient(phi, up, dim);
    real g2 = 0;
    for (int e = 0; e < dim; ++e)
        g2 += grad[e] * grad[e];
    if (g2 < 1e-24) return c * f; // no resolvable direction (isolated cell)
    const Mthinc r = mthinc_reconstruct(f, grad, opt.beta_mthinc, dim);
    Real3 lo{-0.5, -0.5, -0.5}, hi{0.5, 0.5, 0.5};
    if (positive)
        lo[d] = 0.5 - a;
    else
        hi[d] = -0.5 + a;
    const real v = mthinc_box_integral(r, lo, hi);
    return positive ? v : -v;
}

/// Distance in memory between neighbours along d (0, 1, 2) of a field's values.
std::ptrdiff_t stride(const Field& f, int d) {
    const Int3& e = f.extent();
    return d == 0 ? 1 : d == 1 ? std::ptrdiff_t(e[0]) : std::ptrdiff_t(e[0]) * e[1];
}

/// youngs_gradient on plain pointers, for a compile-time dim: the same points in the same
/// order (x offset fastest), so each component adds up the same terms in the same order;
/// the weights are powers of 2, so w * v is exact however w is formed. With the loops
/// unrolled the weights are constants and the sums stay in registers (a table of terms
/// accumulated into g[d] through memory took a fifth of the sweep's time).
template <int Dim>
Real3 youngs_gradient_at(const real* p, const std::ptrdiff_t (&s)[3]) {
    real g[3] = {0, 0, 0};
    constexpr int span2 = Dim > 2 ? 1 : 0, span1 = Dim > 1 ? 1 : 0;
    for (int o2 = -span2; o2 <= span2; ++o2)
        for (int o1 = -span1; o1 <= span1; ++o1)
            for (int o0 = -1; o0 <= 1; ++o0) {
                const int o[3] = {o0, o1, o2};
                const real v = p[o0 + o1 * s[1] + o2 * s[2]];
                for (int d = 0; d < Dim; ++d) {
                    if (o[d] == 0) continue;
                    real w = 0.5 * o[d];
                    for (int e = 0; e < Dim; ++e)
                        if (e != d) w *= (o[e] == 0 ? 0.5 : 0.25);
                    g[d] += w * v;
                }
            }
    return {g[0], g[1], g[2]};
}

} // namespace

VofAdvection::VofAdvection(const HaloFiller& halos, const VofOptions& options)
    : halos_(halos), opt_(options) {
    if (!(opt_.beta_thinc > 0) || !(opt_.beta_mthinc > 0))
        throw InputError("vof: beta must be positive");
    if (opt_.scheme == VofScheme::Mthinc && opt_.beta_mthinc > mthinc_beta_max)
        throw InputError(fmt::format("vof: MTHINC beta {} above {} (the reconstruction is a step "
                                     "already; a smoothed body's beta is 1/smoothing_width)",
                                     opt_.beta_mthinc, mthinc_beta_max));
    if (!(opt_.epsilon > 0 && opt_.epsilon < 0.5))
        throw InputError("vof: epsilon must be in (0, 1/2)");
}

void VofAdvection::sweep_rows(Field& phi, const VelocityField& u, real dt, int d,
                              const Patch* patch, VofStepStats& local) {
    const Decomposition& dec = halos_.decomposition();
    const int dim = dec.dim();
    const real r = dt / dec.grid().dx(d);
    const Box cells = phi.owned();
    const Field& ud = u[d];
    // flux_ and chi_ have phi's layout (same box and halos), so one index serves all three.
    const std::ptrdiff_t sp = stride(phi, d), su = stride(ud, d);
    const int n = cells.hi[d] - cells.lo[d];
    const bool closed_lo = patch && !patch->exchange[d][0];
    const bool closed_hi = patch && !patch->exchange[d][1];
    const real eps = opt_.epsilon;
    const std::ptrdiff_t strides[3] = {1, stride(phi, 1), stride(phi, 2)};
    real* const phi0 = phi.data().data();
    real* const flux0 = flux_.data().data();
    const real* const chi0 = chi_.data().data();
    const real* const u0 = ud.data().data();

    // Fluxes G on the faces 0..n of each row along d (face m is the low face of cell m;
    // face n the low face of the first cell past the box), as face_flux computes them.
    real max_courant = local.max_courant;
    Box rows = cells;
    rows.hi[d] = rows.lo[d] + 1;
    MthincFaces& mf = row_faces_;
    if (mf.face.size() < std::size_t(n + 1)) {
        mf.face.resize(n + 1);
        mf.phi.resize(n + 1);
        mf.courant.resize(n + 1);
        mf.integral.resize(n + 1);
        mf.grad.resize(n + 1);
    }
    for_each_in(rows, [&](int i, int j, int k) {
        const real* ph = phi0 + phi.index(i, j, k);
        const real* uf = u0 + ud.index(i, j, k);
        real* fl = flux0 + flux_.index(i, j, k);
        int nm = 0; // MTHINC faces of the row, gathered for one batched call
        for (int m = 0; m <= n; ++m) {
            const real c = uf[m * su] * r;
            max_courant = std::max(max_courant, std::abs(c));
            real G = 0;
            // No flux through the edge of a body's patch (see sweep), none for c = 0.
            const bool closed = (m == 0 && closed_lo) || (m == n && closed_hi);
            if (!closed && c != 0) {
                const bool positive = c > 0;
                const real* up = ph + std::ptrdiff_t(positive ? m - 1 : m) * sp;
                const real f = *up;
                if (f <= eps)
                    G = 0;
                else if (f >= 1 - eps)
                    G = c * f;
                else if (opt_.scheme == VofScheme::Thinc1D) {
                    const real fm = up[-sp], fp = up[sp];
                    if ((fp - f) * (f - fm) <= 0)
                        G = c * f;
                    else {
                        const real a = std::abs(c);
                        const Thinc1D h =
                            thinc1d_reconstruct(f, fp > fm ? 1.0 : -1.0, opt_.beta_thinc);
                        const real v =
                            positive ? thinc1d_integral(h, 1 - a, 1) : thinc1d_integral(h, 0, a);
                        G = positive ? v : -v;
                    }
                } else {
                    const Real3 grad = dim == 3   ? youngs_gradient_at<3>(up, strides)
                                       : dim == 2 ? youngs_gradient_at<2>(up, strides)
                                                  : youngs_gradient_at<1>(up, strides);
                    real g2 = 0;
                    for (int e = 0; e < dim; ++e)
                        g2 += grad[e] * grad[e];
                    if (g2 < 1e-24)
                        G = c * f;
                    else {
                        mf.face[nm] = m;
                        mf.phi[nm] = f;
                        mf.courant[nm] = c;
                        mf.grad[nm] = grad;
                        ++nm;
                    }
                }
            }
            fl[m * sp] = G;
        }
        mthinc_slab_integrals(nm, mf.phi.data(), mf.grad.data(), opt_.beta_mthinc, dim, d,
                              mf.courant.data(), mf.integral.data());
        for (int q = 0; q < nm; ++q) {
            const real v = mf.integral[q];
            fl[mf.face[q] * sp] = mf.courant[q] > 0 ? v : -v;
        }
    });
    local.max_courant = max_courant;

    // The update, in sweep's cell order (x fastest), so that the statistics add up alike.
    const Box& b = cells;
    real lo_v = local.min_before_clip, hi_v = local.max_before_clip;
    real clipped_sum = local.clipped_volume;
    const bool clip = opt_.clip;
    for (int k = b.lo[2]; k < b.hi[2]; ++k)
        for (int j = b.lo[1]; j < b.hi[1]; ++j) {
            real* ph = phi0 + phi.index(b.lo[0], j, k);
            const real* fl = flux0 + flux_.index(b.lo[0], j, k);
            const real* ch = chi0 + chi_.index(b.lo[0], j, k);
            const real* uf = u0 + ud.index(b.lo[0], j, k);
            const int nx = b.hi[0] - b.lo[0];
            for (int i = 0; i < nx; ++i) {
                const real dc = (uf[i + su] - uf[i]) * r;
                real v = ph[i] - (fl[i + sp] - fl[i]) + ch[i] * dc;
                lo_v = std::min(lo_v, v);
                hi_v = std::max(hi_v, v);
                if (clip) {
                    const real clipped = std::clamp(v, 0.0, 1.0);
                    clipped_sum += std::abs(clipped - v);
                    v = clipped;
                }
                ph[i] = v;
            }
        }
    local.min_before_clip = lo_v;
    local.max_before_clip = hi_v;
    local.clipped_volume = clipped_sum;
}

void VofAdvection::sweep(Field& phi, const VelocityField& u, real dt, int d, const Patch* patch,
                         VofStepStats& local) {
    const Decomposition& dec = halos_.decomposition();
    const GlobalGrid& g = dec.grid();
    const int dim = dec.dim();
    const real r = dt / g.dx(d);
    const Box cells = phi.owned();
    // Faces lo..hi along d (face hi is the low face of the first cell past the box).
    Box faces = cells;
    faces.hi[d] += 1;
    for_each_in(faces, [&](int i, int j, int k) {
        const Int3 p{i, j, k};
        const real c = u[d](p) * r;
        local.max_courant = std::max(local.max_courant, std::abs(c));
        // No flux through the edge of a body's patch (only through faces shared with a
        // neighbour rank's part of it), so the body's volume is conserved exactly.
        const bool closed = patch && ((p[d] == cells.lo[d] && !patch->exchange[d][0]) ||
                                      (p[d] == cells.hi[d] && !patch->exchange[d][1]));
        flux_(p) = closed ? 0.0 : face_flux(phi, opt_, dim, d, p, c);
    });
    for_each_in(cells, [&](int i, int j, int k) {
        const Int3 p{i, j, k}, q = offset(p, d, 1);
        const real dc = (u[d](q) - u[d](p)) * r;
        real v = phi(p) - (flux_(q) - flux_(p)) + chi_(p) * dc;
        local.min_before_clip = std::min(local.min_before_clip, v);
        local.max_before_clip = std::max(local.max_before_clip, v);
        if (opt_.clip) {
            const real clipped = std::clamp(v, 0.0, 1.0);
            local.clipped_volume += std::abs(clipped - v);
            v = clipped;
        }
        phi(p) = v;
    });
}

VofStepStats VofAdvection::advance(Field& phi, const VelocityField& u, real dt, std::int64_t step,
                                   const Patch* patch) {
    return reduce(halos_.decomposition(), advance_local(phi, u, dt, step, patch));
}

VofStepStats VofAdvection::advance_local(Field& phi, const VelocityField& u, real dt,
                                         std::int64_t step, const Patch* patch) {
    VofStepStats local = start(phi, patch);
    for (int s = 0; s < halos_.decomposition().dim(); ++s) {
        sweep_step(phi, u, dt, step, s, patch, local);
        if (patch)
            halos_.fill(phi, *patch);
        else
            halos_.fill(phi);
    }
    return local;
}

VofStepStats VofAdvection::start(Field& phi, const Patch* patch) {
    const int dim = halos_.decomposition().dim();
    // Work arrays follow phi's box (the whole block, or a body's moving patch).
    if (chi_.begin() != phi.begin() || chi_.cells() != phi.cells() || chi_.data().empty()) {
        chi_ = Field::on_patch("vof_chi", Location::Cell, phi.begin(), phi.cells(), dim);
        flux_ = Field::on_patch("vof_flux", Location::Cell, phi.begin(), phi.cells(), dim);
    }
    VofStepStats local;
    local.min_before_clip = 0;
    local.max_before_clip = 1;
    if (!(patch && patch->empty()))
        for_each_in(phi.owned(),
                    [&](int i, int j, int k) { chi_(i, j, k) = phi(i, j, k) >= 0.5 ? 1.0 : 0.0; });
    return local;
}

void VofAdvection::sweep_step(Field& phi, const VelocityField& u, real dt, std::int64_t step, int s,
                              const Patch* patch, VofStepStats& local) {
    if (patch && patch->empty()) return;
    const int dim = halos_.decomposition().dim();
    const int d = (step % 2 == 0) ? s : dim - 1 - s;
    if (opt_.pointwise)
        sweep(phi, u, dt, d, patch, local);
    else
        sweep_rows(phi, u, dt, d, patch, local);
}

VofStepStats VofAdvection::reduce(const Decomposition& dec, const VofStepStats& local) {
    VofStepStats st;
    st.min_before_clip = dec.min(local.min_before_clip);
    st.max_before_clip = dec.max(local.max_before_clip);
    st.clipped_volume = dec.sum(local.clipped_volume) * dec.grid().cell_volume();
    st.max_courant = dec.max(local.max_courant);
    if (st.max_courant >= 0.5)
        throw RunError(
            fmt::format("vof: Courant number {:.3f} >= 1/2 (reduce dt)", st.max_courant));
    return st;
}

real total_volume(const Decomposition& dec, const Field& phi) {
    real v = 0;
    for_each_in(phi.owned(), [&](int i, int j, int k) { v += phi(i, j, k); });
    return dec.sum(v) * dec.grid().cell_volume();
}

} // namespace efsi
