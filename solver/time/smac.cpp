#include "time/smac.hpp"

#include "operators/flow_operators.hpp"
#include "operators/flow_sweeps.hpp"

#include <algorithm>
#include <cmath>

namespace efsi {

namespace {

bool on_box_face(const Decomposition& dec, const BoxBoundaries& bc, int e, int side,
                 const Int3& p) {
    return bc[e][side].type != BoundaryType::Periodic && dec.at_boundary(e, side) &&
           p[e] == (side == 0 ? 0 : dec.block().cells[e] - 1);
}

/// fn(j, k) for each owned row; the rows' points are f.data() + f.index(0, j, k) + i.
template <class F>
void for_each_owned_row(const Decomposition& dec, F&& fn) {
    const Int3 n = dec.block().cells;
    for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
            fn(j, k);
}

real* row_of(Field& f, int j, int k) {
    return f.data().data() + f.index(0, j, k);
}
const real* row_of(const Field& f, int j, int k) {
    return f.data().data() + f.index(0, j, k);
}

/// Row by row over raw pointers, in four partial sums (x index modulo 4, then combined
/// pairwise): one running sum makes every add wait on the previous one, and the compiler
/// may not reorder it. The order is fixed, so the value is the same on every run.
real mean_over_block(const Decomposition& dec, const Field& f) {
    real s[4] = {0, 0, 0, 0};
    const int n0 = dec.block().cells[0];
    for_each_owned_row(dec, [&](int j, int k) {
        const real* r = row_of(f, j, k);
        int i = 0;
        for (; i + 4 <= n0; i += 4)
            for (int q = 0; q < 4; ++q)
                s[q] += r[i + q];
        for (; i < n0; ++i)
            s[0] += r[i];
    });
    return dec.sum((s[0] + s[1]) + (s[2] + s[3])) / real(dec.grid().total_cells());
}

/// The hypre settings behind "auto" (and behind "fft" where it cannot apply).
LinearSolverSettings hypre_settings(LinearSolverSettings s) {
    if (s.method == "auto" || s.method == "fft") s.method = "pcg_pfmg";
    return s;
}

} // namespace

SmacStepper::SmacStepper(const Config& config, const Decomposition& dec, HaloFiller& halos)
    : cfg_(config), dec_(dec), halos_(halos),
      theta_(config.time.viscous == ViscousScheme::Explicit        ? 0.0
             : config.time.viscous == ViscousScheme::CrankNicolson ? 0.5
                                                                   : 1.0),
      adv_("advection", dec.block(), dec.dim()),
      ustar_("predicted_velocity", dec.block(), dec.dim()),
      rhs_("rhs", Location::Cell, dec.block(), dec.dim()),
      phi_("pressure_correction", Location::Cell, dec.block(), dec.dim()),
      choice_(choose_linear_solvers(config)) {
    const Bool3 periodic = periodic_directions(config.boundaries);
    if (choice_.pressure_fft || (theta_ > 0 && choice_.viscous_fft))
        fft_workspace_ = make_fft_workspace(dec);
    if (choice_.pressure_fft) {
        // -lap(phi) with zero normal gradient at every wall (DCT-II there).
        std::array<FftDirection, 3> dirs{};
        for (int e = 0; e < 3; ++e)
            dirs[e].periodic = periodic[e];
        pressure_fft_ = std::make_unique<FftSolver>(dec, dirs, fft_workspace_);
        pressure_fft_->set_coefficients(0.0, 1.0);
    } else {
        pressure_ = std::make_unique<StructuredSolver>(dec, periodic,
                                                       hypre_settings(config.pressure_solver));
        // -lap(phi) with zero normal gradient at walls (the ghost equals the interior
        // value, so the coupling and its share of the centre coefficient both drop out).
        const GlobalGrid& g = dec.grid();
        pressure_->set_operator([&](int i, int j, int k) {
            Stencil s;
            const Int3 p{i, j, k};
            for (int e = 0; e < dec.dim(); ++e)
                for (int side = 0; side < 2; ++side) {
                    if (on_box_face(dec, config.boundaries, e, side, p)) continue;
                    const real w = 1.0 / (g.dx(e) * g.dx(e));
                    s.neighbour[e][side] = -w;
                    s.centre += w;
                }
            return s;
        });
    }
    if (theta_ > 0)
        for (int c = 0; c < dec.dim(); ++c) {
            if (choice_.viscous_fft)
                viscous_fft_[c] =
                    std::make_unique<FftSolver>(dec, viscous_directions(c), fft_workspace_);
            else
                hypre_viscous(c);
        }
}

std::array<FftDirection, 3> SmacStepper::viscous_directions(int c) const {
    // The closures of the viscous stencil below: along its own direction, component c
    // lives on faces and the wall faces are fixed (DST-I on the interior faces); across a
    // no-slip wall the ghost is 2U - u (zero value on the wall, U in the right-hand side),
    // across a free-slip wall it is u (zero gradient).
    const auto& bc = cfg_.boundaries;
    std::array<FftDirection, 3> dirs{};
    for (int e = 0; e < 3; ++e) {
        dirs[e].periodic = bc[e][0].type == BoundaryType::Periodic;
        if (dirs[e].periodic) continue;
        dirs[e].wall_faces = e == c;
        auto side = [&](int s) {
            return bc[e][s].type == BoundaryType::Wall ? FftSide::ZeroValue : FftSide::ZeroGradient;
        };
        dirs[e].low = side(0);
        dirs[e].high = side(1);
    }
    return dirs;
}

StructuredSolver& SmacStepper::hypre_viscous(int c) {
    if (!viscous_[c]) {
        viscous_[c] = std::make_unique<StructuredSolver>(dec_, periodic_directions(cfg_.boundaries),
                                                         hypre_settings(cfg_.viscous_solver));
        viscous_dt_ = -1; // a new solver needs its operator
    }
    return *viscous_[c];
}

std::string SmacStepper::solver_summary() const {
    std::string s = "linear solvers: pressure ";
    s += pressure_fft_ ? "FFT direct [" + pressure_fft_->describe() + "]"
                       : "hypre " + pressure_->settings().method;
    s += " (" + choice_.pressure_reason + "); viscous ";
    if (theta_ == 0)
        s += "none (explicit)";
    else if (viscous_fft_[0])
        s += "FFT direct per component (" + choice_.viscous_reason + ")";
    else
        s += "hypre " + viscous_[0]->settings().method + " (" + choice_.viscous_reason + ")";
    return s;
}

SmacStepper::~SmacStepper() = default;

StepReport SmacStepper::step(FlowState& s, real dt, StageTimers& timers,
                             const VelocityField* force) {
    StepReport report;
    timers.time("halo", [&] {
        halos_.set_time(s.time);
        halos_.fill(s.u);
        if (s.viscosity_varies) halos_.fill(s.mu);
    });
    timers.time("advection", [&] { advection(s); });
    timers.time("predictor", [&] { predictor(s, dt, force); });
    halos_.set_time(s.time + dt); // walls at the new time level for the implicit solve on
    if (theta_ > 0) timers.time("viscous_solve", [&] { report.viscous = viscous_solve(s, dt); });
    timers.time("pressure_solve", [&] { report.pressure = pressure_solve(dt); });
    timers.time("correction", [&] { correction(s, dt); });
    // The advective term of this step is the history of the next one.
    std::swap(s.adv_prev, adv_);
    s.dt_prev = dt;
    s.time += dt;
    ++s.step;
    return report;
}

bool SmacStepper::wall_at_low(int d) const {
    return cfg_.boundaries[d][0].type != BoundaryType::Periodic && dec_.at_boundary(d, 0);
}

void SmacStepper::advection(const FlowState& s) {
    const GlobalGrid& g = dec_.grid();
    sweep::for_each_component(s.u.dim, [&]<int C, int Dim>() {
        sweep::require_same_layout(s.u[C], adv_[C]);
        sweep::advection<C, Dim>(s.u, g, adv_[C]);
    });
}

void SmacStepper::predictor(const FlowState& s, real dt, const VelocityField* force) {
    const GlobalGrid& g = dec_.grid();
    const real rho = cfg_.fluid.density;
    // Adams-Bashforth 2 with variable step; forward Euler on the very first step.
    const bool first = s.dt_prev <= 0;
    const real a1 = first ? 1.0 : 1.0 + 0.5 * dt / s.dt_prev;
    const real a0 = first ? 0.0 : -0.5 * dt / s.dt_prev;
    const real explicit_share = 1.0 - theta_;
    if (!s.viscosity_varies && !pinning_) {
        // Uniform viscosity (no bodies that change it, no pinned solids): the fused sweep.
        const real mu0 = s.mu(0, 0, 0);
        sweep::for_each_component(s.u.dim, [&]<int C, int Dim>() {
            const sweep::PredictorCoefficients k{
                a1, a0, dt, 1.0 / rho, cfg_.body_force[C], explicit_share * mu0 / rho};
            sweep::require_same_layout(s.u[C], ustar_[C]);
            sweep::require_same_layout(s.u[C], s.p);
            sweep::predictor<C, Dim>(s.u, s.p, adv_[C], s.adv_prev[C],
                                     force ? &(*force)[C] : nullptr, g, k, wall_at_low(C),
                                     ustar_[C]);
        });
        return;
    }
    if (!s.viscosity_varies) {
        // Pinned solids in a fluid of uniform viscosity: the pointwise form below without its
        // transpose term, as a row sweep (the same values bit for bit).
        sweep::for_each_component(s.u.dim, [&]<int C, int Dim>() {
            const sweep::PredictorFieldCoefficients k{
                a1, a0, dt, rho, cfg_.body_force[C], explicit_share};
            sweep::require_same_layout(s.u[C], ustar_[C]);
            sweep::require_same_layout(s.u[C], s.p);
            sweep::require_same_layout(s.u[C], s.mu);
            if (pinning_) sweep::require_same_layout(s.u[C], (*pinning_)[C]);
            sweep::predictor_viscosity_field<C, Dim>(
                s.u, s.p, s.mu, adv_[C], s.adv_prev[C], force ? &(*force)[C] : nullptr,
                pinning_ ? &(*pinning_)[C] : nullptr, g, k, wall_at_low(C), ustar_[C]);
        });
        return;
    }
    for (int c = 0; c < s.u.dim; ++c)
        for_each_cell(dec_.block().cells, [&](int i, int j, int k) {
            const Int3 p{i, j, k};
            if (halos_.is_fixed_wall_face(c, p[c])) {
                ustar_[c](p) = 0;
                return;
            }
            // Body forces are explicit like advection: they join the AB2 history, so the
            // elastic and membrane forces are extrapolated to t^{n+1/2} as well.
            if (force) adv_[c](p) += (*force)[c](p) / rho;
            real rate = a1 * adv_[c](p) + a0 * s.adv_prev[c](p);
            rate += (-gradient_at(s.p, g, c, p) + cfg_.body_force[c]) / rho;
            if (explicit_share > 0)
                rate += explicit_share * viscous_laplacian_at(s.u, s.mu, g, c, p) / rho;
            if (s.viscosity_varies) rate += viscous_transpose_at(s.u, s.mu, g, c, p) / rho;
            ustar_[c](p) = s.u[c](p) + dt * rate;
            // Pinned solids, explicit viscous scheme: (1 + K) v* = v^n + dt rate.
            if (pinning_ && explicit_share == 1.0) ustar_[c](p) /= 1.0 + (*pinning_)[c](p);
        });
}

SolveReport SmacStepper::viscous_solve(const FlowState& s, real dt) {
    const GlobalGrid& g = dec_.grid();
    const auto& bc = cfg_.boundaries;
    const real a = theta_ * dt / cfg_.fluid.density;
    // Increment damping (time.increment_damping = F): b lap_h (v* - v^n) joins the implicit
    // side, b = dt (F - 1) mu_f / rho; zero (and no work) when F = 1.
    const real b =
        dt * (cfg_.time.increment_damping - 1) * cfg_.fluid.viscosity / cfg_.fluid.density;
    std::array<real, 3> inv_h2{};
    for (int e = 0; e < s.u.dim; ++e)
        inv_h2[e] = 1.0 / (g.dx(e) * g.dx(e));
    // The damping's weights: b / h^2 each (uniform), or b w / h^2 with w the weight field
    // averaged like the viscosity (band damping, set_damping_weight).
    const Field* w_damp = b > 0 ? damping_weight_ : nullptr;
    auto damping_weights = [&](int c, const Int3& p) {
        std::array<std::array<real, 2>, 3> bw{};
        if (w_damp) {
            bw = viscous_weights(*w_damp, g, s.u.dim, c, p);
            for (int e = 0; e < s.u.dim; ++e)
                for (int side = 0; side < 2; ++side)
                    bw[e][side] *= b;
        } else {
            for (int e = 0; e < s.u.dim; ++e)
                bw[e][0] = bw[e][1] = b * inv_h2[e];
        }
        return bw;
    };
    const bool reassemble = s.viscosity_varies || w_damp || dt != viscous_dt_;
    bool used_hypre = false;
    SolveReport worst;
    for (int c = 0; c < s.u.dim; ++c) {
        // Right-hand side: the predictor plus the known wall values of the ghosts (and, with
        // increment damping, -b lap_h v^n, its ghosts holding the walls at t^n). Written
        // straight into the direct solver's buffer when it solves this component.
        FftSolver* fft = (viscous_fft_[c] && !s.viscosity_varies && !pinning_ && !w_damp)
                             ? viscous_fft_[c].get()
                             : nullptr;
        const Int3 n = dec_.block().cells;
        auto out_row = [&](int j, int k) { return fft ? fft->input_row(j, k) : &rhs_(0, j, k); };
        for_each_owned_row(dec_, [&](int j, int k) {
            const real* from = &ustar_[c](0, j, k);
            std::copy(from, from + n[0], out_row(j, k));
        });
        if (b > 0)
            for_each_owned_row(dec_, [&](int j, int k) {
                real* r = out_row(j, k);
                for (int i = 0; i < n[0]; ++i) {
                    const Int3 p{i, j, k};
                    if (halos_.is_fixed_wall_face(c, p[c])) continue;
                    const real uc = s.u[c](p);
                    if (w_damp) {
                        const auto bw = damping_weights(c, p);
                        real lap = 0;
                        for (int e = 0; e < s.u.dim; ++e)
                            lap += bw[e][0] * (s.u[c](shifted(p, e, -1)) - uc) +
                                   bw[e][1] * (s.u[c](shifted(p, e, 1)) - uc);
                        r[i] -= lap;
                        continue;
                    }
                    real lap = 0;
                    for (int e = 0; e < s.u.dim; ++e)
                        lap += (s.u[c](shifted(p, e, -1)) - 2 * uc + s.u[c](shifted(p, e, 1))) *
                               inv_h2[e];
                    r[i] -= b * lap;
                }
            });
        // Only points next to a no-slip wall across their component get a wall term (the
        // weights are computed there only: this runs before every solve). Such points lie
        // in a row on a wall plane (y or z) or at the ends of a row (x).
        auto wall_terms = [&](const Int3& p, real& r) {
            bool next_to_wall = false;
            for (int e = 0; e < s.u.dim; ++e)
                for (int side = 0; side < 2; ++side)
                    next_to_wall = next_to_wall || (e != c && on_box_face(dec_, bc, e, side, p) &&
                                                    bc[e][side].type == BoundaryType::Wall);
            if (!next_to_wall || halos_.is_fixed_wall_face(c, p[c])) return;
            const auto w = viscous_weights(s.mu, g, s.u.dim, c, p);
            const auto bw = damping_weights(c, p);
            for (int e = 0; e < s.u.dim; ++e)
                for (int side = 0; side < 2; ++side)
                    if (e != c && on_box_face(dec_, bc, e, side, p) &&
                        bc[e][side].type == BoundaryType::Wall)
                        r += 2 * (a * w[e][side] + bw[e][side]) *
                             bc[e][side].velocity_at(c, halos_.time());
        };
        auto wall_plane = [&](int e, int index) {
            if (e == c || e >= s.u.dim) return false;
            for (int side = 0; side < 2; ++side)
                if (bc[e][side].type == BoundaryType::Wall &&
                    on_box_face(dec_, bc, e, side, Int3{index, index, index}))
                    return true;
            return false;
        };
        const bool x_walls = wall_plane(0, 0) || wall_plane(0, n[0] - 1);
        for_each_owned_row(dec_, [&](int j, int k) {
            real* r = out_row(j, k);
            if (wall_plane(1, j) || wall_plane(2, k)) {
                for (int i = 0; i < n[0]; ++i)
                    wall_terms(Int3{i, j, k}, r[i]);
            } else if (x_walls) {
                wall_terms(Int3{0, j, k}, r[0]);
                if (n[0] > 1) wall_terms(Int3{n[0] - 1, j, k}, r[n[0] - 1]);
            }
        });
        if (fft) {
            // Constant coefficients: (I - a mu L_h) solved directly, mu the (uniform)
            // viscosity field's value as the other terms and the hypre operator use it.
            fft->set_coefficients(1.0, a * s.mu(0, 0, 0) + b);
            const SolveReport r = fft->solve_in_place(ustar_[c]);
            if (r.iterations >= worst.iterations) worst = r;
            continue;
        }
        StructuredSolver& solver = hypre_viscous(c);
        if (reassemble || viscous_dt_ < 0) {
            solver.set_operator([&](int i, int j, int k) {
                Stencil st;
                const Int3 p{i, j, k};
                if (halos_.is_fixed_wall_face(c, p[c])) {
                    st.centre = 1; // the wall face keeps its zero normal velocity
                    return st;
                }
                const auto w = viscous_weights(s.mu, g, s.u.dim, c, p);
                const auto bw = damping_weights(c, p);
                // Identity plus the implicit penalisation K = dt chi / tau of pinned solids.
                st.centre = 1 + (pinning_ ? (*pinning_)[c](p) : 0.0);
                for (int e = 0; e < s.u.dim; ++e)
                    for (int side = 0; side < 2; ++side) {
                        const real aw = a * w[e][side] + bw[e][side];
                        st.centre += aw;
                        st.neighbour[e][side] = -aw;
                        if (e == c) {
                            // Coupling to the fixed (zero) wall face drops out, keeping A
                            // symmetric.
                            if (side == 0 && halos_.is_fixed_wall_face(c, p[c] - 1))
                                st.neighbour[e][side] = 0;
                        } else if (on_box_face(dec_, bc, e, side, p)) {
                            // Ghost = 2U - u (wall) or u (free slip), folded into the centre.
                            st.centre += bc[e][side].type == BoundaryType::Wall ? aw : -aw;
                        }
                    }
                return st;
            });
        }
        // Initial guess u^n, not the predictor, whose residual theta dt nu lap(u) is not
        // small in the near-steady low-Re flows that make this solve costly (3D capsule,
        // d/16: 15 -> 13 iterations to the same tolerance, D equal to 9 digits;
        // docs/method.md). u^n is in the checkpoint, so a restart stays bit for bit. It is
        // shifted by the mean of (rhs - u^n) so that, in a periodic box, the initial
        // residual has zero mean like the predictor's: the residual's mean is the momentum
        // error, and the solve's tolerance must not decide it.
        for_each_cell(dec_.block().cells, [&](int i, int j, int k) {
            ustar_[c](i, j, k) = rhs_(i, j, k) - s.u[c](i, j, k);
        });
        const real shift = mean_over_block(dec_, ustar_[c]);
        for_each_cell(dec_.block().cells, [&](int i, int j, int k) {
            const Int3 p{i, j, k};
            ustar_[c](p) = s.u[c](p) + (halos_.is_fixed_wall_face(c, p[c]) ? 0.0 : shift);
        });
        const SolveReport r = solver.solve(rhs_, ustar_[c]);
        if (r.iterations >= worst.iterations) worst = r;
        worst.converged = worst.converged && r.converged;
        used_hypre = true;
    }
    if (used_hypre) viscous_dt_ = dt;
    return worst;
}

SolveReport SmacStepper::pressure_solve(real dt) {
    const GlobalGrid& g = dec_.grid();
    halos_.fill_normal(ustar_); // the divergence reads u*_c across its own c-faces only
    const real scale = cfg_.fluid.density / dt;
    sweep::require_same_layout(ustar_[0], rhs_);
    if (pressure_fft_) {
        // The direct solve needs no stopping floor (so no max |v*| and no reduction for
        // it) and no starting guess; it drops the right-hand side's mean (its zero mode,
        // round-off here) and sets the (undetermined) mean of phi to zero.
        // The right-hand side goes straight into the solver's buffer.
        auto into = [&](int j, int k) { return pressure_fft_->input_row(j, k); };
        if (ustar_.dim == 2)
            sweep::divergence_rows<2, false>(ustar_, g, scale, into);
        else
            sweep::divergence_rows<3, false>(ustar_, g, scale, into);
        return pressure_fft_->solve_in_place(phi_);
    }
    const real speed = ustar_.dim == 2 ? sweep::divergence<2>(ustar_, g, scale, rhs_)
                                       : sweep::divergence<3>(ustar_, g, scale, rhs_);
    // A divergence at round-off level of |v*|/h cannot be reduced further: stop there.
    const real floor = 1e-13 * scale * dec_.max(speed) / g.dx(0) * std::sqrt(real(g.total_cells()));
    // With no Dirichlet pressure anywhere the operator is singular: make the right-hand
    // side compatible (zero mean), start from zero.
    const real mean = mean_over_block(dec_, rhs_);
    for_each_cell(dec_.block().cells, [&](int i, int j, int k) {
        rhs_(i, j, k) -= mean;
        phi_(i, j, k) = 0;
    });
    return pressure_->solve(rhs_, phi_, floor);
}

void SmacStepper::correction(FlowState& s, real dt) {
    const GlobalGrid& g = dec_.grid();
    halos_.fill(phi_);
    const real scale = dt / cfg_.fluid.density;
    sweep::for_each_component(s.u.dim, [&]<int C, int Dim>() {
        sweep::require_same_layout(s.u[C], phi_);
        sweep::correction<C, Dim>(ustar_[C], phi_, g, scale, wall_at_low(C), s.u[C]);
    });
    const real mean = mean_over_block(dec_, phi_);
    const int n0 = dec_.block().cells[0];
    for_each_owned_row(dec_, [&](int j, int k) {
        real* p = row_of(s.p, j, k);
        const real* ph = row_of(phi_, j, k);
        for (int i = 0; i < n0; ++i)
            p[i] += ph[i] - mean;
    });
    halos_.fill(s.p);
}

} // namespace efsi
