#include "solid/solid_mechanics.hpp"

#include "operators/flow_operators.hpp"

#include <algorithm>
#include <cmath>

namespace efsi {

void update_mixture_viscosity(Field& mu, real fluid_viscosity,
                              const std::vector<const Body*>& bodies,
                              const std::vector<SolidLaw>& laws) {
    mu.fill(fluid_viscosity);
    for (std::size_t k = 0; k < bodies.size(); ++k) {
        const Body& b = *bodies[k];
        if (b.patch().empty() || laws[k].viscosity == fluid_viscosity) continue;
        const real jump = laws[k].viscosity - fluid_viscosity;
        for_each_in(b.phi().owned(),
                    [&](int i, int j, int l) { mu(i, j, l) += b.phi()(i, j, l) * jump; });
    }
}

namespace {

/// phi G B'_ab at the centre of cell p.
inline real elastic_stress(const Body& b, real G, int a, int c, const Int3& p) {
    const SymmetricTensorField& B = b.tensor();
    real v = B.value(a, c, p);
    if (a == c) v -= (B.value(0, 0, p) + B.value(1, 1, p) + B.value(2, 2, p)) / 3.0;
    return b.phi()(p) * G * v;
}

} // namespace

void add_elastic_force(VelocityField& force, const Body& body, const SolidLaw& law,
                       const GlobalGrid& g, const LocalBlock& block) {
    if (body.patch().empty() || law.shear_modulus == 0) return;
    const real G = law.shear_modulus;
    const int dim = force.dim;
    const Box cells = body.phi().owned();
    for (int c = 0; c < dim; ++c) {
        // Faces of the patch's cells, including the high face of its last cell, within
        // the faces this rank owns (along x past the periodic seam too, for a patch that
        // crosses it: `force` is then the body system's seam copy).
        Box faces = cells;
        faces.hi[c] += 1;
        for (int d = 0; d < 3; ++d) {
            if (d == 0 && body.patch().crosses_seam()) continue;
            faces.lo[d] = std::max(faces.lo[d], 0);
            faces.hi[d] = std::min(faces.hi[d], block.cells[d]);
        }
        for_each_in(faces, [&](int i, int j, int k) {
            const Int3 p{i, j, k};
            real f = 0;
            for (int e = 0; e < dim; ++e) {
                if (e == c) {
                    f += (elastic_stress(body, G, c, c, p) -
                          elastic_stress(body, G, c, c, shifted(p, c, -1))) /
                         g.dx(c);
                } else {
                    // S_ce on the (c,e) edges of cells p + e_e and p: mean of four cells.
                    auto edge = [&](const Int3& q) {
                        const Int3 qc = shifted(q, c, -1);
                        return 0.25 * (elastic_stress(body, G, c, e, q) +
                                       elastic_stress(body, G, c, e, qc) +
                                       elastic_stress(body, G, c, e, shifted(q, e, -1)) +
                                       elastic_stress(body, G, c, e, shifted(qc, e, -1)));
                    };
                    f += (edge(shifted(p, e, 1)) - edge(p)) / g.dx(e);
                }
            }
            force[c](p) += f;
        });
    }
}

real elastic_time_step_limit(const GlobalGrid& g, real density, real fluid_viscosity,
                             const std::vector<SolidLaw>& laws) {
    real h = g.dx(0);
    for (int d = 1; d < g.dim; ++d)
        h = std::min(h, g.dx(d));
    real limit = 0;
    for (const auto& l : laws) {
        if (l.shear_modulus <= 0) continue;
        // Half the shear-wave CFL limit: AB2's stability region barely reaches the
        // imaginary axis, so undamped waves are held only by the viscosity; with h / c the
        // stiff parallel slab blew up at 1.5x the automatic dt (stability study), with
        // h / (2c) the automatic dt keeps a margin of 2 or more.
        const real waves = 0.5 * h / std::sqrt(l.shear_modulus / density);
        // Viscous relaxation: per Fourier mode, AB2 elasticity with Crank-Nicolson
        // viscosity (the elastic and viscous stresses share their stencils) is stable for
        // every wavenumber when G dt / mu <= 1; mu is the smaller of the two viscosities a
        // cell of the solid's interface mixes.
        const real relaxation = std::min(fluid_viscosity, l.viscosity) / l.shear_modulus;
        const real dt = std::max(waves, relaxation);
        limit = limit > 0 ? std::min(limit, dt) : dt;
    }
    return limit;
}

} // namespace efsi
