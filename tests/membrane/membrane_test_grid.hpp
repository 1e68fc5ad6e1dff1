// A centred box for the membrane unit tests: n cells of size h per direction (nz = 1 in
// 2D), every face of one boundary type, decomposed over MPI_COMM_WORLD.
#pragma once

#include "boundary/boundary.hpp"
#include "parallel/decomposition.hpp"

#include <memory>

namespace efsi::test {

struct GridSetup {
    GlobalGrid g;
    std::unique_ptr<Decomposition> dec;
    std::unique_ptr<HaloFiller> halos;
    BoxBoundaries bc{};
};

inline GridSetup make_setup(int dim, Int3 n, real h, BoundaryType boundary) {
    GridSetup s;
    s.g.dim = dim;
    if (dim == 2) n[2] = 1;
    s.g.cells = n;
    for (int d = 0; d < 3; ++d) {
        s.g.length[d] = n[d] * h;
        s.g.origin[d] = -0.5 * n[d] * h;
    }
    for (int d = 0; d < dim; ++d)
        s.bc[d][0].type = s.bc[d][1].type = boundary;
    s.dec = std::make_unique<Decomposition>(MPI_COMM_WORLD, s.g, periodic_directions(s.bc));
    s.halos = std::make_unique<HaloFiller>(*s.dec, s.bc);
    return s;
}

} // namespace efsi::test
