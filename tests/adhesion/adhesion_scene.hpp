// A small channel for the adhesion coupling tests: cubic cells of h = 0.25 um, walls in y
// (the vWF patch lies on y = 0), periodic in x and z, decomposed over MPI_COMM_WORLD; and
// helpers that build the coupling's configuration directly (the case-file reader is tested
// in test_adhesion_config.cpp).
#pragma once

#include "adhesion/coupling.hpp"
#include "boundary/boundary.hpp"
#include "parallel/decomposition.hpp"

#include <memory>

namespace efsi::test {

inline constexpr real um = 1e-6, nm = 1e-9;

struct Channel {
    GlobalGrid g;
    BoxBoundaries bc{};
    std::unique_ptr<Decomposition> dec;
    std::unique_ptr<HaloFiller> halos;
};

/// n cells of size h per direction; walls in y (moving with `top` / `bottom` in x).
/// `comm` MPI_COMM_SELF gives every rank the whole grid (the serial reference).
inline Channel make_channel(Int3 n, real h, real bottom = 0, real top = 0,
                            MPI_Comm comm = MPI_COMM_WORLD) {
    Channel c;
    c.g.dim = 3;
    c.g.cells = n;
    for (int d = 0; d < 3; ++d)
        c.g.length[d] = n[d] * h;
    c.bc[1][0].type = c.bc[1][1].type = BoundaryType::Wall;
    c.bc[1][0].velocity = {bottom, 0, 0};
    c.bc[1][1].velocity = {top, 0, 0};
    c.dec = std::make_unique<Decomposition>(comm, c.g, periodic_directions(c.bc));
    c.halos = std::make_unique<HaloFiller>(*c.dec, c.bc);
    return c;
}

/// A free solid sphere (the platelet stand-in) of radius r at `centre`.
inline BodyConfig sphere_body(const std::string& name, const Real3& centre, real r) {
    BodyConfig b;
    b.name = name;
    b.kind = BodyKind::Solid;
    b.shape = BodyShape::Sphere;
    b.centre = centre;
    b.radius = r;
    b.shear_modulus = 1e4;
    return b;
}

/// The face velocity u_c = f(c, x_face) on the owned faces, halos filled.
template <class F>
VelocityField velocity_from(const Channel& c, F&& f) {
    VelocityField u("u", c.dec->block(), 3);
    for (int comp = 0; comp < 3; ++comp)
        for_each_cell(c.dec->block().cells, [&](int i, int j, int k) {
            u[comp](i, j, k) = f(comp, position(c.g, c.dec->block(), face_location(comp), i, j, k));
        });
    c.halos->fill(u);
    return u;
}

} // namespace efsi::test
