// The direct FFT solve on any number of ranks, with a fixed number of solves on every rank
// (Google Benchmark picks its iteration count per process, which deadlocks a collective
// solve under mpirun). Prints the slowest rank's time per solve.
// Run: mpirun -np P build/bin/efsi_fft_solve_ranks [cells per direction] [walls 0|1] [solves]
#include "linear/structured_solver.hpp"

#include "fft_problem.hpp"

#include <fmt/core.h>
#include <mpi.h>

#include <array>
#include <cstdlib>

using namespace efsi;

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    {
        LinearAlgebraScope scope;
        const int n = argc > 1 ? std::atoi(argv[1]) : 128;
        const bool walls = argc > 2 && std::atoi(argv[2]) != 0;
        const int solves = argc > 3 ? std::atoi(argv[3]) : 20;
        bench::FftPressureProblem prob(n, walls);
        FftSolver& solver = prob.solver;
        const Decomposition& dec = prob.dec;
        Field &rhs = prob.rhs, &x = prob.x;
        for (int s = 0; s < 3; ++s) // warm-up: first-touch of the buffers
            solver.solve(rhs, x);
        MPI_Barrier(MPI_COMM_WORLD);
        const double t0 = MPI_Wtime();
        const auto before = solver.phase_seconds();
        std::array<double, 5> mine{}, slowest{};
        for (int s = 0; s < solves; ++s)
            solver.solve(rhs, x);
        mine[0] = MPI_Wtime() - t0;
        const auto after = solver.phase_seconds();
        mine[1] = after.copy - before.copy;
        mine[2] = after.transforms - before.transforms;
        mine[3] = after.redistribution - before.redistribution;
        mine[4] = after.divide - before.divide;
        MPI_Reduce(mine.data(), slowest.data(), 5, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
        if (dec.rank() == 0) {
            const double ms = 1e3 / solves;
            fmt::print("fft solve {}^3 {} on {} rank(s) ({}): {:.2f} ms per solve; slowest "
                       "rank per phase: copy {:.2f}, transforms {:.2f}, redistribution {:.2f}, "
                       "divide {:.2f} ms\n",
                       n, walls ? "walls in y" : "periodic", dec.size(), solver.describe(),
                       ms * slowest[0], ms * slowest[1], ms * slowest[2], ms * slowest[3],
                       ms * slowest[4]);
        }
    }
    MPI_Finalize();
    return 0;
}
