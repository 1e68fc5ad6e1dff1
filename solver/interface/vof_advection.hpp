// Conservative VOF advection of a body volume fraction phi by the face velocity.
//
// One step is `dim` one-dimensional sweeps (direction order x-y-z on even steps, z-y-x on
// odd steps, so the splitting error of consecutive steps cancels to leading order). The
// sweep in direction d (Courant numbers c = u_d dt / dx_d on the faces, G the signed volume
// fraction crossing a face in +d, taken from the THINC reconstruction in the upwind cell):
//
//     phi^(d) = phi^(d-1) - (G_{i+1/2} - G_{i-1/2}) + chi (c_{i+1/2} - c_{i-1/2}),
//
// where the last term adds back the 1D compression phi div_d u that the split flux form
// wrongly produces for a solenoidal u. chi is frozen over the whole step at
// chi = 1 if phi^n >= 1/2 else 0 (Weymouth & Yue, JCP 229 (2010) 2853): because the
// same chi multiplies every sweep, the corrections of one step add to chi dt div u = 0 in
// each cell, so the scheme is exactly conservative for a discretely solenoidal u (the
// fluxes telescope), and full cells stay exactly full (their in- and out-fluxes equal c).
// Ii et al. (2012) use the intermediate phi in this term instead, which conserves
// volume only up to the splitting error; we prefer exact conservation.
//
// Bounds: with exact integrals of a reconstruction bounded by [0,1] and |c| < 1/2,
// each sweep maps [0,1] into [0,1]. MTHINC's Gauss quadrature in the transverse
// directions breaks the exactness slightly, so after each sweep phi is clipped to [0,1];
// the clipped volume and the largest excursion are returned so that runs report them.
#pragma once

#include "boundary/boundary.hpp"
#include "core/types.hpp"
#include "grid/field.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace efsi {

enum class VofScheme {
    Thinc1D, ///< 1D THINC in each sweep (baseline)
    Mthinc,  ///< multidimensional THINC: planar tanh along the Youngs normal
};

VofScheme parse_vof_scheme(const std::string& name);
std::string to_string(VofScheme s);

struct VofOptions {
    VofScheme scheme = VofScheme::Mthinc;
    /// 1D THINC sharpness (Xiao et al. 2005 recommend 3.5; jump width ~ 2/beta cells).
    real beta_thinc = 3.5;
    /// MTHINC sharpness along the normal, in unit-cell coordinates.
    real beta_mthinc = 2.0;
    /// Cells with phi <= eps are empty (no outflux: a residue stays put) and cells with
    /// phi >= 1 - eps are full (upwind flux).
    real epsilon = 1e-8;
    /// Clip phi to [0,1] after each sweep (see the header comment).
    bool clip = true;
    /// Run the sweeps the way they ran before the row sweeps (per face through the
    /// pointwise kernels, mthinc_reconstruct then mthinc_box_integral): the reference the
    /// row sweeps are tested and measured against. Same results, only slower.
    bool pointwise = false;
};

/// What one step did, reduced over ranks.
struct VofStepStats {
    real min_before_clip = 0; ///< smallest phi produced by the sweeps
    real max_before_clip = 1; ///< largest phi produced by the sweeps
    real clipped_volume = 0;  ///< sum |phi_clipped - phi| dV over the sweeps
    real max_courant = 0;     ///< largest |u_d| dt / dx_d met
};

class VofAdvection {
  public:
    VofAdvection(const HaloFiller& halos, const VofOptions& options);

    /// Advance phi by dt with the face velocity u. On entry phi's and u's halos must be
    /// filled; on exit phi's halos are filled. `step` selects the sweep order. Throws
    /// RunError when a Courant number reaches 1/2. When phi lives on a body's patch, pass
    /// the patch: the sweeps then cover only the patch (collective: every rank calls it,
    /// also those whose part of the patch is empty).
    VofStepStats advance(Field& phi, const VelocityField& u, real dt, std::int64_t step,
                         const Patch* patch = nullptr);

    /// advance() without its reductions: returns this rank's statistics, to be passed to
    /// reduce(). Many bodies advance their phi with advance_local one after the other and
    /// reduce afterwards, so that ranks holding different bodies do not wait for each
    /// other at every body (the patch halo exchanges stay per body: they are collective
    /// only among the ranks a patch spans).
    VofStepStats advance_local(Field& phi, const VelocityField& u, real dt, std::int64_t step,
                               const Patch* patch = nullptr);

    /// advance_local in parts, for many bodies at once (BodySystem::advance): start() once,
    /// then for s = 0 .. dim - 1 sweep_step(s) followed by the fill of phi's halos, which
    /// the caller does for every body together (HaloFiller's fill of many patch fields), so
    /// that a rank waits for its neighbours once per sweep, not once per body and sweep.
    /// The same arithmetic as advance_local, which is start, then each sweep and its fill.
    VofStepStats start(Field& phi, const Patch* patch);
    void sweep_step(Field& phi, const VelocityField& u, real dt, std::int64_t step, int s,
                    const Patch* patch, VofStepStats& local);

    /// Global statistics from every rank's local ones (collective). Throws RunError when
    /// a Courant number reached 1/2.
    static VofStepStats reduce(const Decomposition& dec, const VofStepStats& local);

    const VofOptions& options() const { return opt_; }

  private:
    /// One sweep in direction d; returns (min, max, clipped amount) locally. phi's halos
    /// are left for the caller to fill.
    void sweep(Field& phi, const VelocityField& u, real dt, int d, const Patch* patch,
               VofStepStats& local);
    /// The same sweep as rows along d with plain pointers (the default).
    void sweep_rows(Field& phi, const VelocityField& u, real dt, int d, const Patch* patch,
                    VofStepStats& local);

    const HaloFiller& halos_;
    VofOptions opt_;
    Field chi_;  ///< Weymouth-Yue indicator of phi^n
    Field flux_; ///< G on the low d-faces of the current sweep
    /// The MTHINC faces of one row, gathered for mthinc_slab_integrals: the face index
    /// along the row, the upwind phi, its gradient, the Courant number, the slab integral.
    struct MthincFaces {
        std::vector<int> face;
        std::vector<real> phi, courant, integral;
        std::vector<Real3> grad;
    } row_faces_;
};

/// sum phi dV over the owned cells, reduced over ranks.
real total_volume(const Decomposition& dec, const Field& phi);

} // namespace efsi
