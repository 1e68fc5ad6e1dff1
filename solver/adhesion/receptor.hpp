// A receptor (GPIb-alpha) on a platelet's surface: a global id (the key of its random
// stream, so it must be the same on every rank), a position carried with the surface, and
// the ligand it is bound to, if any.
#pragma once

#include "core/types.hpp"

#include <cstdint>
#include <limits>

namespace efsi::adhesion {

inline constexpr std::uint64_t no_ligand = std::numeric_limits<std::uint64_t>::max();

struct Receptor {
    std::uint64_t id = 0; ///< unique over the run, < 2^56 (counter_rng.hpp)
    Real3 x{};            ///< position [m]
    std::uint64_t ligand = no_ligand;

    bool bound() const { return ligand != no_ligand; }
};

} // namespace efsi::adhesion
