#include "simulation/diagnostics.hpp"

#include "operators/flow_operators.hpp"

#include <fmt/core.h>

#include <cmath>

namespace efsi {

std::string Diagnostics::csv_header() {
    return "step,time,dt,max_divergence,kinetic_energy,max_speed,cfl,pressure_iterations,"
           "pressure_residual,viscous_iterations";
}

std::string Diagnostics::csv_row() const {
    return fmt::format("{},{:.10e},{:.6e},{:.6e},{:.10e},{:.6e},{:.4f},{},{:.3e},{}", step, time,
                       dt, max_divergence, kinetic_energy, max_speed, cfl, pressure_iterations,
                       pressure_residual, viscous_iterations);
}

void measure_flow(const Decomposition& dec, const FlowState& s, real density, Diagnostics& d) {
    const GlobalGrid& g = dec.grid();
    real div = 0, ke = 0, speed = 0;
    for_each_cell(dec.block().cells, [&](int i, int j, int k) {
        const Int3 p{i, j, k};
        div = std::max(div, std::abs(divergence_at(s.u, g, p)));
        for (int c = 0; c < s.u.dim; ++c) {
            // Each face carries half the energy of the two cells it joins (trapezoid in c).
            const real v = s.u[c](p);
            ke += v * v;
            speed = std::max(speed, std::abs(v));
        }
    });
    d.max_divergence = dec.max(div);
    d.kinetic_energy = 0.5 * density * dec.sum(ke) * g.cell_volume();
    d.max_speed = dec.max(speed);
}

std::string locate_worst_velocity(const Decomposition& dec, const FlowState& s,
                                  const std::string& speed_unit) {
    const GlobalGrid& g = dec.grid();
    real worst = -1;
    Real3 where{0, 0, 0};
    int comp = 0;
    for (int c = 0; c < s.u.dim; ++c)
        for_each_cell(dec.block().cells, [&](int i, int j, int k) {
            const real v = s.u[c](i, j, k);
            const real m = std::isfinite(v) ? std::abs(v) : std::numeric_limits<real>::max();
            if (m > worst) {
                worst = m;
                comp = c;
                where = position(g, dec.block(), face_location(c), i, j, k);
            }
        });
    const real global = dec.max(worst);
    const real mine = worst == global ? 1.0 : 0.0;
    const real owners = dec.sum(mine);
    Real3 x{};
    for (int d = 0; d < 3; ++d)
        x[d] = dec.sum(mine * where[d]) / owners;
    const real cc = dec.sum(mine * comp) / owners;
    const bool finite = global < std::numeric_limits<real>::max();
    return fmt::format("{} velocity component {} at x = ({:.4g}, {:.4g}, {:.4g})",
                       finite ? fmt::format("largest |v| = {:.3e} {} in", global, speed_unit)
                              : std::string("non-finite"),
                       "uvw"[int(std::lround(cc))], x[0], x[1], x[2]);
}

} // namespace efsi
