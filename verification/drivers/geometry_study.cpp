// efsi_geometry_study: accuracy of normals and mean curvature computed from a smoothed
// volume fraction phi = (1 - tanh(Lambda(x) / eps)) / 2, with eps = width * h, for
//   sphere:    Lambda = |x - c| - R                       (exact signed distance)
//   ellipsoid: Lambda = a_min (sqrt(q) - 1), q = sum (x - c)_i^2 / a_i^2
//   biconcave: Lambda = L / |grad L|, L = s^2 - h(rho)^2 the Evans-Fung disc (see below)
// whose level sets are (similar) ellipsoids, so the exact normal of phi's level set
// through x is n = -grad q / |grad q| and its mean curvature is
//   kappa_m = div(grad q / |grad q|) / 2 = (tr(H) |grad q|^2 - grad q.H.grad q) / (2 |grad q|^3),
// H = diag(2 / a_i^2). Errors are weighted by the smoothed delta |grad phi| (the weight
// the membrane force carries). Prints one JSON object. One rank.
#include "interface/geometry.hpp"
#include "parallel/decomposition.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <mpi.h>

#include <cmath>

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

        // Evans-Fung disc (R0 = 0.8, symmetry axis along y, so a 2D run cuts through it):
        // L = s^2 - h(rho)^2 with h^2 = (R0/2)^2 (1 - r^2)(C0 + C1 r^2 + C2 r^4)^2, r = rho/R0,
        // smooth everywhere (h^2 is a polynomial in r^2, with a simple root at the rim), and
        // Lambda = L / |grad L| its first-order distance. The exact normal and curvature of
        // Lambda's level sets come from central differences of Lambda with a step of 1e-4
        // (their own error ~1e-8, far below the errors measured).
        const real R0 = 0.8, C0 = 0.207161, C1 = 2.002558, C2 = -1.122762;
        auto disc_level = [&](const Real3& x) {
            const real s = x[1] - c[1];
            real rho2 = (x[0] - c[0]) * (x[0] - c[0]);
            if (dim == 3) rho2 += (x[2] - c[2]) * (x[2] - c[2]);
            const real r2 = rho2 / (R0 * R0);
            const real poly = C0 + C1 * r2 + C2 * r2 * r2;
            return s * s - 0.25 * R0 * R0 * (1 - r2) * poly * poly;
        };
        auto disc_lambda = [&](const Real3& x) {
            const real d = 1e-6;
            real g2 = 0;
            for (int k = 0; k < dim; ++k) {
                Real3 xp = x, xm = x;
                xp[k] += d;
                xm[k] -= d;
                const real gk = (disc_level(xp) - disc_level(xm)) / (2 * d);
                g2 += gk * gk;
            }
            return disc_level(x) / std::sqrt(std::max(g2, 1e-300));
        };
        // Level function, exact inward normal and exact mean curvature at x.
        auto geometry = [&](const Real3& x, real& lambda, Real3& n, real& kappa,
                            real& grad_lambda) {
            if (shape == "biconcave") {
                const real d = 1e-4;
                Real3 gl{0, 0, 0};
                real H[3][3] = {};
                const real l0 = disc_lambda(x);
                for (int ia = 0; ia < dim; ++ia) {
                    Real3 xp = x, xm = x;
                    xp[ia] += d;
                    xm[ia] -= d;
                    const real lp = disc_lambda(xp), lm = disc_lambda(xm);
                    gl[ia] = (lp - lm) / (2 * d);
                    H[ia][ia] = (lp - 2 * l0 + lm) / (d * d);
                    for (int ib = ia + 1; ib < dim; ++ib) {
                        Real3 pp = x, pm = x, mp = x, mm = x;
                        pp[ia] += d;
                        pp[ib] += d;
                        pm[ia] += d;
                        pm[ib] -= d;
                        mp[ia] -= d;
                        mp[ib] += d;
                        mm[ia] -= d;
                        mm[ib] -= d;
                        H[ia][ib] = H[ib][ia] = (disc_lambda(pp) - disc_lambda(pm) -
                                                 disc_lambda(mp) + disc_lambda(mm)) /
                                                (4 * d * d);
                    }
                }
                real g2 = 0, trH = 0, gHg = 0;
                for (int ia = 0; ia < dim; ++ia) {
                    g2 += gl[ia] * gl[ia];
                    trH += H[ia][ia];
                    for (int ib = 0; ib < dim; ++ib)
                        gHg += gl[ia] * H[ia][ib] * gl[ib];
                }
                const real gn = std::sqrt(g2);
                lambda = l0;
                grad_lambda = gn;
                for (int ia = 0; ia < 3; ++ia)
                    n[ia] = ia < dim ? -gl[ia] / gn : 0.0;
                kappa = (trH * g2 - gHg) / (2 * gn * gn * gn);
                return;
            }

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
            real lambda, kappa, gl;
            Real3 n;
            geometry(position(g, block, Location::Cell, i, j, k), lambda, n, kappa, gl);
            phi(i, j, k) = 0.5 * (1 - std::tanh(lambda / eps));
        });
        std::array<Field, 3> normal;
        for (int d = 0; d < 3; ++d)
            normal[d] = Field("n", Location::Cell, block, dim);
        Box inner{{-1, -1, dim == 3 ? -1 : 0},
                  {g.cells[0] + 1, g.cells[1] + 1, g.cells[2] + (dim == 3 ? 1 : 0)}};
        compute_normals(phi, g, inner, st, normal, eps);

        real wsum = 0, en = 0, ek = 0, kref = 0, en_max = 0;
        for_each_cell(g.cells, [&](int i, int j, int k) {
            real lambda, kappa, gl;
            Real3 n;
            geometry(position(g, block, Location::Cell, i, j, k), lambda, n, kappa, gl);
            const real t = std::tanh(lambda / eps);
            const real delta = 0.5 * (1 - t * t) * gl / eps; // |grad phi|
            if (delta * eps < 1e-6) return;                  // outside the band
            real dn2 = 0;
            for (int d = 0; d < dim; ++d)
                dn2 += (normal[d](i, j, k) - n[d]) * (normal[d](i, j, k) - n[d]);
            const real kh = mean_curvature_at(normal, g, dim, {i, j, k});
            wsum += delta;
            en += delta * dn2;
            ek += delta * (kh - kappa) * (kh - kappa);
            kref += delta * kappa * kappa;
            en_max = std::max(en_max, std::sqrt(dn2));
        });
        fmt::print("{{\"shape\": \"{}\", \"stencil\": \"{}\", \"dim\": {}, \"cells\": {}, "
                   "\"width\": {}, \"normal_error\": {:.6e}, \"normal_error_max\": {:.6e}, "
                   "\"curvature_error\": {:.6e}}}\n",
                   shape, stencil, dim, cells, width, std::sqrt(en / wsum), en_max,
                   std::sqrt(ek / kref));
    }
    MPI_Finalize();
    return 0;
}
