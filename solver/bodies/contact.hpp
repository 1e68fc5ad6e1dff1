// Short-range repulsion between bodies (docs/method.md, "Contact between bodies").
//
// Each pair of bodies i, j whose patches meet gets equal and opposite forces
//   F_ij = -k sum_cells a_i grad(a_j) dV   on i,   F_ji = -F_ij   on j,
// a = phi averaged over the 3^dim cells around each cell (phi dilated by one cell, so the
// pair interacts once their interfaces come within about two cells), k the contact
// stiffness [Pa] (`contact.stiffness`). F_ij is the force of the interaction energy
// k sum a_i a_j dV under a rigid displacement of i; it points away from j. Each body's
// force is spread over its volume, f = phi_i F_i / V_i, so it moves the body as a whole
// (a force that is a gradient would only change the pressure). A body held in place (a
// fixed wall) takes no force; the cell against it is pushed off it.
#pragma once

#include "bodies/body.hpp"
#include "parallel/decomposition.hpp"

#include <vector>

namespace efsi {

struct ContactPairForce {
    int i = 0, j = 0;
    Real3 force_on_i{0, 0, 0}; ///< [N] (2D: per unit depth of the one cell)
};

/// The pair forces of every pair whose patches come within two cells (reduced over the
/// ranks; collective).
std::vector<ContactPairForce> contact_forces(const std::vector<const Body*>& bodies,
                                             const Decomposition& dec, real stiffness);

/// Add every moving body's share, phi_i F_i / V_i on the faces, to `force` (collective).
void add_contact_forces(const std::vector<const Body*>& bodies, const std::vector<bool>& held,
                        const Decomposition& dec, real stiffness, VelocityField& force);

} // namespace efsi
