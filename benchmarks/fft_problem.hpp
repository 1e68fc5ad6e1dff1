// The direct pressure solve the benchmarks time: the unit cube of n^3 cells, periodic, or
// with walls in y (zero gradient), and a smooth right-hand side.
#pragma once

#include "bench_grid.hpp"
#include "grid/field.hpp"
#include "linear/fft_poisson.hpp"
#include "parallel/decomposition.hpp"

#include <mpi.h>

#include <array>
#include <cmath>
#include <numbers>

namespace efsi::bench {

struct FftPressureProblem {
    FftPressureProblem(int n, bool walls)
        : dec(MPI_COMM_WORLD, cube(n), Bool3{true, !walls, true}),
          solver(dec, directions(dec.periodic())), rhs("rhs", Location::Cell, dec.block(), 3),
          x("x", Location::Cell, dec.block(), 3) {
        solver.set_coefficients(0.0, 1.0);
        const real pi = std::numbers::pi;
        const Int3 o = dec.block().offset;
        for_each_cell(dec.block().cells, [&](int i, int j, int k) {
            rhs(i, j, k) = std::sin(2 * pi * (i + o[0]) / n) * std::cos(2 * pi * (j + o[1]) / n) *
                           std::cos(2 * pi * (k + o[2]) / n);
        });
    }
    FftPressureProblem(const FftPressureProblem&) = delete;
    FftPressureProblem& operator=(const FftPressureProblem&) = delete;

    static std::array<FftDirection, 3> directions(const Bool3& periodic) {
        std::array<FftDirection, 3> dirs{};
        for (int d = 0; d < 3; ++d)
            dirs[d].periodic = periodic[d];
        return dirs;
    }

    Decomposition dec;
    FftSolver solver;
    Field rhs, x;
};

} // namespace efsi::bench
