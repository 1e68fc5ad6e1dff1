// All the bodies of a run: created from the case's [[body]] sections, each with the physics
// of its kind (bodies/body_physics.hpp), carried by the flow, kept on patches that follow
// them, and measured. Every method is collective (all ranks call it).
#pragma once

#include "bodies/body.hpp"
#include "bodies/body_physics.hpp"
#include "boundary/boundary.hpp"
#include "config/config.hpp"
#include "time/stage_timers.hpp"
#include "time/time_step_control.hpp"

#include <memory>
#include <string>
#include <vector>

namespace efsi {

/// Whether body `b`'s patch may cross the periodic x seam as one unwrapped box (docs/method.md,
/// "Patches across the seam"): a moving body whose kernels read and write only the flow's
/// velocity and force. Then the bodies work through copies of those two fields with a deep x
/// halo (BodySystem::seam_copy_bytes; `efsi check` counts them).
bool may_cross_seam(const Config& config, const BodyConfig& b);
/// The x halo (cells) of the seam copies for patches reaching `past` cells beyond the seam on a
/// periodic x of `n` cells: the kernels' reach past a patch (its fields' 2 halo cells and a
/// face) added, rounded up to 8 so that a copy is reallocated only when the patches reach
/// further, at most n.
int seam_halo_cells(int past, int n);

struct BodyDiagnostics {
    std::string name;
    real volume = 0;         ///< sum phi dV [m^3]
    Real3 centroid{0, 0, 0}; ///< sum phi x dV / volume [m]; across a periodic seam by the minimum
                             ///< image, reported inside the box
    real phi_min = 0, phi_max = 0;
    std::int64_t patch_cells = 0; ///< cells of the body's patch (all ranks)
    std::int64_t bytes = 0;       ///< memory of the body's fields (all ranks)
    real clipped_volume = 0;      ///< VOF clipping of the last step [m^3]
    real area = 0;                ///< integral of |grad phi| [m^2] (perimeter x dz in 2D)
    /// Taylor deformation D = (L - B)/(L + B) in the x-y (shear) plane and the inclination
    /// of L to x over pi, from the second moments of phi about the centroid: for an
    /// ellipsoid with one principal axis along z they are proportional to the squared
    /// semi-axes, so L, B = the square roots of the eigenvalues of their x-y block.
    real taylor_deformation = 0;
    real inclination_over_pi = 0;
    /// The same D of the body bounded by phi = 1/2: phi replaced by a ramp one cell wide
    /// across that level, chi = clamp(1/2 + (phi - 1/2) / (h |grad phi|), 0, 1). Once the
    /// flow has carried a smoothed profile, its tails are no longer a function of the distance
    /// to the surface and their moments bias D; chi ignores the tails, so this D is the
    /// phi = 1/2 surface's (docs/method.md, "Measuring D").
    real taylor_deformation_sharp = 0;
    /// Largest tr(B) over the cells with phi > 0 (solid; 3 at rest) or tr(Gs) over the
    /// membrane's band 1e-5 < phi < 1 - 1e-5 (2 at rest in 3D and 2D); 0 without a tensor.
    /// Bounded in a steady deformation (docs/method.md, Solids).
    real tensor_trace_max = 0;
    /// Membranes: the area the stored strain implies for the unstrained membrane, the
    /// integral of |grad phi| / J(Gs) over the band (J = sqrt of Gs's second invariant, the
    /// local area ratio). Constant in time when Gs stays consistent with the surface it sits
    /// on; its drift is strain lost or gained by the numerics (a creeping reference shape).
    /// 0 for other bodies.
    real reference_area = 0;
};

class BodySystem {
  public:
    BodySystem(const Config& config, const Decomposition& dec, const HaloFiller& halos);
    ~BodySystem();

    /// phi from each body's shape or mask, then each body's own initial state (tensors).
    void initialise();
    /// Carry every body by the face velocity u (halos filled) over dt.
    void advance(const VelocityField& u, real dt, long step, StageTimers& timers);
    /// Re-fit every patch to its body (after initialisation, restart, or motion).
    void track_patches(bool force = false);

    /// mu(x) = mu_f + sum_k phi_k (mu_k - mu_f) on the owned cells.
    void update_viscosity(Field& mu) const;
    /// Whether some body's material viscosity differs from the fluid's.
    bool viscosity_varies() const;
    /// Whether some body adds a force to the flow.
    bool adds_force() const;
    /// Zero `force`, then add every body's force density to it (body after body).
    void add_forces(VelocityField& force);
    /// Add every fixed wall's phi / (tau / dt) to `chi`; returns whether there is one.
    bool add_pinning(Field& chi) const;
    /// The bodies' explicit time-step limits, one per name (the smallest over the bodies).
    std::vector<TimeStepLimit> time_step_limits() const;

    std::vector<BodyDiagnostics> measure() const;
    /// This rank's bytes held by the copies of the velocity and the force across the periodic
    /// x seam (0 until a patch first crosses it; they only grow, so this is the run's peak).
    std::size_t seam_copy_bytes() const;
    /// Largest time step the VOF advection accepts: 0.45 min(dx) / max|u| (0 = no limit).
    static real vof_time_step_limit(const GlobalGrid& g, real max_speed);

    std::vector<std::unique_ptr<Body>>& bodies() { return bodies_; }
    const std::vector<std::unique_ptr<Body>>& bodies() const { return bodies_; }
    /// physics()[i] is the physics of bodies()[i].
    const std::vector<std::unique_ptr<BodyPhysics>>& physics() const { return physics_; }
    bool empty() const { return bodies_.empty(); }

  private:
    /// This rank's part of the box of the cells with phi above the VOF's epsilon, as
    /// {-lo, hi} per direction in out[0..6) (track_patches reduces every body's at once).
    void occupied_extent(const Body& b, real* out) const;
    /// Zero this rank's residues (phi <= epsilon, which never move) farther than one cell
    /// from `occ` and return their sum. track_patches then puts the dropped volume back on
    /// the band, phi += c phi (1 - phi): a moving body stores no trail, whatever its patch or
    /// the rank layout.
    real drop_local(Body& body, const Box& occ) const;
    /// drop_local for the bodies `tracked` (occupied boxes `occ`), their dropped volumes
    /// put back on their bands, phi += c phi (1 - phi), or counted as clipped where a body
    /// has no band (collective).
    void drop_residues(const std::vector<std::size_t>& tracked, const std::vector<Box>& occ);
    /// Body i's phi on a box that certainly holds it (initialise() then fits the patch).
    void initialise_body(std::size_t i);
    /// For the tracked bodies whose patch covers the whole of a periodic x although they may
    /// cross the seam: their occupied x range as the shortest periodic interval holding their
    /// occupied columns, unwrapped (lo in [0, n)), in place of occ's (collective).
    void unwrap_occupied(const std::vector<std::size_t>& tracked, std::vector<Box>& occ) const;

    // The periodic seam (docs/method.md, "The periodic seam"): a patch that crosses it indexes
    // x past [0, n); its kernels read the velocity and write the force there, in copies of
    // the flow's fields whose x halo reaches past every such patch.
    /// Whether some body's patch crosses the seam now.
    bool any_crosses_seam() const;
    /// The x halo (cells) the seam copies need for the patches as they are now.
    int seam_halo() const;
    /// u, or its seam copy (x halo seam_halo(), filled across the seam) when a patch crosses.
    const VelocityField& seam_velocity(const VelocityField& u);
    /// The field the bodies add their forces to: `force`, or the zeroed seam copy.
    VelocityField& seam_force(VelocityField& force);
    /// Fold the seam copy's x halo back onto the faces it images and copy it into `force`
    /// (nothing when the bodies added to `force` itself).
    void fold_seam_force(VelocityField& force);

    const Config& cfg_;
    const Decomposition& dec_;
    const HaloFiller& halos_;
    std::vector<std::unique_ptr<Body>> bodies_;
    std::vector<std::unique_ptr<BodyPhysics>> physics_;
    /// Carries the membranes' Gs with their surfaces' velocities; one for all bodies (null:
    /// no body uses it).
    std::unique_ptr<SurfaceVelocity> surface_velocity_;
    std::vector<std::size_t> surface_velocity_bodies_; ///< the bodies that compute with it
    std::vector<real> clipped_;
    /// Whether body i's patch may cross the periodic x seam (a moving body whose kernels read
    /// and write only the velocity and the force; the others keep the whole of x there).
    std::vector<char> cross_seam_;
    VelocityField seam_u_, seam_force_; ///< the seam copies (allocated when first needed)
    bool force_in_copy_ = false;        ///< the last seam_force() gave the copy
};

} // namespace efsi
