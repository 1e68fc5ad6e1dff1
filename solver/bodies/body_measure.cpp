// BodySystem::measure: each body's diagnostics (bodies.csv and the summary: centroid,
// volume, area, Taylor deformation and inclination, the tensor's extremes), apart from the
// step's body work in body_system.cpp.
#include "bodies/body_system.hpp"
#include "membrane/kinematics.hpp"

#include "interface/geometry.hpp"
#include "membrane/membrane_force.hpp"
#include "solid/solid_mechanics.hpp"

#include <cmath>

namespace efsi {

namespace {

/// For each owned row (j, k) of `f`, whether f is nonzero somewhere on it or on a row
/// beside it (j +- 1, k +- 1 in 3D, halo rows included), from one cell before the row to one
/// after: 0 where every 3 x 3 (x 3) stencil centred on the row reads zeros only.
std::vector<char> rows_near_nonzero(const Field& f, int dim) {
    const Box own = f.owned();
    const int n1 = own.hi[1] - own.lo[1], n2 = own.hi[2] - own.lo[2];
    const int r2 = dim == 3 ? 1 : 0;
    // Rows with a halo ring: [lo1 - 1, hi1 + 1) x [lo2 - r2, hi2 + r2).
    const int m1 = n1 + 2, m2 = n2 + 2 * r2;
    std::vector<char> any(std::size_t(m1) * std::size_t(m2), 0);
    for (int k = own.lo[2] - r2; k < own.hi[2] + r2; ++k)
        for (int j = own.lo[1] - 1; j < own.hi[1] + 1; ++j) {
            const real* row = f.data().data() + f.index(own.lo[0] - 1, j, k);
            bool nz = false;
            for (int i = 0; i < own.hi[0] - own.lo[0] + 2; ++i)
                nz = nz || row[i] != 0;
            any[std::size_t(k - own.lo[2] + r2) * std::size_t(m1) +
                std::size_t(j - own.lo[1] + 1)] = nz;
        }
    std::vector<char> out(std::size_t(n1) * std::size_t(n2), 0);
    for (int k = 0; k < n2; ++k)
        for (int j = 0; j < n1; ++j) {
            bool nz = false;
            for (int dk = 0; dk <= 2 * r2; ++dk)
                for (int dj = 0; dj <= 2; ++dj)
                    nz = nz || any[std::size_t(k + dk) * std::size_t(m1) + std::size_t(j + dj)];
            out[std::size_t(k) * std::size_t(n1) + std::size_t(j)] = nz;
        }
    return out;
}

} // namespace

std::vector<BodyDiagnostics> BodySystem::measure() const {
    const GlobalGrid& g = dec_.grid();
    std::vector<BodyDiagnostics> out;
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        const Body& b = *bodies_[i];
        BodyDiagnostics d;
        d.name = b.name();
        // Along periodic directions positions are taken relative to a reference point
        // (the circular mean of phi) by the minimum image, so that a body straddling the
        // seam keeps its centroid and moments (exact while it spans less than half the box).
        const real two_pi = 2 * 3.141592653589793;
        Real3 ref{0, 0, 0};
        auto image = [&](const Real3& x, const Real3& about) {
            Real3 r = x;
            for (int k = 0; k < g.dim; ++k)
                if (dec_.periodic()[k])
                    r[k] = x[k] - g.length[k] * std::round((x[k] - about[k]) / g.length[k]);
            return r;
        };
        real v = 0, lo = 1, hi = 0;
        Real3 m{0, 0, 0}, cs{0, 0, 0}, sn{0, 0, 0};
        if (!b.patch().empty())
            for_each_in(b.phi().owned(), [&](int a, int bb, int c) {
                const real p = b.phi()(a, bb, c);
                lo = std::min(lo, p);
                hi = std::max(hi, p);
                // An empty cell adds zero to every sum below (most of a patch is empty).
                if (p == 0) return;
                const Real3 x = position(g, dec_.block(), Location::Cell, a, bb, c);
                for (int k = 0; k < g.dim; ++k) {
                    const real th = two_pi * (x[k] - g.origin[k]) / g.length[k];
                    cs[k] += p * std::cos(th);
                    sn[k] += p * std::sin(th);
                }
            });
        for (int k = 0; k < g.dim; ++k)
            if (dec_.periodic()[k])
                ref[k] = g.origin[k] +
                         g.length[k] / two_pi * std::atan2(dec_.sum(sn[k]), dec_.sum(cs[k]));
        if (!b.patch().empty())
            for_each_in(b.phi().owned(), [&](int a, int bb, int c) {
                const real p = b.phi()(a, bb, c);
                if (p == 0) return;
                const Real3 x = image(position(g, dec_.block(), Location::Cell, a, bb, c), ref);
                v += p;
                for (int k = 0; k < 3; ++k)
                    m[k] += p * x[k];
            });
        v = dec_.sum(v);
        for (int k = 0; k < 3; ++k)
            d.centroid[k] = v > 0 ? dec_.sum(m[k]) / v : 0.0;
        const Real3 centre = d.centroid;
        // Reported inside the box.
        for (int k = 0; k < g.dim; ++k)
            if (dec_.periodic()[k])
                d.centroid[k] =
                    g.origin[k] +
                    std::fmod(std::fmod(centre[k] - g.origin[k], g.length[k]) + g.length[k],
                              g.length[k]);
        // Second moments about the centroid (x-y block) and the area integral of |grad phi|;
        // the same moments of the sharp body chi (BodyDiagnostics::taylor_deformation_sharp),
        // about chi's own centroid: its sums relative to phi's centroid, shifted after.
        real mxx = 0, myy = 0, mxy = 0, area = 0;
        real cv = 0, cx = 0, cy = 0, cxx = 0, cyy = 0, cxy = 0;
        const real h = g.dx(0);
        // Rows (j, k) whose cells add zero here: phi = 0 on them and on the rows beside them
        // (the gradient's stencil, halos included), so |grad phi| = 0 and chi = 0.
        const std::vector<char> busy =
            b.patch().empty() ? std::vector<char>{} : rows_near_nonzero(b.phi(), g.dim);
        const Box own = b.phi().owned();
        if (!b.patch().empty())
            for_each_in(own, [&](int a, int bb, int c) {
                if (!busy[std::size_t(c - own.lo[2]) * std::size_t(own.hi[1] - own.lo[1]) +
                          std::size_t(bb - own.lo[1])])
                    return;
                const real p = b.phi()(a, bb, c);
                const Real3 x = image(position(g, dec_.block(), Location::Cell, a, bb, c), centre);
                const real dx = x[0] - centre[0], dy = x[1] - centre[1];
                mxx += p * dx * dx;
                myy += p * dy * dy;
                mxy += p * dx * dy;
                const Real3 gr = gradient_at(b.phi(), g, {a, bb, c}, GradientStencil::Isotropic);
                const real gn = std::sqrt(gr[0] * gr[0] + gr[1] * gr[1] + gr[2] * gr[2]);
                area += gn;
                const real chi = gn * h > 1e-12 ? std::clamp(0.5 + (p - 0.5) / (gn * h), 0.0, 1.0)
                                                : (p > 0.5 ? 1.0 : 0.0);
                cv += chi;
                cx += chi * dx;
                cy += chi * dy;
                cxx += chi * dx * dx;
                cyy += chi * dy * dy;
                cxy += chi * dx * dy;
            });
        mxx = dec_.sum(mxx);
        myy = dec_.sum(myy);
        mxy = dec_.sum(mxy);
        d.area = dec_.sum(area) * g.cell_volume();
        auto deformation = [](real xx, real yy, real xy) {
            const real mean = 0.5 * (xx + yy);
            const real dev = std::sqrt(0.25 * (xx - yy) * (xx - yy) + xy * xy);
            const real L = std::sqrt(std::max(mean + dev, 0.0)),
                       B = std::sqrt(std::max(mean - dev, 0.0));
            return L + B > 0 ? (L - B) / (L + B) : 0.0;
        };
        d.taylor_deformation = deformation(mxx, myy, mxy);
        d.inclination_over_pi = 0.5 * std::atan2(2 * mxy, mxx - myy) / 3.141592653589793;
        cv = dec_.sum(cv);
        if (cv > 0) {
            const real mx = dec_.sum(cx) / cv, my = dec_.sum(cy) / cv;
            d.taylor_deformation_sharp =
                deformation(dec_.sum(cxx) / cv - mx * mx, dec_.sum(cyy) / cv - my * my,
                            dec_.sum(cxy) / cv - mx * my);
        }
        real trace_max = 0, reference_area = 0;
        const SymmetricTensorField& T = b.tensor();
        // A membrane's Gs means the membrane's stretch only in its band (beyond it is I or
        // an extension): its largest trace is taken where the force is, 1e-5 < phi < 1 - 1e-5
        // and psi (interface/geometry.hpp, profile_distance) a distance, |grad psi| >= 1/2
        // (elsewhere the normal extension resets Gs to I).
        const bool membrane = b.kind() == BodyKind::Membrane;
        const real floor = membrane ? MembraneForceSettings{}.band_cutoff : 0.0;
        const real eps_cells = cfg_.bodies[i].smoothing_width;
        if (!b.patch().empty() && !T.comp.empty())
            for_each_in(b.phi().owned(), [&](int a, int bb, int c) {
                const real f = b.phi()(a, bb, c);
                if (f <= floor || f >= 1 - floor) return;
                const Int3 p{a, bb, c};
                if (membrane) {
                    // |grad psi| from central differences, psi in cells (eps = eps_cells).
                    real g2 = 0;
                    for (int dir = 0; dir < g.dim; ++dir) {
                        Int3 below = p, above = p;
                        --below[dir];
                        ++above[dir];
                        const real gd = 0.5 * (profile_distance(b.phi()(above), eps_cells) -
                                               profile_distance(b.phi()(below), eps_cells));
                        g2 += gd * gd;
                    }
                    if (g2 < 0.25) return;
                }
                trace_max =
                    std::max(trace_max, T.value(0, 0, p) + T.value(1, 1, p) + T.value(2, 2, p));
                if (membrane) {
                    Matrix3 Gs{};
                    for (int r = 0; r < 3; ++r)
                        for (int q = 0; q < 3; ++q)
                            Gs[r][q] = T.value(r, q, p);
                    // A cell whose stored Gs has lost rank (J < 1e-3: no membrane stretch
                    // there, e.g. a cell the extension has not filled) is left out: the
                    // force leaves it out too (membrane_force.hpp, the band's J criterion),
                    // and 1/J would swamp the sum (measured: J ~ 1e-150 in single cells of
                    // the d/16 Ca 0.2 capsule).
                    const real J = std::sqrt(std::max(second_invariant(Gs), real(0)));
                    if (J < 1e-3) return;
                    const Real3 gr = gradient_at(b.phi(), g, p, GradientStencil::Isotropic);
                    reference_area += std::sqrt(gr[0] * gr[0] + gr[1] * gr[1] + gr[2] * gr[2]) / J;
                }
            });
        d.tensor_trace_max = dec_.max(trace_max);
        d.reference_area = membrane ? dec_.sum(reference_area) * g.cell_volume() : 0.0;
        d.volume = v * g.cell_volume();
        d.phi_min = dec_.min(lo);
        d.phi_max = dec_.max(hi);
        d.patch_cells =
            dec_.sum(std::int64_t(b.patch().local.empty() ? 0 : b.patch().local.count()));
        d.bytes = dec_.sum(std::int64_t(b.bytes()));
        d.clipped_volume = clipped_[i];
        out.push_back(d);
    }
    return out;
}

} // namespace efsi
