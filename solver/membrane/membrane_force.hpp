// The membrane's force on the fluid, |grad phi| f, as a force density on velocity faces.
//
// Continuum (MODEL.md): f = (P.grad).tau_s - (P.grad).(q n) (in-plane tension, and the
// transverse shear q of bending when the body has a bending modulus; the sign of the
// bending term is the energy-consistent one, see docs/method.md "Membrane bending"),
// carried by a smoothed delta.
//
// Form chosen: the CONSERVATIVE form F = div(S), S = |grad phi| tau_s.
// Why it is the same force: with delta = |grad phi|, div(delta tau_s) = delta div(tau_s)
// + tau_s.grad(delta), and grad(delta) is parallel to n while tau_s n = 0, so the second
// term vanishes. And div(tau_s) = (P.grad).tau_s for a tangential tensor whenever
// (n.grad) n = 0 (n constant along normal lines, as for the normal of the distance-like
// psi): n_k n_l d_l tau_ik = (n.grad)(tau_ik n_k) - tau_ik (n.grad) n_k = 0. Hence
// F = div(|grad phi| tau_s) = |grad phi| (P.grad).tau_s.
// Why this form discretely: (1) the net force is zero to round-off (the divergence
// telescopes), as the exact load of a closed membrane; (2) it is the adjoint of the
// discrete velocity gradient, sum_faces F.w dV = -sum S : grad_h w dV, a discrete
// virtual-work statement, so the power the force puts into the flow is that of the tension
// on the discrete strain rate; (3) across the band the integral of F along a normal is
// the jump of S-fluxes, so it carries the traction jump without needing the pointwise
// value of f (which is O(1) wrong when the band is a fixed number of cells wide).
//
// Discretisation: S at cell centres in the band (see band_cutoff; only there is the
// tension evaluated); the staggered divergence on the low d-face of cell p,
//   F_d(p) = [S_dd(p) - S_dd(p - e_d)] / h_d
//          + sum_{k != d} [S_dk(p + e_k) + S_dk(p + e_k - e_d) - S_dk(p - e_k)
//                          - S_dk(p - e_k - e_d)] / (4 h_k)
// (the off-diagonal part is the k-difference of S_dk averaged to the two edges of the
// face), applied as a scatter from the band cells, so no work is done outside the band.
//
// Bending (docs/method.md, "Membrane bending"): with psi = eps atanh(2 phi - 1),
//   n = grad psi / |grad psi|,  kappa = -P H P / |grad psi|  (H = Hessian of psi),
//   m = Eb (kappa - kappa_R P_b),  q = P [(P.grad).m],  S_b = -delta_b n q^T,
// F_d += sum_k d_k (S_b)_dk by the same staggered scatter. kappa is the curvature tensor of
// the level surface of psi through the cell, (P.grad).m the derivative along that level
// surface, so by the coarea formula the band force is the delta-weighted average over the
// level surfaces of their own bending loads. delta_b is a cosine kernel in psi of
// half-width `bending_width` cells (or the tension's |grad phi|), times |grad psi|.
#pragma once

#include "bodies/body.hpp"
#include "bodies/body_work.hpp"
#include "bodies/symmetric_tensor.hpp"
#include "boundary/boundary.hpp"
#include "interface/geometry.hpp"
#include "membrane/membrane_law.hpp"

#include <array>
#include <vector>

namespace efsi {

struct MembraneForceSettings {
    /// Gradient stencil for n and |grad phi|; Distance differences psi = eps atanh(2phi-1).
    GradientStencil stencil = GradientStencil::Distance;
    /// eps of phi's tanh profile in cells (eps = smoothing_width * dx).
    real smoothing_width = 1.0;
    /// The band: cells whose whole gradient stencil (the 3^dim block around them) has
    /// band_cutoff < phi < 1 - band_cutoff. Outside it phi is cut (< 1e-8 is set to 0 by
    /// the body system) or saturated, psi = eps atanh(2 phi - 1) is not the distance, and
    /// a wrong normal there would make Bs = P Gs P degenerate (J -> 0, tension ~ 1/J^3)
    /// even where the delta is tiny. The delta mass left out is ~ 4 band_cutoff. 1e-5, not
    /// smaller: after VOF advection the far tail (phi ~ 1e-7) is no longer an exact tanh
    /// profile and its normals are noise (a translated capsule blew up with 1e-7); 1e-4
    /// doubled the force error at 128 cells across, 1e-5 leaves it unchanged.
    real band_cutoff = 1e-5;
    /// With the distance stencil, band cells also need |grad psi| >= this. psi =
    /// eps atanh(2 phi - 1) is a distance (|grad psi| = 1) wherever phi is the tanh profile
    /// of one surface; where it is not (tails sheared off the tips and advected away,
    /// the overlap of the two sides of a capsule a few eps thick) |grad psi| falls well
    /// below 1, the normal of phi is not the material normal that Gs carries (in the
    /// continuum Gs n = 0 for the normal of any material level set), so P Gs P can lose
    /// rank (J -> 0, neo-Hookean tension ~ 1/J^3) even where phi > band_cutoff. Measured
    /// in the d/8 Ca 0.2 shear run that blew up at t = 2.9: every cell with J < 0.5 had
    /// |grad psi| < 0.71, the blow-up cell 0.35 (phi = 1.3e-4, J: 0.17 -> 0). 1/2 keeps
    /// the band cells of a resolved profile (|grad psi| = 1 + O(h^2)). The case key
    /// body.min_distance_gradient sets it (docs/method.md, "What tears the trailing rim").
    real min_distance_gradient = 0.5;
    /// Band cells also need J(P Gs P) >= this times J(Gs), J(Gs) = sqrt of the second
    /// invariant of Gs: the normal of phi must be (close to) a normal of the material
    /// surface whose stretch Gs carries. In a resolved band the ratio is 1 - O(h^2)
    /// (measured >= 0.55, 1st percentile 0.78, in the d/16 Ca 0.2 shear run at t = 2).
    /// Where it is not, P Gs P loses rank and the tension (~ 1/J^3) blows up: VOF debris
    /// far from the capsule (phi ~ 2e-3, |grad psi| ~ 0.5 > min_distance_gradient, at
    /// x = +-3.1 with the capsule in |x| < 1.6) had J(P Gs P) ~ 0 with J(Gs) ~ 2 and
    /// stopped the d/8 Ca 0.2 run at t = 6.0 (velocity 1e147 within one step).
    real min_normal_consistency = 0.5;
    /// Band cells also need J(Gs) >= this: Gs must be an admissible stretch (positive
    /// definite on the surface). In the d/16 Ca 0.2 shear run at t = 7.76, cells in a tail
    /// (phi ~ 7e-5, x = -2.3, beyond the tip) carried an indefinite Gs (Gs_xx = -0.08,
    /// J(Gs)^2 < 0) that passed the consistency test and blew the run up; how such a Gs
    /// survives the extension is not yet understood (docs/verification.md).
    real min_area_ratio = 0.1;

    /// Bending modulus Eb [N m] (J); 0: no bending (no bending fields, no bending work).
    real bending_modulus = 0;
    /// Kernel spreading the bending load: `Cosine` (1 + cos(pi psi / w)) / (2 w) |grad psi|
    /// for |psi| < w, w = bending_width cells, or `Profile`, the tension's |grad phi|
    /// (truncated where the stencil leaves the band).
    enum class BendingKernel { Cosine, Profile } bending_kernel = BendingKernel::Cosine;
    real bending_width = 2.0;
};

/// Explicit bending time-step limit (0 without bending): the larger of the viscous and the
/// inertial bending-wave limits, mu h^3 / Eb and sqrt(rho h^5 / (2 pi Eb)) (docs/method.md,
/// "Membrane bending": Stokes relaxation rate Eb k^3 / (4 mu) of a bending mode at the
/// band's largest wavenumber k = 4^(1/3) / h; the 2D capsule blew up at 3.7 mu h^3 / Eb and
/// ran at 2.4, so the automatic dt, cfl x this, keeps a margin of ~5 at cfl = 0.5).
real bending_time_step_limit(const GlobalGrid& grid, real density, real viscosity, real eb_max);

/// Membrane stress S = |grad phi| tau_s at cell p (zero outside the band).
/// Pointwise kernel: phi needs valid values at p and its 3^dim neighbours.
Matrix3 membrane_stress_at(const Field& phi, const SymmetricTensorField& Gs, const MembraneLaw& law,
                           const GlobalGrid& g, const MembraneForceSettings& s, const Int3& p,
                           bool& in_band);

class MembraneForce {
  public:
    MembraneForce(const GlobalGrid& g, const HaloFiller& halos, MembraneForceSettings settings);

    /// Add the force density |grad phi| f of membrane `body` (law `law`) to the face
    /// field `force` (whole block or any field covering the body's patch, same indices)
    /// on the faces of the patch's owned cells: prepare, run now, then scatter.
    void add(Body& body, const MembraneLaw& law, VelocityField& force);

    /// The force's work on the body's own fields: fills phi's, Gs's (and kappa_R's) halos,
    /// computes S on the band and, with bending, the transverse shear q (whose halos it
    /// fills). A BodyWork (bodies/body_work.hpp): the time loop runs it for all membranes
    /// in rounds of halo fills.
    BodyWork prepare(Body& body, const MembraneLaw& law);
    /// Add the force density of the last prepare() to `force` (tension, then bending):
    /// no halo fill, so the time loop adds the bodies' forces body after body.
    void scatter(const Body& body, VelocityField& force) const;

    /// S = |grad phi| tau_s of the last call, on the patch (owned cells and one halo layer).
    const SymmetricTensorField& stress() const { return stress_; }
    /// Number of cells (owned plus one halo layer) in the band at the last call.
    std::size_t band_cells() const { return band_.size(); }
    /// Owned cells that carried a bending load at the last call, and those inside the
    /// kernel whose stencil left the band (their load is dropped; 0 when the band is wide
    /// enough for the kernel).
    std::size_t bending_cells() const { return bending_cells_; }
    std::size_t bending_dropped() const { return bending_dropped_; }

  private:
    void allocate(const Patch& patch);
    BodyWork prepare_bending(Body& body);
    void scatter_bending(const Body& body, VelocityField& force) const;

    GlobalGrid g_;
    const HaloFiller& halos_;
    MembraneForceSettings settings_;
    SymmetricTensorField stress_;
    Box stress_box_{};
    std::vector<Int3> band_;
    /// |grad psi| (isotropic) of each band_ cell, from bending's pass A for its pass B.
    std::vector<real> band_grad_;
    // Pass-1 scratch on the patch plus two layers: stencil values (psi or phi) and band flags.
    std::vector<real> work_value_;
    std::vector<unsigned char> work_ok_, work_tmp_;
    // Bending scratch (allocated only when bending_modulus > 0), on the patch:
    Field psi_;              ///< eps atanh(2 phi - 1), halo 2
    Field band_mask_;        ///< 1 on band cells, halo 1
    SymmetricTensorField m_; ///< bending moment, halo 1
    std::array<Field, 3> n_; ///< unit normal on band cells, halo 1
    std::array<Field, 3> q_; ///< delta_b q (transverse shear times the kernel), halo 1
    std::size_t bending_cells_ = 0, bending_dropped_ = 0;
};

} // namespace efsi
