// A test scene of the kinetics alone: n receptors, each facing its own ligand at the bond
// length `length` along z, the pairs `pitch` apart on a square lattice in the wall plane
// z = 0 (pitch much larger than the reactive distance, so each receptor reaches only its
// own ligand). With the receptors held still, every bond carries the constant force
// sigma (length - lambda) and the pairs are independent: the closed forms of the
// platelet_adhesion study and of tests/adhesion apply.
#pragma once

#include "adhesion/ligand.hpp"
#include "adhesion/receptor.hpp"

#include <cmath>
#include <vector>

namespace efsi::adhesion {

struct FacingPairs {
    std::vector<Receptor> receptors;
    LigandSet ligands;
};

/// Receptor k has id first_id + k; ligand k is the one it faces. With `bound` every pair
/// starts bonded.
inline FacingPairs make_facing_pairs(std::size_t n, real length, real pitch, real cell,
                                     bool bound = false, std::uint64_t first_id = 0) {
    FacingPairs s;
    const auto side = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<real>(n))));
    std::vector<Real3> sites;
    sites.reserve(n);
    s.receptors.reserve(n);
    for (std::size_t k = 0; k < n; ++k) {
        const Real3 y{pitch * static_cast<real>(k % side), pitch * static_cast<real>(k / side), 0};
        sites.push_back(y);
        s.receptors.push_back({first_id + k, {y[0], y[1], length}, bound ? k : no_ligand});
    }
    s.ligands = LigandSet::from_sites(std::move(sites), cell);
    if (bound)
        for (std::size_t k = 0; k < n; ++k)
            s.ligands.bind(k, first_id + k);
    return s;
}

} // namespace efsi::adhesion
