// efsi_membrane_force_study: the membrane force |grad phi| f on prescribed shapes.
//
// A reference sphere (3D) or circle (2D, a cylinder surface) of radius R0 and centre c is
// moved by a linear map x = c + A X: `--map inflate` is A = s I (uniform stretch s, the
// exact load is normal, 2T/R in 3D and T1/R in 2D, R = s R0), `--map linear` a general
// orientation-preserving A (an ellipsoid with sheared material lines). On the grid:
//   phi = (1 - tanh(L / eps)) / 2,  L = r_g (|A^-1 (x - c)| / R0 - 1),  r_g = R0 det(A)^(1/dim)
// (level sets of L are the images of concentric spheres, so the normal of phi is the
// normal of that image), and Gs = A P_R A^T, P_R = I - n_R n_R, n_R = A^-1(x - c)/|...|:
// the Gs that transport by the flow x -> A x gives, exact in the whole band.
//
// Measure (weak, local, exact): for smooth bumps w_m = exp(-|x - x_m|^2 / l^2) centred on
// surface points x_m = c + A R0 d_m, the force seen by the flow,
//   N_m = sum over faces of F_d w_m dV            (what the momentum equation receives),
// against the exact load integrated against w_m, by virtual work on the exact surface,
//   E_m = int_S f w_m dA = - int_S tau_s : grad_s(w_m e_d) dA = - int_S tau_s.grad w_m dA,
// computed by Gauss-Legendre x trapezoid quadrature on the reference sphere
// (dA = J dA_R, J the area ratio from the law's kinematics). No second derivatives of the
// geometry are needed, and it holds for any map. The error is
//   || N - E || / || E ||  over all bumps and components.
// For `inflate` the normal and tangential parts against the centre normals are reported.
//
// Bending (`--bending Eb`, usually with `--es 0`): the body carries kappa_R, set to
// `--kappa-r reference` (the reference sphere's concentric level sets carried by the map,
// 1/|A^-1 (x - c)|, 1/R0 on the surface: what transport from the initial shape gives),
// `current` (the curvature of the current level set through x: the shape's own) or a
// number (uniform). The exact bending load has no closed form on a deformed shape, so the
// driver prints the bump integrals N_m and the bump centres ("bumps", "numeric"), and the
// study (verification/studies/membrane_bending.py) compares them with the same integrals
// of the load computed independently on a fine spectral parametrisation of the surface.
// Prints one JSON object. `--write DIR` also writes the fields through the solver's field
// output (DIR/fields/fields.xdmf, readable with meshio): the force density |grad phi| f
// [N/m^3] in the `velocity` slot (cell-centred average of the faces; the raw face values
// in `faces_u/v/w` of the .h5), pressure 0, `phi_capsule` and the Gs components (used by
// the cross-code comparison with the FE surface load, verification/studies/cross_code.py).
#include "bodies/body.hpp"
#include "boundary/boundary.hpp"
#include "core/error.hpp"
#include "core/matrix3.hpp"
#include "io/field_output.hpp"
#include "linear/structured_solver.hpp"
#include "membrane/membrane_force.hpp"
#include "parallel/decomposition.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <mpi.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <vector>

using namespace efsi;

namespace {

/// Gs = A P_R A^T for the reference unit normal nR (P_R = I - nR nR; in 2D nR_z = 0, so
/// P_R keeps zz = 1: the cylinder's generators are unstretched).
Matrix3 surface_tensor(const Matrix3& A, const Real3& nR) {
    Matrix3 G{};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            for (int c = 0; c < 3; ++c)
                for (int e = 0; e < 3; ++e)
                    G[a][b] += A[a][c] * ((c == e ? 1.0 : 0.0) - nR[c] * nR[e]) * A[b][e];
    return G;
}

/// Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n).
void gauss_legendre(int n, std::vector<real>& x, std::vector<real>& w) {
    x.resize(n);
    w.resize(n);
    for (int i = 0; i < n; ++i) {
        real z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 0;
        for (int it = 0; it < 100; ++it) {
            real p0 = 1, p1 = z;
            for (int k = 2; k <= n; ++k) {
                const real p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1);
            const real dz = p1 / dp;
            z -= dz;
            if (std::abs(dz) < 1e-16) break;
        }
        x[i] = z;
        w[i] = 2 / ((1 - z * z) * dp * dp);
    }
}

/// A point of the exact deformed surface with its quadrature weight (dA_R) and the unit
/// reference normal.
struct SurfacePoint {
    Real3 nR;
    real weight;
};

std::vector<SurfacePoint> reference_quadrature(int dim, real R0) {
    std::vector<SurfacePoint> pts;
    const real pi = std::numbers::pi;
    if (dim == 2) {
        const int n = 4096;
        for (int i = 0; i < n; ++i) {
            const real t = 2 * pi * i / n;
            pts.push_back({{std::cos(t), std::sin(t), 0}, R0 * 2 * pi / n});
        }
        return pts;
    }
    std::vector<real> mu, wmu;
    gauss_legendre(128, mu, wmu);
    const int nphi = 256;
    for (std::size_t i = 0; i < mu.size(); ++i)
        for (int j = 0; j < nphi; ++j) {
            const real ph = 2 * pi * j / nphi, st = std::sqrt(1 - mu[i] * mu[i]);
            pts.push_back(
                {{st * std::cos(ph), st * std::sin(ph), mu[i]}, R0 * R0 * wmu[i] * 2 * pi / nphi});
        }
    return pts;
}

/// Reference directions of the bump centres: the 26 lattice directions in 3D, 16 angles
/// in 2D.
std::vector<Real3> bump_directions(int dim) {
    std::vector<Real3> dirs;
    if (dim == 2) {
        for (int m = 0; m < 16; ++m) {
            const real t = 0.1 + 2 * std::numbers::pi * m / 16;
            dirs.push_back({std::cos(t), std::sin(t), 0});
        }
        return dirs;
    }
    for (int a = -1; a <= 1; ++a)
        for (int b = -1; b <= 1; ++b)
            for (int c = -1; c <= 1; ++c) {
                if (a == 0 && b == 0 && c == 0) continue;
                const real len = std::sqrt(real(a * a + b * b + c * c));
                dirs.push_back({a / len, b / len, c / len});
            }
    return dirs;
}

} // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    {
        LinearAlgebraScope scope;
        CLI::App app{"Membrane force on prescribed shapes (verification)"};
        std::string map = "inflate", law_name = "neo_hookean", stencil = "distance", write_dir;
        int cells = 32, dim = 3, grid_multiple = 1;
        std::string kappa_r = "reference", kernel = "cosine";
        real stretch = 1.2, alpha = 1, width = 1.0, Es = 1.0, Eb = 0, bending_width = 2.0;
        app.add_option("--map", map, "inflate (A = s I) or linear (a fixed general A)")
            ->check(CLI::IsMember({"inflate", "linear", "identity"}));
        app.add_option("--cells", cells, "cells across the reference diameter 2 R0");
        app.add_option("--dim", dim, "2 or 3")->check(CLI::IsMember({2, 3}));
        app.add_option("--stretch", stretch, "s of the inflation map");
        app.add_option("--law", law_name, "neo_hookean or skalak");
        app.add_option("--alpha", alpha, "Skalak's C");
        app.add_option("--width", width, "smoothing width eps in cells");
        app.add_option("--stencil", stencil, "normal stencil (distance, isotropic, ...)");
        app.add_option("--es", Es, "elastic modulus Es (0: bending only)");
        app.add_option("--bending", Eb, "bending modulus Eb (0: no bending)");
        app.add_option("--kappa-r", kappa_r, "reference, current, or a number");
        app.add_option("--kernel", kernel, "bending kernel: cosine or profile")
            ->check(CLI::IsMember({"cosine", "profile"}));
        app.add_option("--bending-width", bending_width, "cosine kernel half-width in cells");
        app.add_option("--grid-multiple", grid_multiple,
                       "round the cell count per direction up to a multiple of this (for ranks)");
        app.add_option("--write", write_dir, "also write force, phi and Gs to DIR/fields");
        bool normal_bumps = false;
        app.add_flag("--normal-bumps", normal_bumps,
                     "inflate: weigh the band's force by the bump at each point's radial "
                     "projection on the sphere (constant along the normals), so that the "
                     "measure adds no bias of its own from the band's width");
        CLI11_PARSE(app, argc, argv);
        if (normal_bumps && map != "inflate")
            throw InputError("--normal-bumps needs --map inflate (a sphere)");
        const auto law = make_membrane_law(law_name, Es, alpha);

        // The map.
        Matrix3 A{};
        for (int a = 0; a < 3; ++a)
            A[a][a] = map == "inflate" ? stretch : 1.0;
        if (dim == 2) A[2][2] = 1;
        if (map == "linear") {
            if (dim == 3)
                A = {{{1.15, 0.12, 0.0}, {-0.05, 0.9, 0.08}, {0.03, 0.0, 1.05}}};
            else
                A = {{{1.15, 0.12, 0.0}, {-0.05, 0.9, 0.0}, {0.0, 0.0, 1.0}}};
        }
        const Matrix3 Ainv = inverse(A), AinvT = transpose(Ainv);
        const real R0 = 0.5;
        const real rg =
            R0 *
            std::pow(dim == 3 ? determinant(A) : A[0][0] * A[1][1] - A[0][1] * A[1][0], 1.0 / dim);
        const Real3 c{0.013, 0.027, dim == 3 ? 0.041 : 0.0};

        // Grid: h = 2 R0 / cells, box around the deformed shape plus 12 cells.
        const real h = 2 * R0 / cells;
        real amax = 0; // a bound on |A X| / R0 (Frobenius norm)
        for (int a = 0; a < dim; ++a)
            for (int b = 0; b < dim; ++b)
                amax += A[a][b] * A[a][b];
        const real half = 0.05 + std::sqrt(amax) * R0 + 12 * h;
        int n = int(std::ceil(2 * half / h));
        n = (n + grid_multiple - 1) / grid_multiple * grid_multiple; // divisible among ranks
        GlobalGrid g;
        g.dim = dim;
        g.cells = {n, n, dim == 3 ? n : 1};
        g.length = {n * h, n * h, dim == 3 ? n * h : h};
        g.origin = {-0.5 * n * h, -0.5 * n * h, dim == 3 ? -0.5 * n * h : -0.5 * h};
        BoxBoundaries bc{};
        for (int d = 0; d < dim; ++d)
            bc[d][0].type = bc[d][1].type = BoundaryType::Wall;
        Decomposition dec(MPI_COMM_WORLD, g, periodic_directions(bc));
        HaloFiller halos(dec, bc);
        const real eps = width * h;

        // The body on the whole grid: smoothed phi (tail cut like the body system's) and
        // the exact Gs.
        const Patch patch = make_patch(Box{{0, 0, 0}, g.cells}, dec);
        Body body("capsule", BodyKind::Membrane, Eb > 0, dim);
        body.allocate(patch);
        for_each_in(patch.local, [&](int i, int j, int k) {
            const Real3 x = position(g, dec.block(), Location::Cell, i, j, k);
            Real3 y{};
            for (int d = 0; d < dim; ++d)
                y[d] = x[d] - c[d];
            Real3 X = mat_vec(Ainv, y);
            const real len = std::sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
            const real v = 0.5 * (1 - std::tanh(rg * (len / R0 - 1) / eps));
            body.phi()(i, j, k) = v < 1e-8 ? 0.0 : v;
            if (Eb > 0) {
                real kr = 0;
                if (kappa_r == "reference") {
                    kr = 1 / len;
                } else if (kappa_r == "current") {
                    // L = (rg / R0) |X|, X = A^-1 y: grad L = (rg/R0) A^-T X/|X|,
                    // H = (rg/R0) A^-T (I - X X/|X|^2) A^-1 / |X|.
                    Matrix3 M{};
                    for (int a = 0; a < 3; ++a)
                        for (int b = 0; b < 3; ++b)
                            M[a][b] = (a == b ? 1.0 : 0.0) - X[a] * X[b] / (len * len);
                    Matrix3 H{};
                    for (int a = 0; a < 3; ++a)
                        for (int b = 0; b < 3; ++b)
                            for (int e = 0; e < 3; ++e)
                                for (int f = 0; f < 3; ++f)
                                    H[a][b] += AinvT[a][e] * M[e][f] * Ainv[f][b] / len;
                    const Real3 grad = mat_vec(AinvT, {X[0] / len, X[1] / len, X[2] / len});
                    kr = level_set_curvature(H, grad, dim);
                } else {
                    kr = std::stod(kappa_r);
                }
                (*body.reference_curvature())(i, j, k) = kr;
            }
            for (real& comp : X)
                comp /= len;
            const Matrix3 G = surface_tensor(A, X);
            for (int a = 0; a < 3; ++a)
                for (int b = a; b < 3; ++b) {
                    const int s = SymmetricTensorField::slot(a, b, dim);
                    if (s >= 0) body.tensor().comp[s](i, j, k) = G[a][b];
                }
        });

        VelocityField force("membrane_force", dec.block(), dim);
        for (int d = 0; d < dim; ++d)
            force[d].fill(0);
        MembraneForceSettings settings;
        settings.stencil = gradient_stencil_from_string(stencil);
        settings.smoothing_width = width;
        settings.bending_modulus = Eb;
        settings.bending_width = bending_width;
        settings.bending_kernel = kernel == "cosine"
                                      ? MembraneForceSettings::BendingKernel::Cosine
                                      : MembraneForceSettings::BendingKernel::Profile;
        MembraneForce membrane(g, halos, settings);
        const auto t0 = std::chrono::steady_clock::now();
        membrane.add(body, *law, force);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (!write_dir.empty()) { // the force in the velocity slot of a snapshot
            FlowState state(dec.block(), dim);
            for (int d = 0; d < dim; ++d)
                state.u[d] = force[d];
            state.p.fill(0);
            FieldOutput(write_dir, dec).write(state, {&body});
        }

        // Bumps: numerical N_m (faces) and exact E_m (virtual work on the exact surface).
        const std::vector<Real3> dirs = bump_directions(dim);
        const std::size_t nb = dirs.size();
        const real ell = 0.35 * R0;
        std::vector<Real3> centres(nb);
        for (std::size_t m = 0; m < nb; ++m) {
            centres[m] = mat_vec(A, dirs[m]);
            for (int d = 0; d < 3; ++d)
                centres[m][d] = c[d] + R0 * centres[m][d];
        }
        auto bump = [&](std::size_t m, const Real3& x) {
            real r2 = 0;
            for (int d = 0; d < dim; ++d)
                r2 += (x[d] - centres[m][d]) * (x[d] - centres[m][d]);
            return std::exp(-r2 / (ell * ell));
        };
        const real dV = dim == 3 ? h * h * h : h * h; // 2D: per unit length along z
        std::vector<real> num(3 * nb, 0.0);
        Real3 net{0, 0, 0};
        real total_abs = 0;
        for (int d = 0; d < dim; ++d)
            for_each_in(patch.local, [&](int i, int j, int k) {
                const real F = force[d](i, j, k);
                if (F == 0) return;
                net[d] += F * dV;
                total_abs += std::abs(F) * dV;
                Real3 x = position(g, dec.block(), face_location(d), i, j, k);
                if (normal_bumps) {
                    // The radial projection on the inflated sphere (radius s R0 about c).
                    real r = 0;
                    for (int e = 0; e < dim; ++e)
                        r += (x[e] - c[e]) * (x[e] - c[e]);
                    r = std::sqrt(r);
                    for (int e = 0; e < dim; ++e)
                        x[e] = c[e] + stretch * R0 * (x[e] - c[e]) / r;
                }
                for (std::size_t m = 0; m < nb; ++m)
                    num[3 * m + d] += F * bump(m, x) * dV;
            });
        for (real& v : num)
            v = dec.sum(v);
        for (real& v : net)
            v = dec.sum(v);
        total_abs = dec.sum(total_abs);

        std::vector<real> ex(3 * nb, 0.0), ex_closed(3 * nb, 0.0);
        // Closed form for the inflation map: q = -(k T / R) n_out, k = 2 (3D) or 1 (2D).
        const real R = stretch * R0;
        real T = 0;
        {
            const Matrix3 G = surface_tensor(A, {1, 0, 0});
            const Matrix3 tau = law->tension(membrane_kinematics({1, 0, 0}, G));
            T = tau[1][1]; // the in-plane tension along the y tangent at the x pole
        }
        for (const SurfacePoint& sp : reference_quadrature(dim, R0)) {
            Real3 x = mat_vec(A, sp.nR);
            for (int d = 0; d < 3; ++d)
                x[d] = c[d] + R0 * x[d];
            Real3 nn = mat_vec(AinvT, sp.nR); // normals map with A^-T
            const real len = std::sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
            for (real& v : nn)
                v /= len;
            const MembraneKinematics kin = membrane_kinematics(nn, surface_tensor(A, sp.nR));
            const Matrix3 tau = law->tension(kin);
            const real dA = kin.J * sp.weight;
            for (std::size_t m = 0; m < nb; ++m) {
                const real w = bump(m, x);
                Real3 gw{};
                for (int d = 0; d < dim; ++d)
                    gw[d] = -2 * (x[d] - centres[m][d]) / (ell * ell) * w;
                for (int d = 0; d < dim; ++d) {
                    real s = 0;
                    for (int k = 0; k < dim; ++k)
                        s += tau[d][k] * gw[k];
                    ex[3 * m + d] -= s * dA;
                    ex_closed[3 * m + d] -= (dim == 3 ? 2 : 1) * T / R * nn[d] * w * dA;
                }
            }
        }
        real e2 = 0, n2 = 0, quad_check = 0, nerr = 0, nref = 0, tang = 0, nsum = 0, esum = 0;
        for (std::size_t m = 0; m < nb; ++m) {
            real dn = 0, en = 0;
            for (int d = 0; d < dim; ++d) {
                e2 += (num[3 * m + d] - ex[3 * m + d]) * (num[3 * m + d] - ex[3 * m + d]);
                n2 += ex[3 * m + d] * ex[3 * m + d];
                quad_check = std::max(quad_check, std::abs(ex[3 * m + d] - ex_closed[3 * m + d]));
                dn -= num[3 * m + d] * dirs[m][d]; // inward normal part at the centre
                en -= ex[3 * m + d] * dirs[m][d];
            }
            real t2 = 0;
            for (int d = 0; d < dim; ++d) {
                const real t = num[3 * m + d] + dn * dirs[m][d];
                t2 += t * t;
            }
            nerr += (dn - en) * (dn - en);
            nsum += dn;
            esum += en;
            nref += en * en;
            tang += std::sqrt(t2);
        }
        real ex_scale = 0;
        for (real v : ex)
            ex_scale = std::max(ex_scale, std::abs(v));
        const std::size_t band = dec.sum(static_cast<std::int64_t>(membrane.band_cells()));
        const std::size_t bcells = dec.sum(static_cast<std::int64_t>(membrane.bending_cells()));
        const std::size_t bdrop = dec.sum(static_cast<std::int64_t>(membrane.bending_dropped()));
        std::string bumps = "[", numeric = "[";
        for (std::size_t m = 0; m < nb; ++m) {
            const char* sep = m + 1 < nb ? ", " : "";
            bumps += fmt::format("[{:.17g}, {:.17g}, {:.17g}]{}", centres[m][0], centres[m][1],
                                 centres[m][2], sep);
            numeric += fmt::format("[{:.17g}, {:.17g}, {:.17g}]{}", num[3 * m], num[3 * m + 1],
                                   num[3 * m + 2], sep);
        }
        bumps += "]";
        numeric += "]";
        auto ratio = [](real a, real b) { return b > 0 ? a / b : 0.0; };
        if (dec.rank() == 0)
            fmt::print(
                "{{\"map\": \"{}\", \"law\": \"{}\", \"dim\": {}, \"cells\": {}, \"grid\": {}, "
                "\"width\": {}, \"stencil\": \"{}\", \"force_error\": {:.6e}, "
                "\"normal_error\": {:.6e}, \"normal_bias\": {:.6e}, \"tangential_ratio\": {:.6e}, "
                "\"net_force_ratio\": {:.3e}, \"exact_load\": {:.10g}, "
                "\"quadrature_vs_closed_form\": {:.3e}, \"band_cells\": {}, "
                "\"seconds\": {:.4f}, \"ranks\": {}, \"es\": {}, \"bending\": {}, "
                "\"kappa_r\": \"{}\", \"kernel\": \"{}\", \"bending_width\": {}, "
                "\"bending_cells\": {}, \"bending_dropped\": {}, \"R0\": {}, "
                "\"centre\": [{:.17g}, {:.17g}, {:.17g}], \"bump_width\": {:.17g}, "
                "\"A\": [[{:.17g}, {:.17g}, {:.17g}], [{:.17g}, {:.17g}, {:.17g}], "
                "[{:.17g}, {:.17g}, {:.17g}]], \"bumps\": {}, \"numeric\": {}}}\n",
                map, law_name, dim, cells, n, width, stencil, std::sqrt(ratio(e2, n2)),
                std::sqrt(ratio(nerr, nref)), esum != 0 ? nsum / esum - 1 : 0.0,
                ratio(tang, nb * std::sqrt(nref / nb)),
                ratio(std::sqrt(net[0] * net[0] + net[1] * net[1] + net[2] * net[2]), total_abs),
                (dim == 3 ? 2 : 1) * T / R, map == "inflate" ? ratio(quad_check, ex_scale) : 0.0,
                band, seconds, dec.size(), Es, Eb, kappa_r, kernel, bending_width, bcells, bdrop,
                R0, c[0], c[1], c[2], ell, A[0][0], A[0][1], A[0][2], A[1][0], A[1][1], A[1][2],
                A[2][0], A[2][1], A[2][2], bumps, numeric);
    }
    MPI_Finalize();
    return 0;
}
