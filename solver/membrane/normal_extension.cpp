#include "membrane/normal_extension.hpp"

#include "bodies/symmetric_tensor.hpp"
#include "core/error.hpp"
#include "core/matrix3.hpp"
#include "interface/geometry.hpp"
#include "membrane/kinematics.hpp"
#include "membrane/reference_map.hpp"
#include "operators/flow_operators.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <type_traits>

namespace efsi {

namespace {

/// Visit the cells of `box` row by row: those with |psi| > `limit` through `beyond` (nothing
/// when null), the others through `near` (i, j, k). psi is read through a row pointer, so the
/// many cells of a patch far from its surface cost one comparison each.
template <class Beyond, class Near>
void for_each_beyond_or_not(const Field& psi, const Box& box, real limit, Beyond&& beyond,
                            Near&& near) {
    const int nx = box.hi[0] - box.lo[0];
    for (int k = box.lo[2]; k < box.hi[2]; ++k)
        for (int j = box.lo[1]; j < box.hi[1]; ++j) {
            const real* s = psi.data().data() + psi.index(box.lo[0], j, k);
            for (int i = 0; i < nx; ++i) {
                if (std::abs(s[i]) > limit) {
                    if constexpr (!std::is_same_v<std::decay_t<Beyond>, std::nullptr_t>)
                        beyond(Int3{box.lo[0] + i, j, k});
                    continue;
                }
                near(box.lo[0] + i, j, k);
            }
        }
}

/// J = sqrt(II(Gs)), the area ratio of a tangential Gs (2D: its z row is the unit stretch).
real area_ratio(const SymmetricTensorField& G, const Int3& p) {
    Matrix3 m{};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            m[a][b] = G.value(a, b, p);
    return std::sqrt(std::max(second_invariant(m), real(0)));
}

/// Fourth-order central differences (the field needs two halo layers).
Real3 central_gradient4(const Field& f, const GlobalGrid& g, const Int3& p, int dim) {
    Real3 r{0, 0, 0};
    for (int d = 0; d < dim; ++d) {
        const real fm2 = f(shifted(p, d, -2)), fm1 = f(shifted(p, d, -1));
        const real fp1 = f(shifted(p, d, 1)), fp2 = f(shifted(p, d, 2));
        r[d] = (fm2 - 8 * fm1 + 8 * fp1 - fp2) / (12 * g.dx(d));
    }
    return r;
}
} // namespace

real NormalExtension::default_reach(real eps_cells) {
    return std::atanh(1 - 2 * 1e-5) * eps_cells + 2;
}

NormalExtension::NormalExtension(const HaloFiller& halos, const std::string& body_name,
                                 real eps_cells, real core_cells, real reach_cells, bool cubic_map,
                                 bool area_filter, bool newton_foot)
    : halos_(halos), eps_cells_(eps_cells), core_cells_(core_cells),
      reach_cells_(reach_cells > 0 ? reach_cells : default_reach(eps_cells)), cubic_map_(cubic_map),
      area_filter_(area_filter), newton_foot_(newton_foot) {
    // The foot point is |y - x| = |psi| <= reach cells away (n is a unit vector); with u the
    // position in cell units (integer at a cell centre) the stencils read floor(u) .. floor(u)
    // + 1 (trilinear) or floor(u) - 1 .. floor(u) + 2 (cubic), so at most ceil(reach) + 1
    // cells from the owned cell. One more layer is kept as a margin for round-off in u.
    const Decomposition& dec = halos.decomposition();
    wide_halo_ = int(std::ceil(reach_cells_)) + 2;
    for (int d = 0; d < dec.dim(); ++d) {
        const int thinnest = int(std::lround(dec.min(real(dec.block().cells[d]))));
        if (thinnest < wide_halo_)
            throw InputError(fmt::format(
                "body '{}': strain_extension = \"normal\" needs every rank's block to be at "
                "least {} cells wide, but one is {} cells wide along {} ({} ranks along it); "
                "run on fewer ranks, lay them out along wider directions (parallel.ranks) or set "
                "body.strain_model = \"tensor\" and body.strain_extension = \"layers\"",
                body_name, wide_halo_, thinnest, "xyz"[d], dec.ranks_per_dim()[d]));
    }
}

BodyWork NormalExtension::prepare(Body& body, const std::vector<const Field*>& fields,
                                  bool psi_current) {
    const Decomposition& dec = halos_.decomposition();
    const int dim = dec.grid().dim;
    const int ncomp = int(fields.size());
    Field& phi = body.phi();
    const real eps = eps_cells_ * dec.grid().dx(0);
    // The buffers follow the patch; the number of sources changes between the calls of
    // one step (the map's 3, then Gs's 6 with the weights), so they are kept for the
    // largest count and reused, not allocated again at every call.
    const bool moved =
        psi_.data().empty() || psi_.begin() != phi.begin() || psi_.cells() != phi.cells();
    if (moved && psi_current)
        throw std::logic_error("NormalExtension: psi marked current on a moved patch");
    if (moved) {
        psi_ = Field::on_patch("psi", Location::Cell, phi.begin(), phi.cells(), dim, 1);
        psi_wide_ =
            Field::on_patch("psi_wide", Location::Cell, phi.begin(), phi.cells(), dim, wide_halo_);
        src_.clear();
    }
    while (int(src_.size()) < ncomp)
        src_.push_back(Field::on_patch("extension_source", Location::Cell, phi.begin(), phi.cells(),
                                       dim, wide_halo_));
    // Row by row: psi, then a copy of each field's owned values.
    const Box own = phi.owned();
    const int nx = own.hi[0] - own.lo[0];
    for (int k = own.lo[2]; k < own.hi[2]; ++k)
        for (int j = own.lo[1]; j < own.hi[1]; ++j) {
            if (!psi_current) {
                const real* f = phi.data().data() + phi.index(own.lo[0], j, k);
                real* p = &psi_(own.lo[0], j, k);
                for (int i = 0; i < nx; ++i)
                    p[i] = profile_distance(f[i], eps);
                std::copy(p, p + nx, &psi_wide_(own.lo[0], j, k));
            }
            for (int s = 0; s < ncomp; ++s) {
                const real* from = fields[s]->data().data() + fields[s]->index(own.lo[0], j, k);
                std::copy(from, from + nx, &src_[s](own.lo[0], j, k));
            }
        }
    // Collective: every rank with a part of the patch takes part (the patch's exchange
    // flags pair the ranks).
    std::vector<Field*> wide;
    if (!psi_current) {
        wide.push_back(&psi_);
        wide.push_back(&psi_wide_);
    }
    for (int s = 0; s < ncomp; ++s)
        wide.push_back(&src_[s]);
    const Patch& patch = body.patch();
    for (int d = 0; d < 3; ++d) {
        const bool along = d < dim;
        const int lo_layers = !along ? 0 : patch.exchange[d][0] ? wide_halo_ : kEdgeLayers;
        const int hi_layers = !along ? 0 : patch.exchange[d][1] ? wide_halo_ : kEdgeLayers;
        filled_lo_[d] = phi.begin()[d] - std::min(lo_layers, wide_halo_);
        filled_hi_[d] = phi.begin()[d] + phi.cells()[d] - 1 + std::min(hi_layers, wide_halo_);
    }
    co_await halo_fill(std::move(wide), patch, kEdgeLayers);
}

real NormalExtension::cell_coordinate(real x, int d) const {
    const Decomposition& dec = halos_.decomposition();
    const GlobalGrid& g = dec.grid();
    return (x - g.origin[d]) / g.dx(d) - dec.block().offset[d] - 0.5;
}

// Trilinear interpolation at x from cell centres: a convex combination, so the extension
// makes no new extrema. (Tricubic Catmull-Rom, exact for quadratics, was tried: it moved
// D(1) of the d/8 Ca 0.05 capsule by 1 % only, and the d/8 Ca 0.2 run that completes
// t = 10 with trilinear stopped UNSTABLE at t = 1.9 with it; docs/method.md.)
NormalExtension::Trilinear NormalExtension::trilinear_at(const Real3& x) const {
    const Decomposition& dec = halos_.decomposition();
    const GlobalGrid& g = dec.grid();
    const int dim = g.dim;
    Int3 base{0, 0, 0};
    std::array<real, 3> t{0, 0, 0};
    for (int d = 0; d < dim; ++d) {
        const real u = cell_coordinate(x[d], d);
        base[d] = int(std::floor(u));
        t[d] = u - base[d];
    }
    Trilinear r;
    r.corner = psi_wide_.index(base[0], base[1], base[2]);
    const int kz = dim == 3 ? 2 : 1;
    for (int c = 0; c < kz; ++c)
        for (int b = 0; b < 2; ++b)
            for (int a = 0; a < 2; ++a)
                r.weight[4 * c + 2 * b + a] = (a ? t[0] : 1 - t[0]) * (b ? t[1] : 1 - t[1]) *
                                              (dim == 3 ? (c ? t[2] : 1 - t[2]) : 1.0);
    return r;
}

real NormalExtension::interpolate(const Field& f, const Trilinear& at) const {
    const int kz = halos_.decomposition().grid().dim == 3 ? 2 : 1;
    const std::ptrdiff_t s1 = f.extent()[0], s2 = std::ptrdiff_t(f.extent()[0]) * f.extent()[1];
    const real* const p = f.data().data() + at.corner;
    real r = 0;
    for (int c = 0; c < kz; ++c)
        for (int b = 0; b < 2; ++b)
            for (int a = 0; a < 2; ++a)
                r += at.weight[4 * c + 2 * b + a] * p[a + b * s1 + c * s2];
    return r;
}

// Tensor-product 4-point Lagrange interpolation at x (exact for cubics; error O(h^4) on a
// smooth field). For the reference map only: X is smooth across the band (constant along
// the normals), so the overshoot that ruled it out for Gs does not arise.
real NormalExtension::interpolate_cubic(const Field& f, const Real3& x) const {
    const Decomposition& dec = halos_.decomposition();
    const GlobalGrid& g = dec.grid();
    const int dim = g.dim;
    Int3 base{0, 0, 0};
    std::array<std::array<real, 4>, 3> w{};
    for (int d = 0; d < 3; ++d)
        w[d] = {0, 1, 0, 0};
    for (int d = 0; d < dim; ++d) {
        const real u = cell_coordinate(x[d], d);
        base[d] = int(std::floor(u));
        const real t = u - base[d];
        w[d] = {-t * (t - 1) * (t - 2) / 6, (t + 1) * (t - 1) * (t - 2) / 2,
                -(t + 1) * t * (t - 2) / 2, (t + 1) * t * (t - 1) / 6};
    }
    // One direction at a time: each row's sum along x, then the rows' along y, then z.
    const std::ptrdiff_t sy = f.extent()[0];
    real r = 0;
    const int c0 = dim == 3 ? -1 : 0, c1 = dim == 3 ? 2 : 0;
    for (int c = c0; c <= c1; ++c) {
        const real* plane = f.data().data() + f.index(base[0] - 1, base[1] - 1, base[2] + c);
        real along_y = 0;
        for (int b = 0; b < 4; ++b) {
            const real* row = plane + b * sy;
            along_y += w[1][b] *
                       (w[0][0] * row[0] + w[0][1] * row[1] + w[0][2] * row[2] + w[0][3] * row[3]);
        }
        r += (dim == 3 ? w[2][c + 1] : 1.0) * along_y;
    }
    return r;
}

Real3 NormalExtension::foot_point(const Real3& x, real s, const Real3& n, real gradient, int half,
                                  real& to_foot) const {
    const Decomposition& dec = halos_.decomposition();
    const GlobalGrid& g = dec.grid();
    const int dim = g.dim;
    // Whether the stencil of the point x - d n (its base floor(u) as the interpolation forms
    // it) lies in the filled cells along each axis.
    auto fits = [&](real d) {
        for (int e = 0; e < dim; ++e) {
            const int base = int(std::floor(cell_coordinate(x[e] - d * n[e], e)));
            if (base - (half - 1) < filled_lo_[e] || base + half > filled_hi_[e]) return false;
        }
        return true;
    };
    to_foot = foot_distance(s, gradient);
    bool inside = fits(to_foot);
    if (!inside && newton_foot_) {
        to_foot = s;
        inside = fits(s);
    }
    Real3 y = x;
    for (int e = 0; e < dim; ++e)
        y[e] -= to_foot * n[e];
    if (inside) return y;
    for (int e = 0; e < dim; ++e) {
        const real u = cell_coordinate(y[e], e);
        const int base = int(std::floor(u));
        real clamped = u;
        if (base - (half - 1) < filled_lo_[e]) clamped = filled_lo_[e] + (half - 1);
        if (base + half > filled_hi_[e]) clamped = filled_hi_[e] - half;
        y[e] = g.origin[e] + (clamped + dec.block().offset[e] + 0.5) * g.dx(e);
    }
    return y;
}

bool NormalExtension::foot_on_surface(const Trilinear& at) const {
    return std::abs(interpolate(psi_wide_, at)) <=
           kFootTolerance * halos_.decomposition().grid().dx(0);
}

bool NormalExtension::normal_at(const Int3& p, real& s, Real3& n, real& gradient) const {
    const GlobalGrid& g = halos_.decomposition().grid();
    s = psi_(p);
    n = Real3{0, 0, 0};
    if (std::abs(s) > reach_cells_ * g.dx(0)) return false; // before the gradient: most cells
    const Real3 gp = central_gradient(psi_, g, p);
    real g2 = 0;
    for (int d = 0; d < g.dim; ++d)
        g2 += gp[d] * gp[d];
    if (g2 < 0.25) return false;
    for (int d = 0; d < g.dim; ++d)
        n[d] = gp[d] / std::sqrt(g2);
    gradient = std::sqrt(g2);
    return true;
}

BodyWork NormalExtension::apply(Body& body) {
    co_await apply_tensor(body, core_cells_);
}

BodyWork NormalExtension::apply_tensor(Body& body, real core_cells, const Field* weight,
                                       const Field* area, bool psi_current) {
    SymmetricTensorField& G = body.tensor();
    if (G.comp.empty() || body.patch().empty()) co_return;
    std::vector<const Field*> fields;
    for (const Field& c : G.comp)
        fields.push_back(&c);
    if (weight) fields.push_back(weight);
    if (weight && area) fields.push_back(area);
    co_await prepare(body, fields, psi_current);
    const Decomposition& dec = halos_.decomposition();
    const GlobalGrid& g = dec.grid();
    const LocalBlock& block = dec.block();
    const int dim = g.dim;
    const int ncomp = int(G.comp.size());
    const real core = core_cells * g.dx(0);
    auto cell = [&](int i, int j, int k) {
        const Int3 p{i, j, k};
        real s = 0, gradient = 1;
        Real3 n;
        std::array<std::array<real, 3>, 3> T{};
        real target_j = 0; // > 0: the copy's area ratio J is set to this
        if (!normal_at(p, s, n, gradient)) {
            for (int s2 = 0; s2 < ncomp; ++s2)
                G.comp[s2](p) = 0;
            for (int a = 0; a < dim; ++a)
                G.comp[SymmetricTensorField::slot(a, a, dim)](p) = 1;
            return;
        }
        if (std::abs(s) <= core) {
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    T[a][b] = G.value(a, b, p);
        } else {
            real to_foot = 0;
            const Real3 y =
                foot_point(position(g, block, Location::Cell, i, j, k), s, n, gradient, 1, to_foot);
            // One set of weights serves every component (src_ fields share one layout).
            const Trilinear at = trilinear_at(y);
            if (weight && !foot_on_surface(at)) {
                // No surface where the normal leads (a thin body's middle): no membrane
                // strain here. Gs = 0 (J = 0) is what the force leaves out of its band
                // (MembraneForceSettings::min_area_ratio) and the diagnostics skip.
                for (int s2 = 0; s2 < ncomp; ++s2)
                    G.comp[s2](p) = 0;
                return;
            }
            std::array<real, 6> v{};
            for (int s2 = 0; s2 < ncomp; ++s2)
                v[s2] = interpolate(src_[s2], at);
            if (weight) {
                // The components hold w Gs: the mean over the valid cells of the stencil
                // (I where none is).
                const real w = interpolate(src_[ncomp], at);
                for (int s2 = 0; s2 < ncomp; ++s2)
                    v[s2] = w > 1e-3 ? v[s2] / w : (s2 < dim ? 1.0 : 0.0);
                if (area && w > 1e-3) target_j = interpolate(src_[ncomp + 1], at) / w;
            }
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) {
                    const int sl = SymmetricTensorField::slot(a, b, dim);
                    T[a][b] = sl >= 0 ? v[sl] : (a == 2 && b == 2 ? G.zz_2d : 0.0);
                }
            // The reference map's copy is turned into this cell's tangent plane before it is
            // projected onto it, so a normal that differs from the foot point's (far out in
            // the band, where psi's gradient is least accurate) costs no area.
            if (weight) T = turned_into_plane(T, n, dim);
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
        // area_filter: the copy's area ratio set to the low-passed J at the foot point (3D:
        // Gs scales J linearly; 2D: J^2 = Gs_xx + Gs_yy, one tangent and the unit z stretch).
        if (target_j > 0) {
            const real own = area_ratio(G, p);
            if (own > 0) {
                const real r = target_j / own;
                const real scale = dim == 3 ? r : r * r;
                for (Field& c : G.comp)
                    c(p) *= scale;
            }
        }
    };
    // Row by row: most cells of a patch lie beyond the reach, where normal_at finds no
    // normal and the copy is the identity; they are written through row pointers, the
    // others by `cell`.
    const Box own = body.phi().owned();
    const int nx = own.hi[0] - own.lo[0];
    const real far = reach_cells_ * g.dx(0); // normal_at's test
    std::array<real*, 6> row{};
    std::array<real, 6> identity{};
    for (int a = 0; a < dim; ++a)
        identity[SymmetricTensorField::slot(a, a, dim)] = 1;
    for (int k = own.lo[2]; k < own.hi[2]; ++k)
        for (int j = own.lo[1]; j < own.hi[1]; ++j) {
            const real* s = &psi_(own.lo[0], j, k);
            for (int s2 = 0; s2 < ncomp; ++s2)
                row[s2] = &G.comp[s2](own.lo[0], j, k);
            for (int i = 0; i < nx; ++i) {
                if (std::abs(s[i]) > far) {
                    for (int s2 = 0; s2 < ncomp; ++s2)
                        row[s2][i] = identity[s2];
                    continue;
                }
                cell(own.lo[0] + i, j, k);
            }
        }
    co_await halo_fill(G.comp, body.patch());
}

void NormalExtension::apply_reference_map(Body& body, bool whole_band, const Shape* reference) {
    std::vector<Field>& X = body.reference_map();
    SymmetricTensorField& G = body.tensor();
    if (X.empty() || G.comp.empty()) return;
    std::vector<const Field*> fields;
    for (const Field& c : X)
        fields.push_back(&c);
    if (body.patch().empty()) return;
    run_now(prepare(body, fields), halos_);
    const Decomposition& dec = halos_.decomposition();
    const GlobalGrid& g = dec.grid();
    const LocalBlock& block = dec.block();
    const int dim = g.dim;
    // The map's core (|s| <= strain_core cells) keeps its transported values.
    if ((valid_.data().empty() || valid_.begin() != X[0].begin() || valid_.cells() != X[0].cells()))
        valid_ = Field::on_patch("valid", Location::Cell, X[0].begin(), X[0].cells(), dim, 1);
    const real core = core_cells_ * g.dx(0);
    const Real3 period{g.length[0], g.length[1], g.length[2]};
    const real z2d = position(g, block, Location::Cell, 0, 0, 0)[2];
    // 1. The map beyond the core: X(x) = X(y), y = x - s n, i.e. (X - x)(x) = (X - x)(y) - s n.
    //    Beyond the band it keeps its transported value (never read by the force).
    //    With a reference shape every band cell's X then goes onto its surface.
    const real far = reach_cells_ * g.dx(0); // normal_at's first test
    for_each_beyond_or_not(psi_, body.phi().owned(), far, nullptr, [&](int i, int j, int k) {
        const Int3 p{i, j, k};
        real s = 0, gradient = 1;
        Real3 n;
        if (!normal_at(p, s, n, gradient)) return;
        const Real3 x = position(g, block, Location::Cell, i, j, k);
        if (whole_band || std::abs(s) > core) {
            real to_foot = 0;
            const Real3 y = foot_point(x, s, n, gradient, cubic_map_ ? 2 : 1, to_foot);
            // A foot point off the surface (a thin body's middle, where psi's gradient turns)
            // has no map to copy: the cell keeps its transported X.
            if (foot_on_surface(trilinear_at(y)))
                for (int d = 0; d < dim; ++d)
                    X[d](p) = (cubic_map_ ? interpolate_cubic(src_[d], y)
                                          : interpolate(src_[d], trilinear_at(y))) -
                              to_foot * n[d];
        }
        if (!reference) return;
        Real3 Xp = x;
        for (int d = 0; d < dim; ++d)
            Xp[d] += X[d](p);
        const Real3 on = onto_reference_surface(*reference, Xp, dim, dec.periodic(), period, z2d);
        for (int d = 0; d < dim; ++d)
            X[d](p) = on[d] - x[d];
    });
    for (Field& c : X)
        halos_.fill(c, body.patch());
    // 2. Gs from grad X = I + grad (X - x) (fourth-order central differences: with second-order
    //    ones the rest state's area ratio came out 0.4 % high at R = 8 cells, a prestress of
    //    0.4 % of the area modulus, 22 % of Es in a Skalak membrane with C = 100) in the band,
    //    I elsewhere.
    //    X is constant along the normals, so at distance s its gradient is the surface's
    //    taken along the parallel surface through x: grad_y X = grad_x X (I - s W)^-1, W =
    //    P Hess(psi) P the parallel surface's shape operator (second differences of psi).
    //    The band then holds the surface's strain, not its parallel surfaces' (which differ
    //    by s x curvature: a sphere at rest would hold (1 + s/R)^2 P).
    //    Only near the surface (|s| <= 2 cells: the cells the foot points' trilinear stencils
    //    read, up to sqrt(dim) cells away): farther in, the parallel surfaces curve tightly
    //    and second differences of psi lose accuracy.
    const real ih2 = 1 / (g.dx(0) * g.dx(0));
    const real near = 2 * g.dx(0);
    // Cells with |psi| > near: not valid, Gs = 0 (what the cell's own pass below writes there:
    // 0 times I).
    auto far_from_surface = [&](const Int3& p) {
        valid_(p) = 0;
        for (Field& c : G.comp)
            c(p) = 0;
    };
    for_each_beyond_or_not(
        psi_, body.phi().owned(), near, far_from_surface, [&](int i, int j, int k) {
            const Int3 p{i, j, k};
            real s = 0, gradient = 1;
            Real3 n;
            Matrix3 Gm = identity_matrix();
            real ok = 0;
            if (normal_at(p, s, n, gradient) && std::abs(s) <= near) {
                Matrix3 gx = identity_matrix();
                for (int a = 0; a < dim; ++a) {
                    const Real3 ga = central_gradient4(X[a], g, p, dim);
                    for (int b = 0; b < dim; ++b)
                        gx[a][b] += ga[b];
                }
                Matrix3 H{};
                const real c0 = psi_(p);
                for (int a = 0; a < dim; ++a) {
                    H[a][a] = (psi_(shifted(p, a, 1)) - 2 * c0 + psi_(shifted(p, a, -1))) * ih2;
                    for (int b = a + 1; b < dim; ++b) {
                        const Int3 pp = shifted(shifted(p, a, 1), b, 1);
                        const Int3 pm = shifted(shifted(p, a, 1), b, -1);
                        const Int3 mp = shifted(shifted(p, a, -1), b, 1);
                        const Int3 mm = shifted(shifted(p, a, -1), b, -1);
                        H[a][b] = H[b][a] =
                            (psi_(pp) - psi_(pm) - psi_(mp) + psi_(mm)) * 0.25 * ih2;
                    }
                }
                // Q = (I - s P H P)^-1 (the z row and column stay I in 2D). newton_foot: with
                // psi / |grad psi| for s and P H P / |grad psi| for W (exact for psi = c d).
                const Matrix3 W = tangential_part(H, n, dim);
                const real to_foot = foot_distance(s, gradient);
                const real w_scale = newton_foot_ ? 1 / gradient : 1;
                Matrix3 Q = identity_matrix();
                for (int a = 0; a < dim; ++a)
                    for (int b = 0; b < dim; ++b)
                        Q[a][b] -= to_foot * w_scale * W[a][b];
                // Valid where the parallel surfaces are those of a distance: every tangential
                // eigenvalue of I - s W in [1/2, 2] (1 - s k for curvatures k of the surface).
                // Not so where the two faces' bands overlap (a capsule a few cells thick, its
                // tips) or psi wrinkles: there the foot points crowd, X folds (a singular value
                // of grad X P of 0.03 measured in the d/16 Ca 0.2 capsule's thin end) and Gs
                // from X is meaningless; such cells are left out of the copy in step 3.
                real tr = 0, det = 0;
                {
                    // Eigenvalues of the tangential 2x2 block (3D) or the one value (2D):
                    // from the trace and determinant of Q restricted to the tangent plane
                    // (Q n = n, so those of Q are these and 1).
                    tr = -1;
                    for (int a = 0; a < 3; ++a)
                        tr += Q[a][a];
                    det = determinant(Q);
                }
                const real disc = std::sqrt(std::max(real(0), tr * tr / 4 - det));
                const real lo = dim == 3 ? tr / 2 - disc : tr - 1; // 2D: z row is 1
                const real hi = dim == 3 ? tr / 2 + disc : tr - 1;
                ok = (lo >= 0.5 && hi <= 2.0) ? 1.0 : 0.0;
                Q = inverse(Q);
                Matrix3 gy{};
                for (int a = 0; a < dim; ++a)
                    for (int b = 0; b < dim; ++b)
                        for (int c = 0; c < dim; ++c)
                            gy[a][b] += gx[a][c] * Q[c][b];
                Gm = surface_tensor_from_map(gy, n, dim);
            }
            valid_(p) = ok;
            for (int a = 0; a < dim; ++a)
                for (int b = a; b < dim; ++b)
                    G.comp[SymmetricTensorField::slot(a, b, dim)](p) = ok * Gm[a][b];
        });
    for (Field& c : G.comp)
        halos_.fill(c, body.patch());
    // 2b. (area_filter) J of the rebuilt Gs, low-passed: the (1, 2, 1)^dim weighted mean over
    //     the valid cells of each valid cell's 3^dim block. Step 3 then sets every band cell's
    //     area ratio to this J at its foot point. J is a scalar, so the mean has no bias from
    //     the tangent plane turning between the cells (a mean of Gs tensors has: -0.2 % in
    //     area at R = 8 cells); the (1, 2, 1) weights remove the grid-scale (2h) mode, which
    //     grows in an area-stiff membrane (docs/method.md, "The area ratio, low-passed").
    if (area_filter_) {
        halos_.fill(valid_, body.patch());
        auto fresh = [&](Field& f, const char* name) {
            if (f.data().empty() || f.begin() != X[0].begin() || f.cells() != X[0].cells())
                f = Field::on_patch(name, Location::Cell, X[0].begin(), X[0].cells(), dim, 1);
            f.fill(0);
        };
        fresh(area_ratio_, "area_ratio");
        fresh(filtered_area_ratio_, "filtered_area_ratio");
        for_each_in(body.phi().owned(), [&](int i, int j, int k) {
            if (valid_(i, j, k) != 0) area_ratio_(i, j, k) = area_ratio(G, {i, j, k});
        });
        halos_.fill(area_ratio_, body.patch());
        const int kr = dim == 3 ? 1 : 0;
        for_each_in(body.phi().owned(), [&](int i, int j, int k) {
            if (valid_(i, j, k) == 0) return;
            real sum = 0, weight = 0;
            for (int c = -kr; c <= kr; ++c)
                for (int b = -1; b <= 1; ++b)
                    for (int a = -1; a <= 1; ++a) {
                        const real w = (a ? 1.0 : 2.0) * (b ? 1.0 : 2.0) * (c ? 1.0 : 2.0);
                        weight += w * valid_(i + a, j + b, k + c);
                        sum += w * area_ratio_(i + a, j + b, k + c);
                    }
            filtered_area_ratio_(i, j, k) = sum / weight;
        });
    }
    // 3. Every band cell takes P Gs(y) P, Gs(y) interpolated at its foot point (apply() with
    //    a core of 0): Gs is recomputed from X each step, so this copy smooths nothing that
    //    accumulates, and the trilinear mean over the 8 cells around the surface removes the
    //    grid-scale noise that differences of X and second differences of psi carry (keeping
    //    the cells' own values within one cell of the surface gave tr Gs spikes of 8-27 at the
    //    tips of the d/16 Ca 0.05 capsule, against 2.35 with the copy; docs/method.md).
    run_now(apply_tensor(body, 0.0, &valid_, area_filter_ ? &filtered_area_ratio_ : nullptr,
                         /*psi_current=*/true),
            halos_);
}

} // namespace efsi
