// Small helpers shared by the unit tests: MPI size/rank, a case built from TOML text,
// and the global reductions that turn a per-rank check into one verdict.
#pragma once

#include "config/config.hpp"
#include "core/error.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <mpi.h>

#include <string>

namespace efsi::test {

inline int world_size() {
    int n = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &n);
    return n;
}

inline int world_rank() {
    int r = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &r);
    return r;
}

/// Largest value of x over all ranks.
inline double global_max(double x) {
    double r = 0;
    MPI_Allreduce(&x, &r, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    return r;
}

inline long global_sum(long x) {
    long r = 0;
    MPI_Allreduce(&x, &r, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
    return r;
}

inline double global_sum_real(double x) {
    double r = 0;
    MPI_Allreduce(&x, &r, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    return r;
}

/// Parse a case from TOML text; failures are test failures with the message shown.
inline Config case_from(const std::string& toml, const Overrides& overrides = {}) {
    return parse_case(toml, "test_case", overrides);
}

/// The message of the InputError that `f` throws ("" and a test failure if none).
template <class F>
std::string input_error_of(F&& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected an InputError";
    return "";
}

} // namespace efsi::test
