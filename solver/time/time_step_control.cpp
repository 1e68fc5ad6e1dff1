#include "time/time_step_control.hpp"

#include "core/error.hpp"
#include "operators/flow_sweeps.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace efsi {

void velocity_bounds(const Decomposition& dec, const FlowState& s, real& rate, real& speed) {
    // Row by row over unit-stride pointers: the per-cell rate sum_d |v_d| / h_d in a row
    // buffer (the same divisions in the same order as a per-cell loop), the maxima by
    // sweep::max_abs / max_of (exact in any order), non-finite values counted apart.
    const GlobalGrid& g = dec.grid();
    const Int3 n = dec.block().cells;
    const int dim = s.u.dim;
    std::vector<real> row_rate(std::size_t(std::max(n[0], 1)));
    real r = 0, m = 0;
    bool finite = true;
    for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j) {
            std::fill(row_rate.begin(), row_rate.end(), 0.0);
            for (int d = 0; d < dim; ++d) {
                const real* v = s.u[d].data().data() + s.u[d].index(0, j, k);
                const real h = g.dx(d);
                real* __restrict rr = row_rate.data();
                int nonfinite = 0;
                for (int i = 0; i < n[0]; ++i) {
                    const real a = std::abs(v[i]);
                    nonfinite += !(a <= std::numeric_limits<real>::max());
                    rr[i] += a / h;
                }
                if (nonfinite) finite = false;
                m = sweep::max_abs(v, n[0], m);
            }
            r = sweep::max_abs(row_rate.data(), n[0], r);
        }
    // One reduction for the three (every step: each reduction is a wait for all ranks).
    const std::array<real, 3> all = dec.max(std::array<real, 3>{finite ? 0.0 : 1.0, r, m});
    const real nan = std::numeric_limits<real>::quiet_NaN();
    rate = all[0] > 0 ? nan : all[1];
    speed = all[0] > 0 ? nan : all[2];
}

TimeStepChoice choose_time_step(const Config& cfg, const Decomposition& dec, const FlowState& s,
                                const std::vector<TimeStepLimit>& extra) {
    const GlobalGrid& g = dec.grid();
    TimeStepChoice out;
    real rate = 0;
    velocity_bounds(dec, s, rate, out.max_speed);
    real wall_rate = 0;
    for (int d = 0; d < 3; ++d)
        for (int side = 0; side < 2; ++side) {
            real r = 0;
            for (int c = 0; c < g.dim; ++c)
                r += std::abs(cfg.boundaries[d][side].velocity[c]) / g.dx(c);
            wall_rate = std::max(wall_rate, r);
        }
    const real inf = std::numeric_limits<real>::infinity();
    if (!std::isfinite(rate)) {
        out.dt = std::numeric_limits<real>::quiet_NaN();
        out.cfl = out.dt;
        out.limited_by = "non-finite velocity";
        return out;
    }
    real best = inf;
    auto consider = [&](real limit, const char* name) {
        if (limit < best) {
            best = limit;
            out.limited_by = name;
        }
    };
    const real advective_rate = std::max(rate, wall_rate);
    if (advective_rate > 0) consider(1.0 / advective_rate, "advection");
    if (cfg.time.viscous == ViscousScheme::Explicit) {
        real mu_max = 0;
        for_each_cell(dec.block().cells,
                      [&](int i, int j, int k) { mu_max = std::max(mu_max, s.mu(i, j, k)); });
        mu_max = dec.max(mu_max);
        real inv = 0;
        for (int d = 0; d < g.dim; ++d)
            inv += 1.0 / (g.dx(d) * g.dx(d));
        consider(cfg.fluid.density / (2 * mu_max * inv), "viscous");
    }
    real fmag = 0, hmin = inf;
    for (int d = 0; d < g.dim; ++d) {
        fmag += cfg.body_force[d] * cfg.body_force[d];
        hmin = std::min(hmin, g.dx(d));
    }
    if (fmag > 0) consider(std::sqrt(hmin * cfg.fluid.density / std::sqrt(fmag)), "body force");
    for (const TimeStepLimit& l : extra)
        if (l.dt > 0) consider(l.dt, l.name.c_str());
    // The split VOF advection of bodies needs every face Courant number below 1/2: cap it
    // at 0.45 whatever time.cfl is (the limit is divided by cfl, which multiplies below).
    if (!cfg.bodies.empty() && advective_rate > 0) {
        real speed = std::max(out.max_speed, 0.0);
        for (int d = 0; d < 3; ++d)
            for (int side = 0; side < 2; ++side)
                for (int c = 0; c < g.dim; ++c)
                    speed = std::max(speed, std::abs(cfg.boundaries[d][side].velocity[c]));
        if (speed > 0) consider(0.45 * hmin / speed / cfg.time.cfl, "vof courant");
    }

    real dt = cfg.time.fixed_dt > 0 ? cfg.time.fixed_dt : cfg.time.cfl * best;
    if (cfg.time.fixed_dt > 0) out.limited_by = "fixed";
    if (cfg.time.fixed_dt == 0 && cfg.time.dt_max > 0 && dt > cfg.time.dt_max) {
        dt = cfg.time.dt_max;
        out.limited_by = "dt_max";
    }
    if (!std::isfinite(dt))
        throw InputError("time: no stability limit bounds the step (fluid at rest, no forcing, "
                         "implicit viscosity); set time.dt or time.dt_max");
    // Land exactly on the end time instead of overshooting it.
    const real remaining = cfg.time.end_time - s.time;
    if (dt > remaining && remaining > 0) {
        dt = remaining;
        out.limited_by = "end time";
    }
    out.dt = dt;
    out.cfl = dt * advective_rate;
    return out;
}

} // namespace efsi
