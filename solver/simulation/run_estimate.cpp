#include "simulation/run_estimate.hpp"

#include "bodies/body_system.hpp"
#include "membrane/membrane_body.hpp"
#include "membrane/membrane_force.hpp"
#include "membrane/membrane_law.hpp"
#include "parallel/decomposition.hpp"
#include "solid/solid_mechanics.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace efsi {

namespace {

// Measured on the development machine, one rank (docs/performance.md, "Estimates before a
// run"; verification/tests/test_estimate_rates.py checks these against the stored results):
// - the flow with FFT solves: the throughput study's 3D Taylor-Green at 128^3, one rank
//   (verification/results/throughput: cell_updates_per_second_1rank_128, bytes_per_cell);
constexpr double FLOW_SECONDS_FFT = 1 / 2.88e+07;
constexpr double FLOW_BYTES_PER_CELL = 189;
// - the process's base and the flow's bytes per cell with hypre's viscous solve (a pinned
//   vessel wall): the plasma alone at 64 x 32 x 32 and 128 x 64 x 64 cells, the intercept
//   and slope of peak RSS against cells; the flow's seconds with hypre and the bodies'
//   patch cells: the blood_capillary study's runs at 128 x 64 x 64
//   (verification/results/blood_capillary: rate_*), each run's copies across the periodic
//   x seam taken out of its memory (they are counted on their own: seam_copy_bytes).
constexpr double PROCESS_BYTES = 4.04e+07;
constexpr double FLOW_BYTES_PER_CELL_HYPRE = 1130;
constexpr double FLOW_SECONDS_HYPRE = 1.29e-06;
constexpr double HELD_BYTES = 11; // phi alone: 8 B per cell plus the patch's halo
constexpr double SOLID_BYTES = 411;
constexpr double SOLID_SECONDS = 1.01e-06;
constexpr double MEMBRANE_BYTES = 706;
constexpr double MEMBRANE_SECONDS = 2.73e-07;

} // namespace

CostRates measured_rates() {
    // The development machine (2 cores, Debian bookworm), one rank, from
    // the summary.json of the runs named (peak RSS, stage timers, steps, patch_cells);
    // docs/performance.md, "Estimates before a run", gives the derivation.
    CostRates r;
    r.process_bytes = PROCESS_BYTES;
    r.flow_bytes_per_cell = FLOW_BYTES_PER_CELL;
    r.flow_bytes_per_cell_hypre = FLOW_BYTES_PER_CELL_HYPRE;
    r.flow_seconds_fft = FLOW_SECONDS_FFT;
    r.flow_seconds_hypre = FLOW_SECONDS_HYPRE;
    r.held_bytes_per_patch_cell = HELD_BYTES;
    r.solid_bytes_per_patch_cell = SOLID_BYTES;
    r.solid_seconds_per_patch_cell = SOLID_SECONDS;
    r.membrane_bytes_per_patch_cell = MEMBRANE_BYTES;
    r.membrane_seconds_per_patch_cell = MEMBRANE_SECONDS;
    return r;
}

Real3 initial_patch_widths(const BodyConfig& b, const GlobalGrid& g) {
    const Real3 ext = body_half_extent(b, g.dim);
    Real3 widths{1, 1, 1};
    for (int d = 0; d < g.dim; ++d) {
        const double h = g.dx(d);
        if (ext[d] < 0) {
            widths[d] = g.cells[d];
            continue;
        }
        // The smoothed profile is cut where phi < 1e-8, 9.2 eps out; a sharp one in its cells.
        const double tail = b.interface == InterfaceKind::Smoothed ? 9.2 * b.smoothing_width : 1;
        const double n = std::ceil(2 * (ext[d] / h + tail + b.margin));
        widths[d] = std::min(double(g.cells[d]), n);
    }
    return widths;
}

double initial_patch_cells(const BodyConfig& b, const GlobalGrid& g) {
    const Real3 w = initial_patch_widths(b, g);
    return w[0] * w[1] * w[2];
}

double seam_copy_bytes(const Config& cfg, const Int3& ranks_per_dim) {
    const GlobalGrid& g = cfg.grid;
    if (!periodic_directions(cfg.boundaries)[0] || ranks_per_dim[0] != 1) return 0;
    int widest = -1;
    for (const BodyConfig& b : cfg.bodies) {
        const int w = int(initial_patch_widths(b, g)[0]);
        if (may_cross_seam(cfg, b) && w < g.cells[0]) widest = std::max(widest, w);
    }
    if (widest < 0) return 0;
    // A crossing patch reaches past the seam by less than its width.
    const double hx = seam_halo_cells(widest, g.cells[0]);
    const int halo = 2; // the velocity's and the force's y and z halos
    double values = g.cells[0] + 2 * hx;
    for (int d = 1; d < g.dim; ++d)
        values *= double(g.cells[d]) / ranks_per_dim[d] + 2 * halo;
    return 2.0 * g.dim * values * sizeof(real);
}

RunEstimate estimate_run(const Config& cfg, int ranks, const CostRates& r) {
    const GlobalGrid& g = cfg.grid;
    RunEstimate e;
    e.cells = double(g.total_cells());
    double limit = std::numeric_limits<double>::infinity();
    auto take = [&](double dt, const std::string& name) {
        if (dt > 0 && dt < limit) {
            limit = dt;
            e.dt_limit = name;
        }
    };
    const real rho = cfg.fluid.density, mu = cfg.fluid.viscosity;
    for (const BodyConfig& b : cfg.bodies) {
        const double p = initial_patch_cells(b, g);
        if (b.pinned || b.kind == BodyKind::Passive) {
            e.held_patch_cells += p;
        } else if (b.kind == BodyKind::Solid) {
            e.solid_patch_cells += p;
            const real mu_s = b.solid_viscosity_or(mu);
            take(elastic_time_step_limit(g, rho, mu, {SolidLaw{b.shear_modulus, mu_s}}),
                 fmt::format("elastic, body '{}'", b.name));
        } else {
            e.membrane_patch_cells += p;
            const real mu_m = b.membrane_damping_viscosity(mu) + increment_viscosity(cfg);
            const auto law = make_membrane_law(b.law, b.elastic_modulus, b.area_dilation);
            take(membrane_time_step_limit(g, rho, mu_m, law->stiffest_modulus()),
                 fmt::format("membrane, body '{}'", b.name));
            take(bending_time_step_limit(g, rho, mu_m, b.bending_modulus),
                 fmt::format("bending, body '{}'", b.name));
        }
    }
    if (cfg.time.fixed_dt > 0) {
        e.dt = cfg.time.fixed_dt;
        e.dt_limit = "time.dt";
    } else {
        e.dt = std::isfinite(limit) ? cfg.time.cfl * limit : 0;
        if (cfg.time.dt_max > 0 && (e.dt == 0 || cfg.time.dt_max < e.dt)) {
            e.dt = cfg.time.dt_max;
            e.dt_limit = "time.dt_max";
        }
    }
    const LinearSolverChoice solvers = choose_linear_solvers(cfg);
    const double flow_rate = solvers.viscous_fft ? r.flow_seconds_fft : r.flow_seconds_hypre;
    const double flow_bytes =
        solvers.viscous_fft ? r.flow_bytes_per_cell : r.flow_bytes_per_cell_hypre;
    e.seam_copy_bytes_per_rank =
        seam_copy_bytes(cfg, Decomposition::choose_ranks(ranks, g, cfg.ranks));
    e.bytes_per_rank = r.process_bytes + e.seam_copy_bytes_per_rank +
                       (e.cells * flow_bytes + e.held_patch_cells * r.held_bytes_per_patch_cell +
                        e.solid_patch_cells * r.solid_bytes_per_patch_cell +
                        e.membrane_patch_cells * r.membrane_bytes_per_patch_cell) /
                           ranks;
    e.seconds_per_step =
        (e.cells * flow_rate + e.solid_patch_cells * r.solid_seconds_per_patch_cell +
         e.membrane_patch_cells * r.membrane_seconds_per_patch_cell) /
        ranks;
    if (e.dt > 0) {
        e.seconds_per_unit_time = e.seconds_per_step / e.dt;
        e.seconds_to_end = e.seconds_per_unit_time * cfg.time.end_time;
    }
    return e;
}

std::string describe(const RunEstimate& e, const Config& cfg, int ranks) {
    std::string s = fmt::format(
        "# estimate on {} rank(s) (rates measured on the development machine, one rank, "
        "scaled ideally; docs/performance.md \"Estimates before a run\"):\n"
        "#   memory {:.3g} GB per rank ({:.3g} M cells; body patches {:.3g} M cells of "
        "membranes, {:.3g} M of solids, {:.3g} M held; {:.3g} GB of copies across the "
        "periodic x seam)\n",
        ranks, e.bytes_per_rank / 1e9, e.cells / 1e6, e.membrane_patch_cells / 1e6,
        e.solid_patch_cells / 1e6, e.held_patch_cells / 1e6, e.seam_copy_bytes_per_rank / 1e9);
    if (e.dt > 0)
        s += fmt::format("#   step {:.3g} ({}); {:.3g} s per step, {:.3g} s per unit of "
                         "simulated time, {:.3g} h to time.end_time = {:g} (at least: the "
                         "flow's advection limit may shorten the step)\n",
                         e.dt, e.dt_limit, e.seconds_per_step, e.seconds_per_unit_time,
                         e.seconds_to_end / 3600, cfg.time.end_time);
    else
        s += fmt::format("#   {:.3g} s per step; no body limits the step, so the cost per unit "
                         "of time depends on the flow's limits\n",
                         e.seconds_per_step);
    return s;
}

} // namespace efsi
