// Shared by the per-kind body tests (tests/bodies, tests/solid, tests/membrane): a run's
// bodies built from TOML text on an anisotropic 2D grid (24 x 20 cells), and small
// measurements of their fields reduced over the ranks.
#pragma once

#include "bodies/body_system.hpp"
#include "test_support.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace efsi::test {

/// The [grid], [fluid] and [time] tables of the body tests: `cells` and `length` as TOML
/// arrays, density 2, viscosity 0.1, end time 1.
inline std::string grid_toml(const std::string& cells, const std::string& length) {
    return "\n[grid]\ncells = " + cells + "\nlength = " + length +
           "\n\n[fluid]\ndensity = 2.0\nviscosity = 0.1\n\n[time]\nend_time = 1.0\n";
}

/// A 24 x 20 cell 2D grid (one cell thick in z).
inline std::string grid_2d() {
    return grid_toml("[24, 20, 1]", "[1.2, 1.0, 0.05]");
}

/// A 24 x 20 x 16 periodic 3D grid (h = 0.05) followed by `body` (TOML text).
inline std::string grid_3d(const std::string& body) {
    return grid_toml("[24, 20, 16]", "[1.2, 1.0, 0.8]") + body;
}

/// A run's bodies on this rank count: the decomposition, halos and BodySystem of `toml`.
struct Bodies {
    Config cfg;
    Decomposition dec;
    HaloFiller halos;
    BodySystem system;
    explicit Bodies(const std::string& toml)
        : cfg(case_from(toml)),
          dec(MPI_COMM_WORLD, cfg.grid, periodic_directions(cfg.boundaries), cfg.ranks),
          halos(dec, cfg.boundaries), system(cfg, dec, halos) {
        system.initialise();
    }
    Body& body(std::size_t i) { return *system.bodies()[i]; }
    const BodyPhysics& physics(std::size_t i) { return *system.physics()[i]; }
};

inline const TimeStepLimit* find_limit(const std::vector<TimeStepLimit>& limits,
                                       const std::string& n) {
    for (const auto& l : limits)
        if (l.name == n) return &l;
    return nullptr;
}

inline real largest_force(const VelocityField& f) {
    real m = 0;
    for (int c = 0; c < f.dim; ++c)
        for_each_in(f[c].owned(),
                    [&](int i, int j, int k) { m = std::max(m, std::abs(f[c](i, j, k))); });
    return global_max(m);
}

inline real volume(const Decomposition& dec, const Body& b) {
    real v = 0;
    if (!b.patch().empty())
        for_each_in(b.phi().owned(), [&](int i, int j, int k) { v += b.phi()(i, j, k); });
    return dec.sum(v);
}

/// A uniform velocity (ux, uy) on every face, halos filled.
inline VelocityField uniform_velocity(Bodies& s, real ux, real uy) {
    VelocityField u("u", s.dec.block(), s.dec.dim());
    u[0].fill(ux);
    u[1].fill(uy);
    s.halos.fill(u);
    return u;
}

} // namespace efsi::test
