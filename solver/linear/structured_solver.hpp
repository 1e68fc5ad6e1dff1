// Linear solves on the structured grid: (2*dim+1)-point operators, one unknown per
// point of the rank's block, periodic wrap where the box is periodic. The backend is
// hypre's Struct interface (PFMG/SMG multigrid, alone or preconditioning CG/GMRES);
// linear/hypre_struct_solver.cpp is the only file in the project that includes hypre.
#pragma once

#include "core/types.hpp"
#include "grid/field.hpp"
#include "parallel/decomposition.hpp"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace efsi {

struct LinearSolverSettings {
    /// pcg_pfmg | gmres_pfmg | pcg_smg | pfmg; a case may also say auto | fft (config.hpp,
    /// choose_linear_solvers), which the stepper resolves before it builds a hypre solver
    std::string method = "pcg_pfmg";
    real tolerance = 1e-10; ///< relative residual ||r|| / ||b||
    int max_iterations = 200;
};

struct SolveReport {
    int iterations = 0;
    real relative_residual = 0;
    bool converged = true;
};

/// Coefficients of one row: centre and the low (0) / high (1) neighbour in each direction.
struct Stencil {
    real centre = 0;
    std::array<std::array<real, 2>, 3> neighbour{};
};

/// Starts and stops the linear-algebra library (once per process, around everything).
class LinearAlgebraScope {
  public:
    LinearAlgebraScope();
    ~LinearAlgebraScope();
    LinearAlgebraScope(const LinearAlgebraScope&) = delete;
    LinearAlgebraScope& operator=(const LinearAlgebraScope&) = delete;
};

class StructuredSolver {
  public:
    StructuredSolver(const Decomposition& dec, Bool3 periodic, LinearSolverSettings settings);
    ~StructuredSolver();
    StructuredSolver(const StructuredSolver&) = delete;
    StructuredSolver& operator=(const StructuredSolver&) = delete;

    /// Set the operator from a pointwise function stencil(i, j, k) over the owned block.
    /// Couplings across non-periodic box faces must already be folded into the centre
    /// coefficient and right-hand side by the caller; they are dropped here.
    template <class StencilAt>
    void set_operator(StencilAt&& stencil_at) {
        const int dim = dec_.dim();
        const Int3 n = dec_.block().cells;
        const int entries = 2 * dim + 1;
        values_.resize(std::size_t(dec_.block().count()) * entries);
        std::size_t c = 0;
        for_each_cell(n, [&](int i, int j, int k) {
            const Stencil s = stencil_at(i, j, k);
            const Int3 p{i, j, k};
            values_[c++] = s.centre;
            for (int d = 0; d < dim; ++d)
                for (int side = 0; side < 2; ++side) {
                    const bool outside = !periodic_[d] && dec_.at_boundary(d, side) &&
                                         p[d] == (side == 0 ? 0 : n[d] - 1);
                    values_[c++] = outside ? 0.0 : s.neighbour[d][side];
                }
        });
        assemble_operator();
    }

    /// Solve A x = b over the owned block; x holds the initial guess on entry. The solve
    /// stops at ||r|| <= max(tolerance ||b||, absolute_tolerance) (Krylov methods), so a
    /// right-hand side that is only round-off does not run to the iteration cap.
    SolveReport solve(const Field& rhs, Field& x, real absolute_tolerance = 0);

    const LinearSolverSettings& settings() const { return settings_; }

  private:
    void assemble_operator();

    struct Impl;
    const Decomposition& dec_;
    Bool3 periodic_;
    LinearSolverSettings settings_;
    std::vector<real> values_;
    std::vector<real> buffer_;
    std::unique_ptr<Impl> impl_;
};

} // namespace efsi
