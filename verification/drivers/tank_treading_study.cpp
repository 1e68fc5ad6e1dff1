// efsi_tank_treading_study: a membrane's strain carrier under tank-treading, against the
// exact map, with no flow solve.
//
// A membrane lies unstrained on the ellipsoid x^2/a^2 + y^2/b^2 + z^2/c^2 = 1 (its reference
// shape). The prescribed steady flow v = w (-(a/b) y, (b/a) x, 0) is solenoidal and tangent
// to every ellipsoid of that family, so phi stays where it is while the membrane goes round
// it: the tank-treading of a sheared capsule at its steady shape, without the shape. Points
// move on ellipses at a uniform phase rate w, x(t) = F X with F = A R(w t) A^-1, A =
// diag(a, b, 1), R a rotation about z. F is uniform, so the exact surface strain is known
// everywhere:
//   X(y, t) = F^-1 y  (y on the surface),   Gs = F P_R F^T,   J = sqrt(II(Gs)),
// P_R the tangent projector of the reference ellipsoid at X. The membrane is stretched and
// relaxed twice per turn (J = 1 where the material started; the in-plane stretch reaches a/b).
//
// The solver's own body pipeline runs each step (BodySystem::advance: VOF, the surface
// velocity, the map's transport, its extension along the normals and projection on the
// reference surface, Gs rebuilt from the map), with the case keys of cases/capsule_shear
// for the membrane. Measured on the band core (cells with |psi| <= 1 cell), against the
// exact values at each cell's foot point y (the closest point of the fixed ellipsoid):
//   X_error_rms / X_error_max   |X - F^-1 y| / h (the map's tangential position error),
//   J_error_rms / J_error_max   |J - J_exact|; J_error_mean its signed mean (a bias),
//   shear_error_rms / _mean     lambda1/lambda2 - exact (the in-plane stretch ratio): rms, mean,
// one JSON line per sample time (every `--samples` per turn) on stdout.
#include "bodies/body.hpp"
#include "bodies/body_shape.hpp"
#include "bodies/body_system.hpp"
#include "boundary/boundary.hpp"
#include "config/config.hpp"
#include "core/error.hpp"
#include "core/matrix3.hpp"
#include "interface/geometry.hpp"
#include "interface/prescribed_velocity.hpp"
#include "interface/shapes.hpp"
#include "membrane/kinematics.hpp"
#include "parallel/decomposition.hpp"
#include "time/stage_timers.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <mpi.h>

#include <chrono>
#include <cmath>

using namespace efsi;

namespace {

/// A R(angle) A^-1 with A = diag(a, b, 1): the flow map over a phase `angle`.
Matrix3 flow_map(real a, real b, real angle) {
    const real c = std::cos(angle), s = std::sin(angle);
    return {{{c, -a / b * s, 0}, {b / a * s, c, 0}, {0, 0, 1}}};
}

Matrix3 product(const Matrix3& A, const Matrix3& B) {
    Matrix3 C{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k)
                C[i][j] += A[i][k] * B[k][j];
    return C;
}

/// The stretch ratio lambda1 / lambda2 >= 1 of a surface tensor (its two nonzero
/// eigenvalues are lambda^2: tr = l1^2 + l2^2, II = l1^2 l2^2).
real stretch_ratio(const Matrix3& G) {
    const real tr = G[0][0] + G[1][1] + G[2][2], ii = std::max(second_invariant(G), 1e-300);
    const real disc = std::sqrt(std::max(tr * tr - 4 * ii, 0.0));
    return std::sqrt((tr + disc) / std::max(tr - disc, 1e-300));
}

int run(int argc, char** argv) {
    CLI::App app{"efsi_tank_treading_study: a membrane's map carried round a fixed ellipsoid by a "
                 "tank-treading flow, against the exact map (JSON lines on stdout)"};
    int per_diameter = 16, samples = 4;
    real a = 1.4, b = 0.7, turns = 2, cfl = 0.2, omega = 1;
    std::vector<std::string> sets;
    app.add_option("--per-diameter", per_diameter,
                   "cells per diameter of the volume-equivalent sphere (radius 1)");
    app.add_option("--a", a, "semi-axis along x");
    app.add_option("--b", b, "semi-axis along y (c = 1 / (a b): the unit sphere's volume)");
    app.add_option("--turns", turns, "membrane turns (of period 2 pi / omega) to run");
    app.add_option("--omega", omega, "phase rate of the tank-treading [1/s]");
    app.add_option("--cfl", cfl, "dt = cfl h / (largest surface speed)");
    app.add_option("--samples", samples, "measurements per turn");
    app.add_option("--set", sets, "extra case keys, key=value (as efsi run --set)");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    if (!(a > 0 && b > 0 && turns > 0 && cfl > 0 && omega > 0 && per_diameter >= 4 && samples >= 1))
        throw InputError("positive --a, --b, --turns, --omega, --cfl, --samples and "
                         "--per-diameter >= 4 are required");
    const real c = 1 / (a * b);
    const real h = 2.0 / per_diameter;
    // The box: the flow's moving region (rho2 below, times the largest semi-axis) and 6 cells.
    const int half =
        int(std::ceil(std::max({a, b, c}) * (1 + 10 * h / std::min(a, b) + 0.5) / h)) + 6;
    const real length = 2 * half * h;
    const std::string toml = fmt::format(R"(
[case]
name = "tank_treading"
[grid]
cells = [{0}, {0}, {0}]
length = [{1}, {1}, {1}]
origin = [{2}, {2}, {2}]
[fluid]
density = 0.01
viscosity = 1.0
[time]
end_time = 1.0
[[body]]
name = "membrane"
kind = "membrane"
law = "neo_hookean"
elastic_modulus = 1.0
shape = "ellipsoid"
semi_axes = [{3}, {4}, {5}]
centre = [0.0, 0.0, 0.0]
interface = "smoothed"
smoothing_width = 0.75
)",
                                         2 * half, length, -0.5 * length, a, b, c);
    Overrides over;
    for (const std::string& kv : sets) {
        const auto eq = kv.find('=');
        if (eq == std::string::npos)
            throw InputError(fmt::format("--set {}: expected key=value", kv));
        over.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
    }
    const Config cfg = parse_case(toml, ".", over);

    Decomposition dec(MPI_COMM_WORLD, cfg.grid, periodic_directions(cfg.boundaries), cfg.ranks);
    HaloFiller halos(dec, cfg.boundaries);
    BodySystem bodies(cfg, dec, halos);
    bodies.initialise();
    Body& body = *bodies.bodies()[0];
    if (body.reference_map().empty())
        throw InputError("the membrane carries no reference map (strain_model must be "
                         "reference_map)");
    const auto shape = make_body_shape(cfg.bodies[0]);

    const GlobalGrid& g = dec.grid();
    VelocityField u("u", dec.block(), 3);
    // v = curl (0, 0, psi) (u = dpsi/dy, v = -dpsi/dx: discretely solenoidal), psi = -w/2
    // f(q), q = (a/b) y^2 + (b/a) x^2 = a b rho^2 (rho = 1 on the ellipsoid's equator).
    // f(q) = q out to rho1, past every cell the band and its stencils reach, so the flow
    // there is exactly the tank-treading one; beyond, f' falls to 0 by a cosine over
    // rho1 < rho < rho2, so the far field is at rest (the VOF step's Courant number is
    // taken over the whole box, and the box is periodic).
    const real rho1 = 1 + 10 * h / std::min(a, b), rho2 = rho1 + 0.5;
    const real q1 = a * b * rho1 * rho1, q2 = a * b * rho2 * rho2;
    const real pi = 3.141592653589793;
    auto f = [&](real q) {
        if (q <= q1) return q;
        if (q >= q2) return q1 + 0.5 * (q2 - q1);
        return q1 + 0.5 * (q - q1) + (q2 - q1) / (2 * pi) * std::sin(pi * (q - q1) / (q2 - q1));
    };
    set_velocity_from_potential(u, g, dec.block(), [&](const Real3& x) {
        return Real3{0, 0, -0.5 * omega * f(a / b * x[1] * x[1] + b / a * x[0] * x[0])};
    });
    const real speed = omega * std::max(a, b) * rho2;
    const real period = 2 * 3.141592653589793 / omega;
    const int steps_per_sample = int(std::ceil(period / samples / (cfl * h / speed)));
    const real dt = period / samples / steps_per_sample;
    const int total = int(std::lround(turns * samples)) * steps_per_sample;

    StageTimers timers;
    const real eps = cfg.bodies[0].smoothing_width * h;
    const auto t0 = std::chrono::steady_clock::now();
    for (int step = 0; step <= total; ++step) {
        if (step % steps_per_sample == 0) {
            const real t = step * dt;
            const Matrix3 Finv = flow_map(a, b, -omega * t), F = flow_map(a, b, omega * t);
            real x2 = 0, xmax = 0, j1 = 0, s1 = 0, j2 = 0, jmax = 0, s2 = 0, count = 0;
            // The body's fields live on its patch: its owned cells.
            for_each_in(body.phi().owned(), [&](int i, int j, int k) {
                const real psi = profile_distance(body.phi()(i, j, k), eps);
                if (std::abs(psi) > h) return;
                const Real3 x = position(g, dec.block(), Location::Cell, i, j, k);
                const Real3 y = shape->closest_point(x);
                const Real3 Xe = mat_vec(Finv, y);
                real dx2 = 0;
                for (int d = 0; d < 3; ++d) {
                    const real Xs = x[d] + body.reference_map()[d](i, j, k);
                    dx2 += (Xs - Xe[d]) * (Xs - Xe[d]);
                }
                // P_R at Xe: the normal of the reference ellipsoid.
                Real3 nR{Xe[0] / (a * a), Xe[1] / (b * b), Xe[2] / (c * c)};
                const real len = std::sqrt(nR[0] * nR[0] + nR[1] * nR[1] + nR[2] * nR[2]);
                Matrix3 P = identity_matrix();
                for (int p = 0; p < 3; ++p)
                    for (int q = 0; q < 3; ++q)
                        P[p][q] -= nR[p] * nR[q] / (len * len);
                const Matrix3 E = product(product(F, P), transpose(F));
                Matrix3 G{};
                for (int p = 0; p < 3; ++p)
                    for (int q = 0; q < 3; ++q)
                        G[p][q] = body.tensor().value(p, q, {i, j, k});
                const real dj = std::sqrt(std::max(second_invariant(G), 0.0)) -
                                std::sqrt(std::max(second_invariant(E), 0.0));
                const real ds = stretch_ratio(G) - stretch_ratio(E);
                x2 += dx2 / (h * h);
                xmax = std::max(xmax, std::sqrt(dx2) / h);
                j1 += dj;
                s1 += ds;
                j2 += dj * dj;
                jmax = std::max(jmax, std::abs(dj));
                s2 += ds * ds;
                count += 1;
            });
            count = dec.sum(count);
            x2 = dec.sum(x2);
            j1 = dec.sum(j1);
            s1 = dec.sum(s1);
            j2 = dec.sum(j2);
            s2 = dec.sum(s2);
            xmax = dec.max(xmax);
            jmax = dec.max(jmax);
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            if (dec.rank() == 0)
                fmt::print("{{\"per_diameter\": {}, \"a\": {}, \"b\": {}, \"turns\": {:.6f}, "
                           "\"t\": {:.6f}, \"step\": {}, \"dt\": {:.6e}, \"core_cells\": {}, "
                           "\"X_error_rms\": {:.6e}, \"X_error_max\": {:.6e}, "
                           "\"J_error_rms\": {:.6e}, "
                           "\"J_error_max\": {:.6e}, \"J_error_mean\": {:.6e}, "
                           "\"shear_error_rms\": {:.6e}, \"shear_error_mean\": {:.6e}, "
                           "\"seconds\": {:.3f}, \"ranks\": {}}}\n",
                           per_diameter, a, b, t / period, t, step, dt, std::int64_t(count),
                           std::sqrt(x2 / count), xmax, std::sqrt(j2 / count), jmax, j1 / count,
                           std::sqrt(s2 / count), s1 / count, seconds, dec.size());
            std::fflush(stdout);
        }
        if (step < total) bodies.advance(u, dt, step, timers);
    }
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    int code = 0;
    try {
        code = run(argc, argv);
    } catch (const std::exception& e) {
        int rank = 0;
        MPI_Comm_rank(MPI_COMM_WORLD, &rank);
        if (rank == 0) fmt::print(stderr, "efsi_tank_treading_study: {}\n", e.what());
        code = 1;
    }
    MPI_Finalize();
    return code;
}
