// The grid the micro-benchmarks run on.
#pragma once

#include "grid/grid.hpp"

namespace efsi::bench {

/// A periodic unit cube of n^3 cells.
inline GlobalGrid cube(int n) {
    GlobalGrid g;
    g.cells = {n, n, n};
    g.length = {1, 1, 1};
    g.dim = 3;
    return g;
}

} // namespace efsi::bench
