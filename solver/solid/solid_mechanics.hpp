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

/// Explicit membrane force limit (0 without membranes): the larger of the viscous and the
/// inertial capillary-type limits, 4 mu h / K and sqrt(rho h^3 / (2 pi K)), K the stiffest
/// small-strain modulus of the laws in the scene (MembraneLaw::stiffest_modulus; Es for the
/// neo-Hookean law). Galusinski & Vigneaux 2008 show the stable step follows the viscous one
/// at low Re and the inertial one, Brackbill et al. 1992, at high Re. The factor 4 is
/// measured (docs/method.md, "Membranes in the time step"): at Re = 0.01 the neo-Hookean
/// capsule runs stably up to 8 mu h / Es (2D d/16, Ca 0.002: 12 mu h / Es blows up; 3D d/8
/// Ca 0.0125 and d/16 Ca 0.0125 stable at 8 mu h / Es), so with cfl = 0.5 the automatic step
/// 2 mu h / K keeps a margin of 4 while D(t) changes by < 5e-4.
real membrane_time_step_limit(const GlobalGrid& grid, real density, real viscosity, real es_max);

/// Step limit for the elastic shear waves: min(dx) / (2 sqrt(G_max / rho)) (0 if none);
/// the factor 1/2 is the measured margin of the explicit (AB2) elastic force.
real elastic_time_step_limit(const GlobalGrid& grid, real density,
                             const std::vector<SolidLaw>& laws);

} // namespace efsi
