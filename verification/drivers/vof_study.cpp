// efsi_vof_study: prescribed-velocity VOF advection tests, one run per call, JSON out.
//
// Tests (unit box, periodic halos; phi is zero near the box faces in all of them):
//   zalesak        2D slotted disc (R 0.15 at (0.5, 0.75), slot 0.05 x 0.25) in rigid
//                  rotation about (0.5, 0.5), omega = 2 pi, one revolution T = 1;
//                  psi = -(omega/2) |x - (1/2, 1/2)|^2.
//   single_vortex  2D disc R 0.15 at (0.5, 0.75), psi = -(1/pi) sin^2(pi x) sin^2(pi y)
//                  cos(pi t / T), T = 8 (Rider & Kothe; the flow reverses at T/2).
//   deformation3d  sphere R 0.15 at (0.35, 0.35, 0.35), LeVeque's field
//                  u = (2 sin^2(pi x) sin(2 pi y) sin(2 pi z), -sin(2 pi x) sin^2(pi y)
//                  sin(2 pi z), -sin(2 pi x) sin(2 pi y) sin^2(pi z)) cos(pi t / T), T = 3,
//                  written as u = curl A with A = (0, -psi_2, psi_1),
//                  psi_1 = sin^2(pi x) sin^2(pi y) sin(2 pi z) / pi,
//                  psi_2 = sin^2(pi x) sin(2 pi y) sin^2(pi z) / pi.
// Face velocities come from the vector potential (discretely solenoidal) at mid-step
// t + dt/2. The shape error is E = sum |phi(T) - phi(0)| dV with dV the cell area in 2D
// and volume in 3D.
#include "boundary/boundary.hpp"
#include "core/error.hpp"
#include "interface/prescribed_velocity.hpp"
#include "interface/shapes.hpp"
#include "interface/vof_advection.hpp"
#include "io/hdf5_file.hpp"
#include "parallel/decomposition.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <mpi.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <numbers>

using namespace efsi;

namespace {

constexpr real pi = std::numbers::pi;

struct TestCase {
    int dim = 2;
    real period = 1;
    std::function<std::unique_ptr<Shape>()> shape;
    std::function<Real3(const Real3&)> potential;                     ///< A(x) at t = 0
    std::function<real(real)> time_factor = [](real) { return 1.0; }; ///< A(x,t) = A(x) g(t)
};

TestCase make_case(const std::string& name) {
    TestCase c;
    if (name == "zalesak") {
        c.dim = 2;
        c.period = 1;
        c.shape = [] {
            return make_difference(make_cylinder({0.5, 0.75, 0}, 0.15),
                                   make_box({0.5, 0.70, 0}, {0.025, 0.15, 1.0}));
        };
        c.potential = [](const Real3& x) {
            const real dx = x[0] - 0.5, dy = x[1] - 0.5;
            return Real3{0, 0, -pi * (dx * dx + dy * dy)};
        };
    } else if (name == "single_vortex") {
        c.dim = 2;
        c.period = 8;
        c.shape = [] { return make_cylinder({0.5, 0.75, 0}, 0.15); };
        c.potential = [](const Real3& x) {
            const real sx = std::sin(pi * x[0]), sy = std::sin(pi * x[1]);
            return Real3{0, 0, -sx * sx * sy * sy / pi};
        };
        c.time_factor = [T = c.period](real t) { return std::cos(pi * t / T); };
    } else if (name == "deformation3d") {
        c.dim = 3;
        c.period = 3;
        c.shape = [] { return make_sphere({0.35, 0.35, 0.35}, 0.15); };
        c.potential = [](const Real3& x) {
            const real sx = std::sin(pi * x[0]), sy = std::sin(pi * x[1]), sz = std::sin(pi * x[2]);
            const real g = 1 / pi;
            const real psi1 = sx * sx * sy * sy * std::sin(2 * pi * x[2]) * g;
            const real psi2 = sx * sx * std::sin(2 * pi * x[1]) * sz * sz * g;
            return Real3{0, -psi2, psi1};
        };
        c.time_factor = [T = c.period](real t) { return std::cos(pi * t / T); };
    } else {
        throw InputError(fmt::format(
            "unknown test '{}' (expected zalesak, single_vortex or deformation3d)", name));
    }
    return c;
}

real abs_max_velocity(const Decomposition& dec, const VelocityField& u) {
    real m = 0;
    for (int d = 0; d < u.dim; ++d)
        for_each_cell(dec.block().cells,
                      [&](int i, int j, int k) { m = std::max(m, std::abs(u[d](i, j, k))); });
    return dec.max(m);
}

int run(int argc, char** argv) {
    CLI::App app{"efsi_vof_study: prescribed-velocity VOF advection tests (JSON on stdout)"};
    std::string test = "single_vortex", scheme = "mthinc", h5;
    int n = 64, subsamples = 8;
    real cfl = 0.3, beta_thinc = 3.5, beta_mthinc = 2.0;
    app.add_option("test", test, "zalesak | single_vortex | deformation3d")->required();
    app.add_option("--n", n, "cells across the unit box");
    app.add_option("--scheme", scheme, "thinc | mthinc");
    app.add_option("--cfl", cfl, "max |u| dt / dx (< 1/2)");
    app.add_option("--beta-thinc", beta_thinc, "1D THINC sharpness");
    app.add_option("--beta-mthinc", beta_mthinc, "MTHINC sharpness");
    app.add_option("--subsamples", subsamples, "sub-samples per direction for phi(0)");
    app.add_option("--h5", h5, "write phi0 and phiT to this HDF5 file");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }

    const TestCase tc = make_case(test);
    GlobalGrid grid;
    grid.dim = tc.dim;
    grid.cells = {n, n, tc.dim == 3 ? n : 1};
    grid.length = {1, 1, tc.dim == 3 ? 1.0 : 1.0 / n};
    Decomposition dec(MPI_COMM_WORLD, grid, {true, true, true});
    BoxBoundaries bc{}; // all periodic
    HaloFiller halos(dec, bc);

    VofOptions opt;
    opt.scheme = parse_vof_scheme(scheme);
    opt.beta_thinc = beta_thinc;
    opt.beta_mthinc = beta_mthinc;
    VofAdvection vof(halos, opt);

    Field phi("phi", Location::Cell, dec.block(), grid.dim);
    const auto shape = tc.shape();
    initial_volume_fraction(*shape, grid, dec.block(), phi, subsamples);
    halos.fill(phi);
    const Field phi0 = phi;

    // The time dependence is a factor g(t) (|g| <= 1), so the face velocities are built
    // once at t = 0 and scaled each step: u(t) = g(t) u0.
    VelocityField u0("u0", dec.block(), grid.dim);
    set_velocity_from_potential(u0, grid, dec.block(), tc.potential);
    VelocityField u = u0;
    const real umax = abs_max_velocity(dec, u0);
    const real h = grid.dx(0);
    const auto steps = std::int64_t(std::ceil(tc.period * umax / (cfl * h)));
    const real dt = tc.period / real(steps);

    // Measures are per unit depth in 2D: dV = dx dy.
    const real dv_scale = tc.dim == 3 ? 1.0 : 1.0 / grid.dx(2);
    const real v0 = total_volume(dec, phi) * dv_scale;
    real phi_min = 0, phi_max = 1, clipped = 0, courant = 0, drift = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (std::int64_t s = 0; s < steps; ++s) {
        const real tm = (real(s) + 0.5) * dt;
        const real g = tc.time_factor(tm);
        for (int d = 0; d < grid.dim; ++d)
            for (std::size_t q = 0; q < u0[d].data().size(); ++q)
                u[d].data()[q] = g * u0[d].data()[q];
        const VofStepStats st = vof.advance(phi, u, dt, s);
        phi_min = std::min(phi_min, st.min_before_clip);
        phi_max = std::max(phi_max, st.max_before_clip);
        clipped += st.clipped_volume * dv_scale;
        courant = std::max(courant, st.max_courant);
        drift = std::max(drift, std::abs(total_volume(dec, phi) * dv_scale - v0) / v0);
    }
    const real wall = std::chrono::duration<real>(std::chrono::steady_clock::now() - t0).count();

    real err = 0, fmin = 1, fmax = 0;
    for_each_cell(dec.block().cells, [&](int i, int j, int k) {
        err += std::abs(phi(i, j, k) - phi0(i, j, k));
        fmin = std::min(fmin, phi(i, j, k));
        fmax = std::max(fmax, phi(i, j, k));
    });
    err = dec.sum(err) * grid.cell_volume() * dv_scale;
    const real v1 = total_volume(dec, phi) * dv_scale;

    if (!h5.empty()) {
        Hdf5File f(h5, Hdf5File::Mode::Create, dec);
        f.write_block("phi0", phi0);
        f.write_block("phiT", phi);
        f.write_attribute("n", n);
        f.write_attribute("dim", tc.dim);
    }
    if (dec.rank() == 0)
        std::cout << fmt::format(
                         "{{\"test\": \"{}\", \"scheme\": \"{}\", \"n\": {}, \"ranks\": {}, "
                         "\"steps\": {}, \"dt\": {:.10e}, \"cfl\": {}, \"max_courant\": {:.6e}, "
                         "\"beta\": {}, \"shape_error\": {:.10e}, \"volume0\": {:.16e}, "
                         "\"volume_error\": {:.6e}, \"volume_drift_max\": {:.6e}, "
                         "\"phi_min\": {:.6e}, \"phi_max\": {:.16e}, \"phi_min_final\": {:.6e}, "
                         "\"phi_max_final\": {:.16e}, \"clipped_volume\": {:.6e}, "
                         "\"wall_time\": {:.4f}}}",
                         test, scheme, n, dec.size(), steps, dt, cfl, courant,
                         opt.scheme == VofScheme::Mthinc ? beta_mthinc : beta_thinc, err, v0,
                         std::abs(v1 - v0) / v0, drift, phi_min, phi_max, fmin, fmax, clipped, wall)
                  << std::endl;
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    int code = 0;
    try {
        code = run(argc, argv);
    } catch (const std::exception& e) {
        std::cerr << "efsi_vof_study: " << e.what() << std::endl;
        code = 1;
    }
    MPI_Finalize();
    return code;
}
