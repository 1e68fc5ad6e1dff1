#include "flow/initial_conditions.hpp"

#include "core/error.hpp"

#include <cmath>
#include <numbers>

namespace efsi {

void set_initial_condition(const Config& cfg, const Decomposition& dec, FlowState& s) {
    const GlobalGrid& g = dec.grid();
    const LocalBlock& b = dec.block();
    const real U = cfg.initial.amplitude;
    const std::string& type = cfg.initial.type;
    const real k = 2 * std::numbers::pi / g.length[0];
    const real Ly = g.length[1];
    for (int c = 0; c < s.u.dim; ++c) {
        const Location loc = face_location(c);
        for_each_cell(b.cells, [&](int i, int j, int kk) {
            const Real3 x = position(g, b, loc, i, j, kk);
            const real y = x[1] - g.origin[1];
            real v = 0;
            if (type == "uniform") {
                v = cfg.initial.velocity[c];
            } else if (type == "taylor_green") {
                const real cz = g.dim == 3 ? std::cos(k * x[2]) : 1.0;
                if (c == 0) v = U * std::sin(k * x[0]) * std::cos(k * x[1]) * cz;
                if (c == 1) v = -U * std::cos(k * x[0]) * std::sin(k * x[1]) * cz;
            } else if (c == 0 && type == "couette") {
                v = U * y / Ly;
            } else if (c == 0 && type == "poiseuille") {
                v = U * 4 * y * (Ly - y) / (Ly * Ly);
            } else if (c == 0 && type == "shear") {
                v = U * (2 * y / Ly - 1);
            }
            s.u[c](i, j, kk) = v;
        });
    }
    for_each_cell(b.cells, [&](int i, int j, int kk) {
        const Real3 x = position(g, b, Location::Cell, i, j, kk);
        s.p(i, j, kk) =
            (type == "taylor_green" && g.dim == 2)
                ? cfg.fluid.density * U * U / 4 * (std::cos(2 * k * x[0]) + std::cos(2 * k * x[1]))
                : 0.0;
        s.mu(i, j, kk) = cfg.fluid.viscosity;
    });
    for (int c = 0; c < s.u.dim; ++c)
        s.adv_prev[c].fill(0);
}

} // namespace efsi
