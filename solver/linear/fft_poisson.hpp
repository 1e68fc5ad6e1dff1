// Direct solves of the constant-coefficient operator (alpha I - beta L_h) on the uniform
// grid, L_h the standard (2*dim+1)-point Laplacian, by diagonalising L_h with the fast
// real transforms of FFTW 3 in every direction (docs/method.md, "Direct FFT solves"):
//
//   closure of a direction (ghost rule)            transform (FFTW)      eigenvalue of -h^2 L
//   periodic                                       R2HC / HC2R           4 sin^2(pi k / N)
//   zero gradient at both faces (ghost = u)        REDFT10 / REDFT01     4 sin^2(pi k / 2N)
//   zero value on both faces (ghost = -u)          RODFT10 / RODFT01     4 sin^2(pi (k+1) / 2N)
//   zero value low, zero gradient high             RODFT11               4 sin^2(pi (2k+1) / 4N)
//   zero gradient low, zero value high             REDFT11               4 sin^2(pi (2k+1) / 4N)
//   face unknowns, both box faces fixed            RODFT00 on 1..N-1     4 sin^2(pi (k+1) / 2N)
//
// The last one is the velocity component normal to a pair of walls: index 0 of its
// direction is the (stored) low wall face, an identity row (x = rhs there), and the high
// wall face is not stored. Inhomogeneous boundary values belong in the right-hand side.
// With alpha = 0 and no zero-value closure the operator is singular; the zero mode of
// the solution is then set to zero (the caller makes the right-hand side zero-mean).
//
// With x periodic, x is transformed real-to-complex (an even x as a complex DFT of half the
// length, HalfLengthReal in fft_detail.hpp) and the other periodic directions by
// complex DFTs (FFTW's vectorised codelets; its R2HC and DCT/DST kinds are scalar), and a
// wall direction (y, else z) is not transformed at all: each wavenumber pair of the other
// directions leaves a tridiagonal system along it, solved by the Thomas algorithm (the
// approach of CaNS, Costa 2018). The answer is the same discrete solution either way.
//
// Under MPI the data goes from the Decomposition's Cartesian blocks to slabs (split along
// the last direction) for the transforms in the other directions, then to slabs split
// along another direction for the transform in the last one (parallel/redistribution.hpp);
// with a tridiagonal direction the first slabs transform x alone and the second, split
// along x, everything else. Periodic in all three directions on several ranks, z (along
// which the first slabs are split) is not transformed but solved as cyclic tridiagonal
// systems split over the ranks, joined by a reduced system of one unknown per rank and
// line (one small all-gather instead of two transposes of the whole array).
// linear/fft_poisson.cpp, linear/fft_tridiagonal.cpp and their private header
// linear/fft_detail.hpp are the only files that include FFTW.
#pragma once

#include "core/types.hpp"
#include "grid/field.hpp"
#include "linear/structured_solver.hpp"
#include "parallel/decomposition.hpp"

#include <array>
#include <memory>
#include <string>

namespace efsi {

/// How one box face closes the Laplacian (ignored along a periodic direction).
enum class FftSide {
    ZeroGradient, ///< ghost = mirror (homogeneous Neumann at the face)
    ZeroValue,    ///< ghost = -mirror (homogeneous Dirichlet at the face)
};

/// The closure of one direction.
struct FftDirection {
    bool periodic = true;
    FftSide low = FftSide::ZeroGradient, high = FftSide::ZeroGradient;
    /// Unknowns on the faces normal to this direction with both box faces fixed (the
    /// wall-normal velocity): `low` and `high` are then not used.
    bool wall_faces = false;
};

/// Buffers and data movements shared by the FFT solvers of one decomposition (they
/// solve one after the other, so one set of buffers serves them all).
class FftWorkspace;
std::shared_ptr<FftWorkspace> make_fft_workspace(const Decomposition& dec);

class FftSolver {
  public:
    FftSolver(const Decomposition& dec, const std::array<FftDirection, 3>& directions,
              std::shared_ptr<FftWorkspace> workspace = nullptr);
    ~FftSolver();
    FftSolver(const FftSolver&) = delete;
    FftSolver& operator=(const FftSolver&) = delete;

    /// The operator alpha I - beta L_h (alpha >= 0, beta >= 0, not both zero).
    void set_coefficients(real alpha, real beta);

    /// Solve over the owned block (x's halos are not touched). A direct solve: the report
    /// has one iteration and a zero (not measured) residual.
    SolveReport solve(const Field& rhs, Field& x);

    /// The right-hand side written straight into the solver's buffer, which saves the copy
    /// of solve(rhs, x): row (j, k) of the owned block (block-local indices, n[0] values)
    /// goes to input_row(j, k); then solve_in_place(x). A wall-face identity row takes its
    /// value from the buffer too.
    real* input_row(int j, int k);
    SolveReport solve_in_place(Field& x);

    /// One line naming the transform of each direction (for logs).
    std::string describe() const;

    /// Wall seconds spent so far in each phase of solve(), summed over calls on this rank:
    /// copy (block in and out), transforms (every FFTW execution), redistribution (the
    /// block-to-slab and slab-to-slab moves, MPI included) and divide (by the eigenvalues).
    struct PhaseSeconds {
        double copy = 0, transforms = 0, redistribution = 0, divide = 0;
    };
    const PhaseSeconds& phase_seconds() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace efsi
