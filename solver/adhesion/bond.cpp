#include "adhesion/bond.hpp"

#include "core/error.hpp"

#include <fmt/core.h>

#include <cmath>

namespace efsi::adhesion {

BondForce bond_force(const Real3& xr, const Real3& xl, real stiffness, real rest_length) {
    BondForce b;
    const Real3 d{xl[0] - xr[0], xl[1] - xr[1], xl[2] - xr[2]};
    b.length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    b.tension = stiffness * (b.length - rest_length);
    if (b.length > 0) {
        const real s = b.tension / b.length;
        for (int a = 0; a < 3; ++a) {
            b.on_receptor[a] = s * d[a];
            b.on_ligand[a] = -b.on_receptor[a];
        }
    }
    return b;
}

void bond_loads(std::span<const Receptor> receptors, const LigandSet& ligands,
                const AdhesionParameters& p, std::vector<BondLoad>& out) {
    for (const Receptor& r : receptors) {
        if (!r.bound()) continue;
        if (r.ligand >= ligands.size())
            throw RunError(fmt::format("adhesion: receptor {} is bound to ligand {}, which "
                                       "does not exist ({} ligands)",
                                       r.id, r.ligand, ligands.size()));
        BondLoad load{
            r.id, r.ligand, r.x, ligands.position(r.ligand),
            bond_force(r.x, ligands.position(r.ligand), p.bond_stiffness, p.bond_rest_length)};
        if (std::abs(load.force.tension) > p.max_bond_force || !std::isfinite(load.force.tension))
            throw RunError(fmt::format(
                "adhesion: the bond of receptor {} at ({:g}, {:g}, {:g}) m with ligand {} at "
                "({:g}, {:g}, {:g}) m carries {:g} N (length {:g} m), above the time step's "
                "limit adhesion.max_bond_force = {:g} N",
                r.id, r.x[0], r.x[1], r.x[2], r.ligand, load.ligand_x[0], load.ligand_x[1],
                load.ligand_x[2], load.force.tension, load.force.length, p.max_bond_force));
        out.push_back(load);
    }
}

} // namespace efsi::adhesion
