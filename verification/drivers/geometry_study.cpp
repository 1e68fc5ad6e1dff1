// efsi_geometry_study: accuracy of normals and mean curvature computed from a smoothed
// volume fraction phi = (1 - tanh(Lambda(x) / eps)) / 2, with eps = width * h, for
//   sphere:    Lambda = |x - c| - R                       (exact signed distance)
//   ellipsoid: Lambda = a_min (sqrt(q) - 1), q = sum (x - c)_i^2 / a_i^2
//   biconcave: Lambda = the exact signed distance to the Evans-Fung disc (the solver's
//              make_biconcave_distance, the level of a smoothed red cell; see below)
// The ellipsoid's level sets are (similar) ellipsoids, so the exact normal of phi's level
// set through x is n = -grad q / |grad q| and its mean curvature is
//   kappa_m = div(grad q / |grad q|) / 2 = (tr(H) |grad q|^2 - grad q.H.grad q) / (2 |grad q|^3),
// H = diag(2 / a_i^2); the disc's are its parallel surfaces (reference computed below). Errors are
// weighted by the smoothed delta |grad phi| (the weight the membrane force carries). Prints one
// JSON object. One rank.
#include "interface/geometry.hpp"
#include "interface/shapes.hpp"
#include "membrane/membrane_force.hpp"
#include "parallel/decomposition.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

using namespace efsi;

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    {
        CLI::App app{"Normals and curvature from a smoothed VOF field (verification)"};
        std::string shape = "sphere", stencil = "isotropic";
        int cells = 32, dim = 3;
        real width = 1.0;
        app.add_option("--shape", shape, "sphere, ellipsoid or biconcave")
            ->check(CLI::IsMember({"sphere", "ellipsoid", "biconcave"}));
        app.add_option("--stencil", stencil, "central, youngs, isotropic or distance");
        app.add_option("--cells", cells, "cells across the box [-1,1]^dim");
        app.add_option("--dim", dim, "2 or 3");
        app.add_option("--width", width, "smoothing half-width eps in cells");
        real r0 = 0.8;
        app.add_option("--r0", r0, "biconcave: the disc's radius R0 (box [-1,1])")
            ->check(CLI::Range(0.05, 0.9));
        CLI11_PARSE(app, argc, argv);
        const GradientStencil st = gradient_stencil_from_string(stencil);

        GlobalGrid g;
        g.dim = dim;
        g.cells = {cells, cells, dim == 3 ? cells : 1};
        g.length = {2, 2, dim == 3 ? 2.0 : 2.0 / cells};
        g.origin = {-1, -1, dim == 3 ? -1.0 : -1.0 / cells};
        const LocalBlock block{g.cells, {0, 0, 0}};
        const real h = g.dx(0), eps = width * h;
        const Real3 c{0.013, 0.027, dim == 3 ? 0.041 : 0.0};
        const Real3 a = shape == "sphere" ? Real3{0.5, 0.5, 0.5} : Real3{0.6, 0.4, 0.3};
        const real amin = dim == 3 ? std::min({a[0], a[1], a[2]}) : std::min(a[0], a[1]);

        // Evans-Fung disc (radius R0, default 0.8; symmetry axis along y, so a 2D run cuts
        // through it). Lambda is the level function the solver gives a smoothed red cell
        // (make_biconcave_distance: the exact signed distance, body_system.cpp), and the
        // reference is computed here independently of it: the nearest point of the upper
        // meridian c(t) = (R0 sin t, (R0/2) cos t P(sin^2 t)), P(u) = C0 + C1 u + C2 u^2,
        // t in [0, pi/2] (2048 samples, then Newton on (c - q).c' = 0), its outward normal
        // N = (-z', rho') / |c'| and principal curvatures (convex > 0)
        //   k1 = (z' rho'' - rho' z'') / |c'|^3 (meridian),  k2 = N_rho / rho_c (azimuth),
        // so that phi's level set through x, the parallel surface at distance d, has the
        // normal N and the mean curvature (sum_i k_i / (1 + d k_i)) / 2 (k1 only in 2D, as
        // div(n) / 2 there). On the axis (rho_c -> 0) k2 = k1.
        // (The former Lambda = L / |grad L| with L = s^2 - h(rho)^2 the Evans-Fung polynomial
        // had a second zero set: P(r^2) = 0 at r = 1.372, so L = s^2 + (r^2 - 1) P^2 R0^2 / 4
        // vanished on the ring rho = 1.10 (R0 = 0.8), s = 0, which lies in the corners of the
        // 3D box but outside the 2D one; that spurious thin tube carried most of the 3D error.)
        EvansFungCoefficients ef;
        ef.r0 = r0;
        const real R0 = ef.r0, C0 = ef.c0, C1 = ef.c1, C2 = ef.c2;
        // Columns are the body axes in the lab frame: body x = lab x, body y = -lab z,
        // body z (the symmetry axis) = lab y.
        const Matrix3 disc_rot{Real3{1, 0, 0}, Real3{0, 0, 1}, Real3{0, -1, 0}};
        const auto disc = make_biconcave_distance(c, disc_rot, ef);
        struct MeridianPoint {
            real rho, z, drho, dz, ddrho, ddz;
        };
        auto meridian = [&](real t) {
            const real s = std::sin(t), co = std::cos(t), u = s * s;
            const real du = 2 * s * co, ddu = 2 * (co * co - s * s);
            const real p = C0 + C1 * u + C2 * u * u, dp = (C1 + 2 * C2 * u) * du,
                       ddp = 2 * C2 * du * du + (C1 + 2 * C2 * u) * ddu;
            return MeridianPoint{R0 * s,  0.5 * R0 * co * p,
                                 R0 * co, 0.5 * R0 * (-s * p + co * dp),
                                 -R0 * s, 0.5 * R0 * (-co * p - 2 * s * dp + co * ddp)};
        };
        constexpr int msamples = 2048;
        const real tmax = 0.5 * std::numbers::pi, tstep = tmax / msamples;
        std::vector<MeridianPoint> msample(msamples + 1);
        for (int i = 0; i <= msamples; ++i)
            msample[i] = meridian(i * tstep);
        // The reference at x: signed distance d, inward normal n, mean curvature kappa of
        // the level set through x, and r_near = rho_c / R0 of the nearest surface point.
        auto disc_geometry = [&](const Real3& x, real& d, Real3& n, real& kappa, real& r_near) {
            // Body coordinates y = R^T (x - c).
            Real3 y{0, 0, 0};
            for (int q = 0; q < 3; ++q)
                for (int p = 0; p < 3; ++p)
                    y[q] += disc_rot[p][q] * (x[p] - c[p]);
            const real rho = std::hypot(y[0], y[1]), z = std::abs(y[2]);
            int best = 0;
            real dbest = std::numeric_limits<real>::max();
            for (int i = 0; i <= msamples; ++i) {
                const real d2 = (rho - msample[i].rho) * (rho - msample[i].rho) +
                                (z - msample[i].z) * (z - msample[i].z);
                if (d2 < dbest) {
                    dbest = d2;
                    best = i;
                }
            }
            // Newton on g(t) = (c - q).c', kept in the bracket of the best sample.
            const real lo = std::max(0, best - 1) * tstep,
                       hi = std::min(msamples, best + 1) * tstep;
            real t = best * tstep;
            for (int it = 0; it < 50; ++it) {
                const MeridianPoint m = meridian(t);
                const real gt = (m.rho - rho) * m.drho + (m.z - z) * m.dz;
                const real dgt =
                    m.drho * m.drho + m.dz * m.dz + (m.rho - rho) * m.ddrho + (m.z - z) * m.ddz;
                if (!(dgt > 0)) break;
                const real tn = std::clamp(t - gt / dgt, lo, hi);
                const bool done = std::abs(tn - t) < 1e-15;
                t = tn;
                if (done) break;
            }
            const MeridianPoint m = meridian(t);
            const real sp = std::hypot(m.drho, m.dz);
            const real nrho = -m.dz / sp, nz = m.drho / sp; // outward, upper half
            const real dist = std::hypot(rho - m.rho, z - m.z);
            d = (rho - m.rho) * nrho + (z - m.z) * nz >= 0 ? dist : -dist;
            r_near = m.rho / R0;
            const real k1 = (m.dz * m.ddrho - m.drho * m.ddz) / (sp * sp * sp);
            const real k2 = m.rho > 1e-7 * R0 ? nrho / m.rho : k1;
            kappa = 0.5 * (k1 / (1 + d * k1) + (dim == 3 ? k2 / (1 + d * k2) : 0.0));
            // Inward normal in body coordinates, then in the lab frame.
            const real er0 = rho > 0 ? y[0] / rho : 0.0, er1 = rho > 0 ? y[1] / rho : 0.0;
            const Real3 nb{-nrho * er0, -nrho * er1, -(y[2] >= 0 ? nz : -nz)};
            for (int p = 0; p < 3; ++p) {
                n[p] = 0;
                for (int q = 0; q < 3; ++q)
                    n[p] += disc_rot[p][q] * nb[q];
            }
            if (dim == 2) n[2] = 0;
        };
        // Sphere and ellipsoid: level function, exact inward normal and mean curvature at x.
        auto geometry = [&](const Real3& x, real& lambda, Real3& n, real& kappa,
                            real& grad_lambda) {
            Real3 gq{0, 0, 0};
            real q = 0, trH = 0, gHg = 0, gq2 = 0;
            for (int d = 0; d < dim; ++d) {
                const real y = x[d] - c[d];
                q += y * y / (a[d] * a[d]);
                gq[d] = 2 * y / (a[d] * a[d]);
                trH += 2 / (a[d] * a[d]);
                gHg += gq[d] * gq[d] * 2 / (a[d] * a[d]);
                gq2 += gq[d] * gq[d];
            }
            const real gn = std::sqrt(gq2);
            lambda = amin * (std::sqrt(q) - 1);
            grad_lambda = amin * gn / (2 * std::sqrt(q));
            for (int d = 0; d < 3; ++d)
                n[d] = d < dim ? -gq[d] / gn : 0.0;
            kappa = (trH * gq2 - gHg) / (2 * gn * gn * gn);
        };

        Field phi("phi", Location::Cell, block, dim);
        const Int3 hw = phi.halo();
        const Box all{{-hw[0], -hw[1], -hw[2]},
                      {g.cells[0] + hw[0], g.cells[1] + hw[1], g.cells[2] + hw[2]}};
        for_each_in(all, [&](int i, int j, int k) {
            const Real3 x = position(g, block, Location::Cell, i, j, k);
            real lambda, kappa, gl;
            Real3 n;
            if (shape == "biconcave")
                lambda = disc->level(x);
            else
                geometry(x, lambda, n, kappa, gl);
            phi(i, j, k) = 0.5 * (1 - std::tanh(lambda / eps));
        });
        std::array<Field, 3> normal;
        for (int d = 0; d < 3; ++d)
            normal[d] = Field("n", Location::Cell, block, dim);
        Box inner{{-1, -1, dim == 3 ? -1 : 0},
                  {g.cells[0] + 1, g.cells[1] + 1, g.cells[2] + (dim == 3 ? 1 : 0)}};
        compute_normals(phi, g, inner, st, normal, eps);

        // Besides the delta-weighted errors over the whole band: the normal error on the
        // cells where the membrane force evaluates the tension (MembraneForceSettings: the
        // 3^dim block in band_cutoff < phi < 1 - band_cutoff and, with the distance stencil,
        // |grad psi| >= min_distance_gradient), and the curvature error weighted by the
        // bending kernel (1 + cos(pi psi / w)) / (2 w), w = bending_width cells.
        // Biconcave: the errors are also split by where the nearest surface point lies
        // (dimple r < 1/2, rim r >= 1/2), each part as its share of the totals (the two parts
        // add in squares), and the solver's level is checked against the reference distance.
        const MembraneForceSettings force;
        const real wb = force.bending_width * h;
        auto in_force_band = [&](int i, int j, int k) {
            for (int oz = dim == 3 ? -1 : 0; oz <= (dim == 3 ? 1 : 0); ++oz)
                for (int oy = -1; oy <= 1; ++oy)
                    for (int ox = -1; ox <= 1; ++ox) {
                        const real v = phi(i + ox, j + oy, k + oz);
                        if (!(v > force.band_cutoff && v < 1 - force.band_cutoff)) return false;
                    }
            if (st != GradientStencil::Distance) return true;
            const Real3 gr = gradient_at(phi, g, {i, j, k}, st, eps);
            return std::sqrt(gr[0] * gr[0] + gr[1] * gr[1] + gr[2] * gr[2]) >=
                   force.min_distance_gradient;
        };
        real wsum = 0, en = 0, ek = 0, kref = 0, en_max = 0, en_dimple = 0, ek_dimple = 0,
             level_mismatch = 0, wband = 0, en_band = 0, en_band_max = 0, ekb = 0, krefb = 0,
             en_band_dimple = 0, ekb_dimple = 0;
        for_each_cell(g.cells, [&](int i, int j, int k) {
            const Real3 x = position(g, block, Location::Cell, i, j, k);
            real lambda, kappa = 0, gl, r_near = 1;
            Real3 n;
            if (shape == "biconcave") {
                lambda = disc->level(x);
                gl = 1;
            } else {
                geometry(x, lambda, n, kappa, gl);
            }
            const real t = std::tanh(lambda / eps);
            const real delta = 0.5 * (1 - t * t) * gl / eps; // |grad phi|
            if (delta * eps < 1e-6) return;                  // outside the band
            if (shape == "biconcave") {
                real d;
                disc_geometry(x, d, n, kappa, r_near);
                level_mismatch = std::max(level_mismatch, std::abs(d - lambda));
            }
            real dn2 = 0;
            for (int d = 0; d < dim; ++d)
                dn2 += (normal[d](i, j, k) - n[d]) * (normal[d](i, j, k) - n[d]);
            const real kh = mean_curvature_at(normal, g, dim, {i, j, k});
            wsum += delta;
            en += delta * dn2;
            ek += delta * (kh - kappa) * (kh - kappa);
            kref += delta * kappa * kappa;
            en_max = std::max(en_max, std::sqrt(dn2));
            if (r_near < 0.5) {
                en_dimple += delta * dn2;
                ek_dimple += delta * (kh - kappa) * (kh - kappa);
            }
            if (in_force_band(i, j, k)) {
                wband += delta;
                en_band += delta * dn2;
                en_band_max = std::max(en_band_max, std::sqrt(dn2));
                if (r_near < 0.5) en_band_dimple += delta * dn2;
            }
            if (const real psi = profile_distance(phi(i, j, k), eps); std::abs(psi) < wb) {
                const real wc = (1 + std::cos(std::numbers::pi * psi / wb)) / (2 * wb);
                ekb += wc * (kh - kappa) * (kh - kappa);
                krefb += wc * kappa * kappa;
                if (r_near < 0.5) ekb_dimple += wc * (kh - kappa) * (kh - kappa);
            }
        });
        std::string extra;
        if (shape == "biconcave")
            extra = fmt::format(
                ", \"r0\": {}, \"h_over_r0\": {:.6e}, \"dimple_cells\": {:.6e}, "
                "\"normal_error_dimple\": {:.6e}, \"normal_error_rim\": {:.6e}, "
                "\"curvature_error_dimple\": {:.6e}, "
                "\"curvature_error_rim\": {:.6e}, "
                "\"normal_error_force_band_dimple\": {:.6e}, "
                "\"normal_error_force_band_rim\": {:.6e}, "
                "\"curvature_error_bending_dimple\": {:.6e}, "
                "\"curvature_error_bending_rim\": {:.6e}, \"level_mismatch\": {:.3e}",
                R0, h / R0, R0 * C0 / h, std::sqrt(en_dimple / wsum),
                std::sqrt((en - en_dimple) / wsum), std::sqrt(ek_dimple / kref),
                std::sqrt((ek - ek_dimple) / kref), std::sqrt(en_band_dimple / wband),
                std::sqrt((en_band - en_band_dimple) / wband), std::sqrt(ekb_dimple / krefb),
                std::sqrt((ekb - ekb_dimple) / krefb), level_mismatch / R0);
        fmt::print(
            "{{\"shape\": \"{}\", \"stencil\": \"{}\", \"dim\": {}, \"cells\": {}, "
            "\"width\": {}, \"normal_error\": {:.6e}, \"normal_error_max\": {:.6e}, "
            "\"curvature_error\": {:.6e}, \"normal_error_force_band\": {:.6e}, "
            "\"normal_error_max_force_band\": {:.6e}, \"curvature_error_bending\": {:.6e}{}}}\n",
            shape, stencil, dim, cells, width, std::sqrt(en / wsum), en_max, std::sqrt(ek / kref),
            std::sqrt(en_band / wband), en_band_max, std::sqrt(ekb / krefb), extra);
    }
    MPI_Finalize();
    return 0;
}
