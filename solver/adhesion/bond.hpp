// A receptor-ligand bond as a linear spring: length l = |x_ligand - x_receptor|, tension
// T = sigma (l - lambda) (positive when stretched), force on the receptor T (x_l - x_r) / l
// (pulled towards the ligand when stretched) and exactly the opposite on the ligand, so a
// bond's two forces sum to zero bit for bit: momentum is conserved by construction. The flow
// coupling (not built yet) spreads the receptor's force onto the platelet's interface band
// and the ligand's onto the wall.
#pragma once

#include "adhesion/ligand.hpp"
#include "adhesion/parameters.hpp"
#include "adhesion/receptor.hpp"

#include <span>
#include <vector>

namespace efsi::adhesion {

struct BondForce {
    Real3 on_receptor{}; ///< [N]
    Real3 on_ligand{};   ///< [N], = -on_receptor
    real tension = 0;    ///< sigma (l - lambda) [N]
    real length = 0;     ///< l [m]
};

/// The spring force of a bond between a receptor at xr and a ligand at xl. At l = 0 the
/// direction is undefined and the force is zero (tension still reported).
BondForce bond_force(const Real3& xr, const Real3& xl, real stiffness, real rest_length);

/// One bond's load, for the coupling.
struct BondLoad {
    std::uint64_t receptor = 0;
    std::uint64_t ligand = 0;
    Real3 receptor_x{};
    Real3 ligand_x{};
    BondForce force;
};

/// The loads of every bond of `receptors`, appended to `out` (which is left untouched when no
/// receptor is bound). Throws RunError naming the receptor, the ligand, where they are and
/// the force when a bond's force exceeds p.max_bond_force (the time step's limit).
void bond_loads(std::span<const Receptor> receptors, const LigandSet& ligands,
                const AdhesionParameters& p, std::vector<BondLoad>& out);

} // namespace efsi::adhesion
