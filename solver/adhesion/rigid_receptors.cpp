// Receptors that move with their body (receptor_motion = rigid; docs/method.md, "Receptors
// that move with their platelet"): the Coupling members that move the receptors with the
// fitted rigid motions, keep them off the walls, and sum the bonds into rigid loads.
#include "adhesion/coupling.hpp"

#include "core/error.hpp"
#include "core/matrix3.hpp"

#include <cmath>
#include <stdexcept>

namespace efsi::adhesion {

void Coupling::add_to_load(RigidLoad& load, const Real3& x, const Real3& F) const {
    const Real3 y = image_near(x, load.point);
    const Real3 arm{y[0] - load.point[0], y[1] - load.point[1], y[2] - load.point[2]};
    const Real3 moment = cross(arm, F);
    for (int a = 0; a < 3; ++a) {
        load.force[a] += F[a];
        load.torque[a] += moment[a];
    }
}

void Coupling::carry_rigidly(std::span<const RigidMotion> motions, real dt) {
    if (!active_ || receptors_.empty()) return;
    if (motions.size() != bodies_.size())
        throw std::logic_error("Coupling::carry_rigidly: one motion per body with receptors");
    x_.resize(receptors_.size());
    const GlobalGrid& g = dec_->grid();
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        const BodyReceptors& b = bodies_[i];
        // The fitted centre, taken in the periodic image of the receptors' cloud.
        RigidMotion m = motions[i];
        m.centre = image_near(m.centre, {0.5 * (b.lo[0] + b.hi[0]), 0.5 * (b.lo[1] + b.hi[1]),
                                         0.5 * (b.lo[2] + b.hi[2])});
        for (std::size_t k = b.begin; k < b.end; ++k)
            x_[k] = m.move(receptors_[k].x, dt);
        // Non-penetration: a rigid body does not pass a no-slip wall. The fitted motion can
        // take its surface there (the flow in the gap, thinner than a cell, is not resolved):
        // the cloud is then lifted back along the wall's normal onto the wall.
        for (int a = 0; a < 3; ++a) {
            if (!no_slip_[a][0] && !no_slip_[a][1]) continue;
            std::size_t lo = b.begin, hi = b.begin;
            for (std::size_t k = b.begin; k < b.end; ++k) {
                if (x_[k][a] < x_[lo][a]) lo = k;
                if (x_[k][a] > x_[hi][a]) hi = k;
            }
            const real wall_lo = g.origin[a], wall_hi = g.origin[a] + g.length[a];
            std::size_t touching = b.end;
            real lift = 0, wall = 0;
            if (no_slip_[a][0] && x_[lo][a] < wall_lo) {
                lift = wall_lo - x_[lo][a];
                touching = lo;
                wall = wall_lo;
            } else if (no_slip_[a][1] && x_[hi][a] > wall_hi) {
                lift = wall_hi - x_[hi][a];
                touching = hi;
                wall = wall_hi;
            }
            if (touching == b.end) continue;
            for (std::size_t k = b.begin; k < b.end; ++k)
                x_[k][a] += lift;
            // Exactly on the wall: the contact the bond forces see (support_on_walls).
            x_[touching][a] = wall;
            stats_.wall_lift += std::abs(lift);
        }
    }
    place_moved();
}

void Coupling::support_on_walls(const BodyReceptors& b, RigidLoad& load) {
    const GlobalGrid& g = dec_->grid();
    for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
            if (!no_slip_[a][side]) continue;
            const real wall = g.origin[a] + side * g.length[a];
            const real inward = side == 0 ? 1.0 : -1.0;
            if (load.force[a] * inward >= 0) continue; // not pulled towards this wall
            // In contact: carry_rigidly put a receptor exactly on the wall.
            std::size_t on = b.end;
            for (std::size_t k = b.begin; k < b.end && on == b.end; ++k)
                if (receptors_[k].x[a] == wall) on = k;
            if (on == b.end) continue;
            // The wall pushes back at the contact point with the normal pull.
            Real3 support{0, 0, 0};
            support[a] = -load.force[a];
            add_to_load(load, receptors_[on].x, support);
            for (int c = 0; c < 3; ++c) {
                stats_.wall_support[c] += support[c];
                stats_.force_on_bodies[c] += support[c];
                stats_.reaction_on_walls[c] -= support[c];
            }
        }
}

} // namespace efsi::adhesion
