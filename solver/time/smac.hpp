// The simplified-MAC (SMAC) fractional step of Amsden & Harlow, as used in the seed:
//
//   1. advection   A^n = -div(v^n v^n)                      (central, conservative)
//   2. predictor   v* = v^n + dt [ AB2(A + F/rho) - grad p^n / rho + f / rho
//                                  + (1 - theta) Lmu(v^n) / rho + T(v^n) / rho ]
//   3. viscous     (I - theta dt Lmu / rho - b lap) v* = (predictor) - b lap v^n  (implicit)
//   4. pressure    -lap(phi) = -(rho / dt) div v*
//   5. correction  v^{n+1} = v* - (dt / rho) grad phi,   p^{n+1} = p^n + phi
//
// Lmu u_c = div(mu grad u_c) is treated implicitly (theta = 1/2 Crank-Nicolson or 1
// backward Euler; theta = 0 is the explicit scheme) and T = div(mu (grad v)^T), which
// vanishes for uniform mu, explicitly. AB2 uses the variable-step weights; F, the force
// density of bodies (elastic, membrane), is extrapolated with the advection. b = dt (D - 1)
// mu_f / rho damps the velocity increment (D = time.increment_damping, 1 = off: b = 0 and
// no work); it vanishes at steady state and relaxes the explicit membrane limits D-fold.
// With time.increment_damping_on = "membranes" the damping is confined to the membranes'
// bands: b lap becomes b div(w grad), w in [0, 1] a cell field (set_damping_weight).
//
// Pinned solids add the Brinkman penalisation -(chi / tau) v (chi their volume fraction on
// the faces), implicit: the viscous solve becomes (I + K - theta dt Lmu / rho) v* = ...
// with K = dt chi / tau, and the explicit scheme divides v* by (1 + K).
//
// The linear solves are direct (FFT, linear/fft_poisson.hpp) where the operator has
// constant coefficients: always for the pressure, and for the viscous solve when mu is
// uniform and nothing is pinned; otherwise hypre (config.hpp, choose_linear_solvers).
#pragma once

#include "boundary/boundary.hpp"
#include "config/config.hpp"
#include "linear/fft_poisson.hpp"
#include "linear/structured_solver.hpp"
#include "time/flow_state.hpp"
#include "time/stage_timers.hpp"

#include <array>
#include <memory>

namespace efsi {

struct StepReport {
    SolveReport pressure;
    SolveReport viscous; ///< the worst of the component solves (most iterations)
};

class SmacStepper {
  public:
    SmacStepper(const Config& config, const Decomposition& dec, HaloFiller& halos);
    ~SmacStepper();

    /// Advance the state by dt; `force` (optional) is an extra force density on the faces
    /// [N/m^3] from bodies.
    StepReport step(FlowState& s, real dt, StageTimers& timers,
                    const VelocityField* force = nullptr);
    /// Penalise pinned solids: `k` holds K = dt chi / tau on the faces (dimensionless, as
    /// tau is a fixed multiple of dt); null (the default) adds no term and no work.
    void set_pinning(const VelocityField* k) { pinning_ = k; }
    /// Confine the increment damping to where the cell field `w` (in [0, 1], halos filled)
    /// is non-zero: the damping's Laplacian becomes div(w grad), weighted like the
    /// viscous term's mu. Null (the default): the damping is uniform.
    void set_damping_weight(const Field* w) { damping_weight_ = w; }

    /// Which solver runs for the pressure and the viscous solves, and why (for the log).
    std::string solver_summary() const;

  private:
    void advection(const FlowState& s);
    void predictor(const FlowState& s, real dt, const VelocityField* force);
    SolveReport viscous_solve(const FlowState& s, real dt);
    SolveReport pressure_solve(real dt);
    void correction(FlowState& s, real dt);
    /// True when this rank holds the fixed wall face at the low end of direction d.
    bool wall_at_low(int d) const;
    StructuredSolver& hypre_viscous(int c);
    std::array<FftDirection, 3> viscous_directions(int c) const;

    const Config& cfg_;
    const Decomposition& dec_;
    HaloFiller& halos_; ///< also told the time, for moving walls
    real theta_ = 0.5;
    VelocityField adv_;   ///< A^n
    VelocityField ustar_; ///< v*
    Field rhs_, phi_;
    LinearSolverChoice choice_;
    std::unique_ptr<StructuredSolver> pressure_; ///< hypre, when the FFT solve is not used
    std::array<std::unique_ptr<StructuredSolver>, 3> viscous_; ///< hypre, built when needed
    std::shared_ptr<FftWorkspace> fft_workspace_;
    std::unique_ptr<FftSolver> pressure_fft_;
    std::array<std::unique_ptr<FftSolver>, 3> viscous_fft_;
    real viscous_dt_ = -1;                   ///< dt the hypre viscous operators were assembled for
    const VelocityField* pinning_ = nullptr; ///< K = dt chi / tau of pinned solids
    const Field* damping_weight_ = nullptr;  ///< where the increment damping acts (null: all)
};

} // namespace efsi
