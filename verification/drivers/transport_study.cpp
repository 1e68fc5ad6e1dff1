// efsi_transport_study: upper-convected transport of B and Gs in a steady linear flow
// v = A x, for which the deformation gradient is F(t) = exp(A t) everywhere, so
//   B(x, t)  = F F^T                                  (uniform; starts at I)
//   Gs(x, t) = F (I - n_R n_R) F^T,  n_R = (X - c0)/|X - c0|,  X = exp(-A t) x,
// the projection on the sphere of centre c0 through the material point. A is traceless
// (solenoidal flow): "shear" A = [[0,1,0],[0,0,0],[0,0,0]] (F = I + A t exactly), or
// "extension" A = diag(1, -1/2, -1/2) (2D: diag(1, -1)), or "rotation" about z,
// A = [[0,-1,0],[1,0,0],[0,0,0]] (F = R(t), a rigid rotation: Gs stays the projection on the
// rotated sphere and carries no strain, so any J(Gs) != 1 is spurious; this is what the
// membrane's tank-treading asks of the transport). The sphere (radius R) translates
// and deforms with the flow; errors are measured in the shell R/2 < |X - c0| < 3R/2.
// Prints one JSON object: L2 and max errors of B and Gs (relative to |T|), the rms error of
// the surface area ratio J(Gs) = sqrt(II(Gs)) on the shell, steps, seconds.
#include "bodies/body.hpp"
#include "bodies/transport.hpp"
#include "boundary/boundary.hpp"
#include "core/matrix3.hpp"
#include "linear/structured_solver.hpp"
#include "membrane/kinematics.hpp"
#include "parallel/decomposition.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <mpi.h>

#include <chrono>
#include <cmath>

using namespace efsi;

namespace {

enum class Flow { Shear, Extension, Rotation };

/// exp(A t) for the three flows (nilpotent, diagonal, or the generator of z rotations).
Matrix3 flow_map(const Matrix3& A, real t, Flow flow) {
    if (flow == Flow::Rotation)
        return {{{std::cos(t), -std::sin(t), 0}, {std::sin(t), std::cos(t), 0}, {0, 0, 1}}};
    Matrix3 F{};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            F[a][b] = flow == Flow::Shear ? (a == b ? 1.0 : 0.0) + A[a][b] * t
                                          : (a == b ? std::exp(A[a][a] * t) : 0.0);
    return F;
}

/// Area ratio J = sqrt(II) of a surface tensor (Gs has a zero eigenvalue).
real area_ratio(const Matrix3& G) {
    return std::sqrt(std::max(second_invariant(G), 0.0));
}

/// Exact Gs (or B when `projection` is false) at lab point x, time t.
Matrix3 exact(const Matrix3& A, Flow flow, const Real3& c0, const Real3& x, real t, bool projection,
              int dim) {
    const Matrix3 F = flow_map(A, t, flow);
    const Matrix3 Finv = flow_map(A, -t, flow);
    const Real3 X = mat_vec(Finv, x);
    Real3 n{};
    real len = 0;
    for (int d = 0; d < dim; ++d) {
        n[d] = X[d] - c0[d];
        len += n[d] * n[d];
    }
    len = std::sqrt(len);
    Matrix3 P{};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            P[a][b] = (a == b ? 1.0 : 0.0) - (projection ? n[a] * n[b] / (len * len) : 0.0);
    Matrix3 G{};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            for (int c = 0; c < 3; ++c)
                for (int e = 0; e < 3; ++e)
                    G[a][b] += F[a][c] * P[c][e] * F[b][e];
    return G;
}

} // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    int code = 0;
    {
        LinearAlgebraScope scope;
        CLI::App app{"Upper-convected tensor transport in a steady linear flow (verification)"};
        std::string flow = "shear";
        int cells = 32, dim = 3;
        real end_time = 0.5, cfl = 0.4;
        app.add_option("--flow", flow, "shear, extension or rotation")
            ->check(CLI::IsMember({"shear", "extension", "rotation"}));
        app.add_option("--cells", cells, "cells across the box [-1,1]^dim");
        app.add_option("--dim", dim, "2 or 3")->check(CLI::IsMember({2, 3}));
        app.add_option("--time", end_time, "end time (shear-rate units)");
        app.add_option("--cfl", cfl, "dt = cfl * h / max|v|");
        CLI11_PARSE(app, argc, argv);
        const Flow kind = flow == "shear"       ? Flow::Shear
                          : flow == "extension" ? Flow::Extension
                                                : Flow::Rotation;

        GlobalGrid g;
        g.dim = dim;
        g.cells = {cells, cells, dim == 3 ? cells : 1};
        g.length = {2, 2, dim == 3 ? 2.0 : 2.0 / cells};
        g.origin = {-1, -1, dim == 3 ? -1.0 : -1.0 / cells};
        BoxBoundaries bc{};
        for (int d = 0; d < dim; ++d)
            bc[d][0].type = bc[d][1].type = BoundaryType::Wall;
        Decomposition dec(MPI_COMM_WORLD, g, periodic_directions(bc));
        HaloFiller halos(dec, bc);

        Matrix3 A{};
        if (kind == Flow::Shear)
            A[0][1] = 1;
        else if (kind == Flow::Rotation)
            A = {{{0, -1, 0}, {1, 0, 0}, {0, 0, 0}}};
        else if (dim == 3)
            A = {{{1, 0, 0}, {0, -0.5, 0}, {0, 0, -0.5}}};
        else
            A = {{{1, 0, 0}, {0, -1, 0}, {0, 0, 0}}};
        const Real3 c0{0.15, 0.1, 0.0};
        const real R = 0.3;

        // Face velocity v = A x everywhere, halos included (no flow solve).
        VelocityField u("velocity", dec.block(), dim);
        for (int c = 0; c < dim; ++c) {
            const Int3 h = u[c].halo();
            const Int3 n = u[c].cells();
            for_each_in(Box{{-h[0], -h[1], -h[2]}, {n[0] + h[0], n[1] + h[1], n[2] + h[2]}},
                        [&](int i, int j, int k) {
                            const Real3 x = position(g, dec.block(), face_location(c), i, j, k);
                            u[c](i, j, k) = mat_vec(A, x)[c];
                        });
        }
        // Two bodies on the whole box: a "solid" carrying B and a "membrane" carrying Gs.
        const Patch patch = make_patch(Box{{0, 0, 0}, g.cells}, dec);
        Body solid("solid", BodyKind::Solid, false, dim),
            membrane("capsule", BodyKind::Membrane, false, dim);
        solid.allocate(patch);
        membrane.allocate(patch);
        for_each_in(patch.local, [&](int i, int j, int k) {
            const Real3 x = position(g, dec.block(), Location::Cell, i, j, k);
            const Matrix3 G0 = exact(A, kind, c0, x, 0.0, true, dim);
            for (int a = 0; a < 3; ++a)
                for (int b = a; b < 3; ++b) {
                    const int s = SymmetricTensorField::slot(a, b, dim);
                    if (s >= 0) membrane.tensor().comp[s](i, j, k) = G0[a][b];
                }
        });
        BodyTransport transport(halos);
        real vmax = 0;
        for (int d = 0; d < dim; ++d) {
            real row = 0;
            for (int e = 0; e < dim; ++e)
                row += std::abs(A[d][e]);
            vmax = std::max(vmax, row);
        }
        const real h = g.dx(0);
        const int steps = int(std::ceil(end_time / (cfl * h / vmax)));
        const real dt = end_time / steps;
        const auto t0 = std::chrono::steady_clock::now();
        for (int n = 0; n < steps; ++n) {
            run_now(transport.advance(solid, u, dt), halos);
            run_now(transport.advance(membrane, u, dt), halos);
        }
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

        // Errors over the material shell R/2 < |X - c0| < 3R/2.
        real e2[2] = {0, 0}, emax[2] = {0, 0}, norm2[2] = {0, 0}, j2 = 0;
        std::int64_t count = 0;
        const Matrix3 Finv = flow_map(A, -end_time, kind);
        for_each_in(patch.local, [&](int i, int j, int k) {
            const Real3 x = position(g, dec.block(), Location::Cell, i, j, k);
            const Real3 X = mat_vec(Finv, x);
            real r = 0;
            for (int d = 0; d < dim; ++d)
                r += (X[d] - c0[d]) * (X[d] - c0[d]);
            r = std::sqrt(r);
            if (r < 0.5 * R || r > 1.5 * R) return;
            ++count;
            const Body* bodies[2] = {&solid, &membrane};
            for (int m = 0; m < 2; ++m) {
                const Matrix3 E = exact(A, kind, c0, x, end_time, m == 1, dim);
                Matrix3 T{};
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b) {
                        T[a][b] = bodies[m]->tensor().value(a, b, {i, j, k});
                        const real diff = T[a][b] - E[a][b];
                        e2[m] += diff * diff;
                        norm2[m] += E[a][b] * E[a][b];
                        emax[m] = std::max(emax[m], std::abs(diff));
                    }
                if (m == 1) j2 += std::pow(area_ratio(T) - area_ratio(E), 2);
            }
        });
        count = dec.sum(count);
        for (int m = 0; m < 2; ++m) {
            e2[m] = dec.sum(e2[m]);
            norm2[m] = dec.sum(norm2[m]);
            emax[m] = dec.max(emax[m]);
        }
        j2 = dec.sum(j2);
        if (dec.rank() == 0)
            fmt::print(
                "{{\"flow\": \"{}\", \"dim\": {}, \"cells\": {}, \"steps\": {}, \"dt\": {:.6e}, "
                "\"B_error_L2\": {:.6e}, \"B_error_max\": {:.6e}, \"Gs_error_L2\": {:.6e}, "
                "\"Gs_error_max\": {:.6e}, \"J_error_rms\": {:.6e}, \"shell_cells\": {}, "
                "\"seconds\": {:.4f}, "
                "\"bytes_per_body\": {}, \"ranks\": {}}}\n",
                flow, dim, cells, steps, dt, std::sqrt(e2[0] / norm2[0]), emax[0],
                std::sqrt(e2[1] / norm2[1]), emax[1], std::sqrt(j2 / double(count)), count, seconds,
                membrane.bytes(), dec.size());
    }
    MPI_Finalize();
    return code;
}
