// Visco-hyperelastic solids in the one-fluid formulation (Sugiyama et al. 2011):
//
//   sigma = -p I + 2 mu(x) D + sum_k phi_k G_k B_k',   mu(x) = mu_f + sum_k phi_k (mu_s,k - mu_f)
//
// (D is traceless for incompressible flow, so D' = D.) The viscous part goes to the flow
// step as the viscosity field mu(x) (implicit Laplacian + explicit transpose term); the
// elastic part is the force density div(phi G B') on the velocity faces, discretised with
// the same stencils as the viscous stress: normal components from the two cells beside a
// face, shear components on cell edges as the mean of the four cells around the edge.
// In 2D (plane strain) B' = B - tr(B)/3 I with B_zz = 1.
#pragma once

#include "bodies/body.hpp"
#include "config/body_config.hpp"
#include "grid/field.hpp"

#include <vector>

namespace efsi {

struct SolidLaw {
    real shear_modulus = 0; ///< G [Pa]
    real viscosity = 0;     ///< mu_s [Pa s]
};

/// mu(x) = mu_f + sum_k phi_k (mu_s,k - mu_f) over the owned cells (halos are filled by
/// the flow step). `bodies` and `laws` pair up; bodies without a law are skipped.
void update_mixture_viscosity(Field& mu, real fluid_viscosity,
                              const std::vector<const Body*>& bodies,
                              const std::vector<SolidLaw>& laws);

/// Add div(phi G B') of one solid body to the face force density `force` [N/m^3], over the
/// faces its patch touches. phi's and B's patch halos must be filled.
void add_elastic_force(VelocityField& force, const Body& body, const SolidLaw& law,
                       const GlobalGrid& grid, const LocalBlock& block);

/// Step limit of the explicit (AB2) elastic force, the smallest over the solids of
///   max(min(dx) / (2 sqrt(G / rho)), min(mu_f, mu_s) / G)   (0 if no solid has a G):
/// the shear-wave limit (its factor 1/2 the measured margin of AB2 for weakly damped waves)
/// or, where viscosity damps every mode the grid holds, the viscous-relaxation limit
/// G dt / mu <= 1, under which the AB2 force with the Crank-Nicolson viscous term is stable
/// for every wavenumber and any density (docs/method.md, "Solids in the time step").
real elastic_time_step_limit(const GlobalGrid& grid, real density, real fluid_viscosity,
                             const std::vector<SolidLaw>& laws);

} // namespace efsi
