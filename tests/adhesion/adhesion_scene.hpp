// A small channel for the adhesion coupling tests: cubic cells of h = 0.25 um, walls in y
// (the vWF patch lies on y = 0), periodic in x and z, decomposed over MPI_COMM_WORLD; and
// helpers that build the coupling's configuration directly (the case-file reader is tested
// in test_adhesion_config.cpp), the bond scene and the force field's totals.
#pragma once

#include "adhesion/coupling.hpp"
#include "boundary/boundary.hpp"
#include "parallel/decomposition.hpp"
#include "test_support.hpp"

#include <memory>
#include <vector>

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

/// Largest minus smallest of x over the ranks: 0 when every rank holds the same value.
inline real spread_over_ranks(real x) {
    return global_max(x) + global_max(-x);
}

/// A configuration with one group of `count` receptors per body and one ligand patch on
/// the wall y = 0 over [lo_x, hi_x] x [lo_z, hi_z] with 50 nm spacing.
inline AdhesionConfig adhesion_config(std::size_t bodies, std::uint64_t count, Real3 patch_lo,
                                      Real3 patch_hi) {
    AdhesionConfig a;
    a.enabled = true;
    a.seed = 11;
    a.ligand_regions.push_back({patch_lo, patch_hi, 50 * nm});
    a.ligand_density.push_back(1 / (50 * nm * 50 * nm));
    // These tests give the receptors a velocity field and no body: carried by the flow (the
    // rigid motion is tested with its fit, test_adhesion_receptors.cpp).
    a.receptor_motion = ReceptorMotion::flow;
    for (std::size_t k = 0; k < bodies; ++k)
        a.receptors.push_back({"", k, count, 0});
    return a;
}

/// Sum over the owned faces of every rank of force * cell volume, per component.
inline Real3 total_force(const VelocityField& f, const Channel& c) {
    Real3 t{0, 0, 0};
    for (int comp = 0; comp < 3; ++comp) {
        real s = 0;
        for_each_cell(c.dec->block().cells,
                      [&](int i, int j, int k) { s += f[comp](i, j, k) * c.g.cell_volume(); });
        t[comp] = c.dec->sum(s);
    }
    return t;
}

inline VelocityField zero_field(const Channel& c) {
    VelocityField f("force", c.dec->block(), 3);
    for (int comp = 0; comp < 3; ++comp)
        f[comp].fill(0);
    return f;
}

/// A sphere resting 30 nm above the vWF patch on y = 0, and a second one far from it.
struct BondScene {
    Channel c = make_channel({16, 16, 16}, 0.25 * um);
    std::vector<BodyConfig> bodies{sphere_body("near", {2 * um, 1.03 * um, 2 * um}, 1 * um),
                                   sphere_body("far", {2 * um, 2.9 * um, 2 * um}, 0.9 * um)};
    AdhesionConfig cfg = [] {
        AdhesionConfig a =
            adhesion_config(2, 2000, {1.0 * um, 0, 1.0 * um}, {3.0 * um, 0, 3.0 * um});
        a.parameters.k_on = 2e6; // bonds form within a few steps of 1e-7 s
        return a;
    }();
};

} // namespace efsi::test
