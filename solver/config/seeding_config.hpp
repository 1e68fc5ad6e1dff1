// The case file's [seeding] section: cells placed at random in a vessel's lumen to a target
// haematocrit (bodies/seeding.hpp), expanded into ordinary [[body]] entries while the case
// is read, before anything is allocated. The scene is a function of the case file only
// (the seed and the keys), so every rank expands the same bodies, on any rank count.
//
//   [seeding]
//   vessel = "wall"               # a [[body]] of shape "tube": its lumen is the region
//   target_haematocrit = 0.2      # volume of the fill kind's cells / lumen volume
//   seed = 2026
//   [[seeding.kind]]              # one per kind of cell
//   name = "rbc"                  # the bodies are rbc_0, rbc_1, ...
//   fill = true                   # this kind fills to the target (or: count = 3)
//   [seeding.kind.body]           # its [[body]] keys, but name, centre, axis and angle
//   kind = "membrane"
//   shape = "biconcave"
//   ...
#pragma once

#include "config/body_config.hpp"
#include "grid/grid.hpp"

#include <toml++/toml.h>

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace efsi {

class TableReader;

/// What the seeding did, for the log and summary.json (used = false without [seeding]).
struct SeedingReport {
    bool used = false;
    std::uint64_t seed = 0;
    std::string vessel;
    std::string fill_kind; ///< the kind whose volume fraction is the haematocrit ("" none)
    real target = 0;       ///< target haematocrit
    real achieved = 0;     ///< placed volume of the fill kind / lumen volume
    real lumen_volume = 0; ///< [m^3] pi R^2 L of the vessel's lumen
    real gap = 0;          ///< [m] clearance kept between cells and to the wall
    std::int64_t candidates = 0;
    std::int64_t shake_sweeps = 0;                   ///< Monte Carlo sweeps spent opening space
    std::vector<std::pair<std::string, int>> placed; ///< per kind: its name and count
    std::string message;                             ///< one line: what was placed
};

/// Read [seeding] (documenting its keys when the catalogue documents) and append the bodies
/// it places to `bodies` and, as [[body]] tables, to `root` (which loses its [seeding]
/// table, so the resolved case is the explicit scene). A target that cannot be reached is
/// an InputError saying what was reached.
/// `length_unit` labels lengths in the messages.
SeedingReport expand_seeding(toml::table& root, TableReader& top, const GlobalGrid& grid,
                             const std::array<bool, 3>& periodic, std::vector<BodyConfig>& bodies,
                             std::string_view length_unit = "m");

/// The axis and angle of a rotation matrix (the inverse of axis_angle_rotation; angle in
/// [0, pi], axis (0, 0, 1) for the identity).
void rotation_axis_angle(const Matrix3& r, Real3& axis, real& angle);

} // namespace efsi
