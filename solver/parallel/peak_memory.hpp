// Peak memory of a run: the resident set size high-water mark (getrusage ru_maxrss) of each
// rank, reduced over the ranks (the largest one and the sum; the sum bounds the job's peak
// from above, since the ranks' peaks need not coincide).
#pragma once

#include <mpi.h>
#include <sys/resource.h>

#include <cstdint>

namespace efsi {

struct PeakMemory {
    double max_rank_bytes = 0; ///< the largest rank's peak RSS
    double sum_bytes = 0;      ///< the ranks' peak RSS summed
};

/// This process's peak RSS in bytes (Linux reports ru_maxrss in kB).
inline double peak_rss_bytes() {
    rusage u{};
    if (getrusage(RUSAGE_SELF, &u) != 0) return 0;
    return double(u.ru_maxrss) * 1024.0;
}

/// Collective over `comm` when `collective` (every rank must call it then); otherwise this
/// rank's own figure for both, with no communication (a run stopping on one rank only must
/// not wait for the others).
inline PeakMemory peak_memory(MPI_Comm comm, bool collective) {
    const double mine = peak_rss_bytes();
    PeakMemory m{mine, mine};
    if (!collective) return m;
    MPI_Allreduce(&mine, &m.max_rank_bytes, 1, MPI_DOUBLE, MPI_MAX, comm);
    MPI_Allreduce(&mine, &m.sum_bytes, 1, MPI_DOUBLE, MPI_SUM, comm);
    return m;
}

} // namespace efsi
