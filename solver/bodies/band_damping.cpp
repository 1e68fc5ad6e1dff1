#include "bodies/band_damping.hpp"

#include "bodies/body_physics.hpp"
#include "bodies/body_system.hpp"

#include <algorithm>

namespace efsi {

void membrane_damping_weight(const BodySystem& bodies, const HaloFiller& halos, Field& w) {
    w.fill(0);
    for (std::size_t i = 0; i < bodies.bodies().size(); ++i) {
        const Body& b = *bodies.bodies()[i];
        if (bodies.physics()[i]->config().kind != BodyKind::Membrane || b.patch().empty()) continue;
        const Field& phi = b.phi();
        for_each_in(phi.owned(), [&](int x, int y, int z) {
            const real f = phi(x, y, z);
            w(x, y, z) = std::min(real(1), w(x, y, z) + 4 * f * (1 - f));
        });
    }
    halos.fill(w); // collective: every rank, also one that holds no membrane
}

} // namespace efsi
