// What a run will need before it starts (`efsi check --ranks N`): memory per rank and wall
// time per unit of simulated time, from the case alone (nothing is allocated).
//
// Memory and work are counted as the solver lays them out (docs/method.md, "Bodies: storage
// only where a body is"): the flow's fields on every cell, each body's on its patch (its
// bounding box, the smoothed profile's tails and the margin). They are turned into bytes and
// seconds by rates measured on the development machine (measured_rates(), with their
// source), so the estimate is that machine's: scale the seconds by the ratio of memory
// bandwidths. The step is the smallest of the bodies' limits times time.cfl (or the fixed
// time.dt, capped by time.dt_max); the flow's own advection limit, which depends on the flow
// to come, may shorten it, so the cost is a lower bound. Work is divided evenly over the
// ranks (ideal scaling).
#pragma once

#include "config/config.hpp"

#include <string>

namespace efsi {

/// Bytes per cell and seconds per cell and step (peak RSS and stage timers of runs on
/// the development machine, one rank).
struct CostRates {
    double process_bytes = 0;             ///< per rank: MPI, hypre, FFTW, the libraries
    double flow_bytes_per_cell = 0;       ///< constant-coefficient (FFT) solves
    double flow_bytes_per_cell_hypre = 0; ///< viscous solve by hypre (its matrices, PFMG levels)
    double flow_seconds_fft = 0;          ///< per cell and step, constant-coefficient (FFT) solves
    double flow_seconds_hypre = 0;        ///< per cell and step, viscous solve by hypre
    double held_bytes_per_patch_cell = 0; ///< a pinned or passive body: phi (and chi)
    double solid_bytes_per_patch_cell = 0;
    double solid_seconds_per_patch_cell = 0; ///< per step
    double membrane_bytes_per_patch_cell = 0;
    double membrane_seconds_per_patch_cell = 0; ///< per step
};

/// The rates measured for efsi on the development machine (values and source in the .cpp).
CostRates measured_rates();

struct RunEstimate {
    double cells = 0;
    double held_patch_cells = 0, solid_patch_cells = 0, membrane_patch_cells = 0;
    /// The bodies' copies of the velocity and the force across the periodic x seam (part of
    /// bytes_per_rank; 0 when no body may cross it or x is split over the ranks).
    double seam_copy_bytes_per_rank = 0;
    double bytes_per_rank = 0;
    double dt = 0;        ///< [time unit of the case]
    std::string dt_limit; ///< which limit sets it
    double seconds_per_step = 0;
    double seconds_per_unit_time = 0;
    double seconds_to_end = 0;
};

/// Patch cells of one body at its start (its bounding box, tails and margin, cut to the grid).
double initial_patch_cells(const BodyConfig& b, const GlobalGrid& g);
/// The same box's width in cells along each direction.
Real3 initial_patch_widths(const BodyConfig& b, const GlobalGrid& g);

/// Bytes per rank of the seam copies (bodies/body_seam.cpp) once some body's patch crosses
/// the periodic x seam: two copies (velocity, force) of every velocity component over the
/// rank's y-z block with their halos and over the whole of x with an x halo of the widest
/// crossing patch plus 4 cells, rounded up to 8 (BodySystem::seam_halo; a crossing patch
/// reaches past the seam by less than its width). 0 when x is not periodic, is split over
/// the ranks (`ranks_per_dim`), or no body may cross (may_cross_seam).
double seam_copy_bytes(const Config& cfg, const Int3& ranks_per_dim);

RunEstimate estimate_run(const Config& cfg, int ranks, const CostRates& rates = measured_rates());

/// The lines `efsi check` prints.
std::string describe(const RunEstimate& e, const Config& cfg, int ranks);

} // namespace efsi
