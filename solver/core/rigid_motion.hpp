// A rigid-body motion (translation with `velocity`, rotation with `spin` about `centre`, held
// constant over a step) and a rigid load (a force and a torque). The adhesion coupling moves a
// stiff platelet's receptors with the rigid motion fitted to the flow over the platelet
// (bodies/rigid_fit.hpp; docs/method.md, "Receptors move with the platelet").
#pragma once

#include "core/matrix3.hpp"
#include "core/types.hpp"

#include <cmath>

namespace efsi {

struct RigidMotion {
    Real3 centre{};   ///< point the rotation is about [m]
    Real3 velocity{}; ///< velocity of `centre` [m/s]
    Real3 spin{};     ///< angular velocity [1/s]

    /// Where the point x is after dt: centre + velocity dt + R(spin dt) (x - centre), the
    /// rotation by the angle |spin| dt about spin (Rodrigues' formula), so that distances
    /// between moved points are kept to round-off however many steps are taken.
    Real3 move(const Real3& x, real dt) const {
        const Real3 r{x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]};
        const real w = std::sqrt(spin[0] * spin[0] + spin[1] * spin[1] + spin[2] * spin[2]);
        Real3 rr = r;
        if (w * dt > 0) {
            const Real3 k{spin[0] / w, spin[1] / w, spin[2] / w};
            const real c = std::cos(w * dt), s = std::sin(w * dt);
            const real kr = k[0] * r[0] + k[1] * r[1] + k[2] * r[2];
            const Real3 kxr = cross(k, r);
            for (int a = 0; a < 3; ++a)
                rr[a] = r[a] * c + kxr[a] * s + k[a] * kr * (1 - c);
        }
        Real3 out;
        for (int a = 0; a < 3; ++a)
            out[a] = centre[a] + velocity[a] * dt + rr[a];
        return out;
    }
};

/// A force and a torque on a rigid body (the sum of the bond forces on its receptors).
struct RigidLoad {
    Real3 point{};  ///< point the torque is taken about [m]
    Real3 force{};  ///< [N]
    Real3 torque{}; ///< about `point` [N m]
    bool empty() const {
        for (int a = 0; a < 3; ++a)
            if (force[a] != 0 || torque[a] != 0) return false;
        return true;
    }
};

} // namespace efsi
