// Case-file description of platelet adhesion: the [adhesion] table (kinetics parameters,
// seed, the coupling's step limit), its [[adhesion.ligand_regions]] (vWF on wall boxes) and
// [[adhesion.receptors]] (GPIb-alpha on a body's surface). docs/method.md, "Platelet
// adhesion", has the model, the defaults and their sources.
//
// Everything is checked here, before any allocation, with errors naming the key: negative
// rates or stiffness, a ligand region outside the domain,
// receptors on a body that is not a free solid sphere/ellipsoid (the platelet), a 2D grid.
// Without an [adhesion] table `enabled` is false and the vectors stay empty (no memory).
#pragma once

#include "adhesion/ligand.hpp"
#include "adhesion/parameters.hpp"
#include "adhesion/placement.hpp"
#include "config/body_config.hpp"
#include "grid/grid.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace efsi {

class TableReader;

/// Receptors on one body's initial surface.
struct ReceptorGroupConfig {
    std::string body;           ///< name of a [[body]] of kind "solid", not pinned
    std::size_t body_index = 0; ///< its index in Config::bodies
    std::uint64_t count = 0;    ///< receptors (given, or density x surface area rounded)
    real density = 0;           ///< [1/m^2] as given; 0 when `count` was given
};

/// How the receptors move between steps (docs/method.md, "Receptors move with the platelet").
enum class ReceptorMotion : std::uint8_t {
    flow, ///< each with the flow interpolated at its position (the default)
    rigid ///< with the rigid motion fitted to the flow over their body, loading it rigidly
};

struct AdhesionConfig {
    bool enabled = false; ///< an [adhesion] table is present
    ReceptorMotion receptor_motion = ReceptorMotion::flow;
    adhesion::AdhesionParameters parameters;
    std::uint64_t seed = 1;
    /// Largest distance [cells] a bond's force may move its receptor in one step (the
    /// per-bond force limit of the coupling, docs/method.md).
    real max_step_displacement = 0.5;
    std::vector<adhesion::LigandRegion> ligand_regions; ///< spacing = 1 / sqrt(density)
    std::vector<real> ligand_density;                   ///< [1/m^2] per region, as given
    std::vector<ReceptorGroupConfig> receptors;
};

/// Read and check [adhesion] against the grid and the bodies. With `check_receptor_bodies`
/// false the receptors' bodies are not looked up (a first pass before the seeding has placed
/// the bodies they name: every other key is checked at once).
AdhesionConfig read_adhesion(TableReader& top, const GlobalGrid& grid,
                             const std::vector<BodyConfig>& bodies,
                             bool check_receptor_bodies = true);

/// The initial surface of a body that carries receptors (a sphere or an ellipsoid, with the
/// body's orientation). Throws InputError for other shapes.
adhesion::SurfaceEllipsoid receptor_surface(const BodyConfig& b);

/// The adhesion lines of the case fingerprint (empty when adhesion is off, so cases and
/// checkpoints without adhesion keep their fingerprint).
std::string adhesion_fingerprint(const AdhesionConfig& a);

} // namespace efsi
