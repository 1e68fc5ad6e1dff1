// Gs in a membrane's band: kept near the surface, copied outward along the normals.
//
// Gs stands for the stretch of one surface, the membrane at phi = 1/2, but it is stored in
// every cell of a band some 12 eps thick. Transported on its own in every cell, the band's
// layers drift away from the surface's strain (the outer band, where the outside fluid
// shears past, ran away to tr Gs ~ 100 in the 3D capsule at Ca 0.2; docs/verification.md).
// After each step, therefore (closest-point extension, Ruuth & Merriman 2008; the strategy
// of the public Basilisk re-implementation of the Ii et al. method):
//   - core, |psi| <= core (cells): the transported Gs is kept, projected on the tangent
//     plane of phi, Gs <- P Gs P (P = I - n n): a tangential tensor, as the membrane's is;
//   - band, core < |psi| <= reach: Gs(x) <- P(x) Gs(y) P(x), y = x - psi n the foot point on
//     phi = 1/2, Gs(y) interpolated (trilinear) from the values of the step; the band
//     never holds a strain that the surface does not have;
//   - elsewhere on the patch (beyond the band, or where psi is not a distance,
//     |grad psi|^2 < 1/4): Gs <- I (no elastic memory; the force is not evaluated there).
// psi = eps atanh(1 - 2 phi) (positive outside), n = grad psi / |grad psi| by central
// differences. The interpolation reads cells up to ceil(reach) + 1 cells away (the reference
// map's cubic stencil; trilinear: ceil(reach)), so the copy it reads carries ceil(reach) + 2
// halo layers: every rank's block must be that wide. At a patch's own edge (no neighbour)
// only kEdgeLayers of them are filled: the foot points lie on the surface, well inside.
#pragma once

#include "bodies/body.hpp"
#include "bodies/body_work.hpp"
#include "boundary/boundary.hpp"
#include "grid/field.hpp"

#include <array>
#include <string>
#include <vector>

namespace efsi {

class Shape;

class NormalExtension {
  public:
    /// `eps_cells`: the smoothing width of phi in cells; `core_cells`: half-thickness of the
    /// core in cells; `reach_cells`: |psi| (cells) up to which Gs is extended (default: the
    /// band's edge, |psi| = eps atanh(1 - 2e-5) = 5.75 eps, plus 2 cells for the force's and
    /// the transport's stencils). Throws InputError (naming `body_name`) when a rank's block
    /// is too thin for the interpolation's halo.
    /// `cubic_map`: the reference map is interpolated at the foot points by the tensor-product
    /// 4-point Lagrange interpolant (otherwise trilinear, as Gs always is).
    /// `area_filter` (reference map): J of the rebuilt strain low-passed over the valid cells
    /// near the surface, every band cell's Gs rescaled to the J at its foot point.
    /// `newton_foot`: the foot point and the distance the map's gradient is corrected for
    /// are psi / |grad psi| along the normal (one Newton step onto phi = 1/2, exact where psi
    /// is a distance times a constant), not psi: a drawn-out profile (|grad psi| < 1) then
    /// still finds its surface (docs/method.md, "What tears the trailing rim").
    NormalExtension(const HaloFiller& halos, const std::string& body_name, real eps_cells,
                    real core_cells, real reach_cells = -1, bool cubic_map = true,
                    bool area_filter = false, bool newton_foot = false);

    /// Replace Gs on the body's patch as described above; fills Gs's halos. Collective; a
    /// BodyWork that waits at its halo fills (bodies/body_work.hpp).
    BodyWork apply(Body& body);
    /// strain_model = reference_map: extend the body's reference map X from the core along
    /// the normals (X(x) = X(y), y the foot point; kept beyond the band), then set Gs from
    /// its gradient taken along the surface (membrane/reference_map.hpp) near the surface
    /// (|psi| <= core + 2 cells) and extend that Gs over the band as apply() does. `whole_band`:
    /// extend the core too (the initial state, X = x: then X = x - psi n, the closest point, in the
    /// whole band). With `reference` (map_projection), every band cell's X is then put onto
    /// that shape's surface (onto_reference_surface) before Gs is formed. With the area
    /// filter, the area ratio J of the Gs formed near the surface is low-passed and each band
    /// cell's Gs rescaled to the J at its foot point. Collective.
    void apply_reference_map(Body& body, bool whole_band = false, const Shape* reference = nullptr);

    real core_cells() const { return core_cells_; }
    real reach_cells() const { return reach_cells_; }

    /// The default reach for a smoothing width of `eps_cells` cells.
    static real default_reach(real eps_cells);

    /// The halo layers of the wide copies filled at a patch's own edges (no neighbour across
    /// it): the foot points lie on the surface, which the patch keeps its margin and the
    /// smoothed profile's tails away from such an edge, and the cubic stencil reads two
    /// points beyond its base (HaloFiller::fill's `edge_layers`; docs/method.md, "The wide
    /// copies' edges").
    static constexpr int kEdgeLayers = 3;

  private:
    /// apply() with a core of `core_cells`; with `weight`, Gs holds w Gs and the copy is
    /// the mean over the cells with w = 1 of each foot point's stencil; with `area` (w J), each
    /// copy is rescaled to the mean J over those cells.
    /// `psi_current`: psi_ and psi_wide_ already hold this phi's (an earlier prepare() of the
    /// same call, phi unchanged since), so prepare() copies the fields only.
    BodyWork apply_tensor(Body& body, real core_cells, const Field* weight = nullptr,
                          const Field* area = nullptr, bool psi_current = false);
    /// psi and a wide-halo copy of `fields` (src_). Only on a rank with a part of the patch
    /// (the callers return first on an empty one).
    /// `psi_current`: see apply_tensor.
    BodyWork prepare(Body& body, const std::vector<const Field*>& fields, bool psi_current = false);
    /// The trilinear stencil at x: the index (in src_'s layout) of its low corner and the
    /// weights of its points, x fastest.
    struct Trilinear {
        std::size_t corner = 0;
        std::array<real, 8> weight{};
    };
    Trilinear trilinear_at(const Real3& x) const;
    /// x along d in the block's cell units, 0 at its first owned cell's centre (the
    /// interpolations' stencils start at floor of it).
    real cell_coordinate(real x, int d) const;
    /// Whether a foot point lies on the surface: |psi| there (trilinear, from the wide-halo
    /// copy of psi that prepare() keeps in psi_wide_) at most kFootTolerance cells. Off it
    /// where the normal at the cell is not the distance's: a thin body's middle, where the
    /// two faces' profiles meet and psi's gradient turns. Measured on field snapshots
    /// (verification/records/capsule_longtime/foot_points.py): d/16 Ca 0.05 at t = 20, every
    /// band cell's foot within 0.30 cells (99.9th percentile 0.24); d/16 Ca 0.2 at t = 15.8,
    /// 137 of 8832 beyond 0.5 (up to 3.2), all deep inside (phi > 0.998).
    bool foot_on_surface(const Trilinear& at) const;
    static constexpr real kFootTolerance = 0.5;
    /// Trilinear interpolant of a src_ field at the stencil's point.
    real interpolate(const Field& f, const Trilinear& at) const;
    /// Tensor-product 4-point Lagrange interpolant of a src_ field at x.
    real interpolate_cubic(const Field& f, const Real3& x) const;
    /// psi (s) and unit normal at p; false beyond the reach or where psi is not a distance.
    /// `gradient`: |grad psi| there.
    bool normal_at(const Int3& p, real& s, Real3& n, real& gradient) const;
    /// The distance from p's centre to its foot point along -n: psi, or psi / |grad psi|
    /// (newton_foot).
    real foot_distance(real s, real gradient) const { return newton_foot_ ? s / gradient : s; }
    /// The foot point x - d n of the cell at x: d = foot_distance(), or psi where that
    /// point's stencil (`half` = 1: trilinear, 2: cubic) would leave the copy's filled cells
    /// (the Newton distance psi / |grad psi| can be up to twice the reach, |grad psi| >= 1/2,
    /// where the wide halo holds one reach); `to_foot` is set to the d taken. A point whose
    /// stencil leaves the filled cells even so is moved, along each axis, onto the last one
    /// whose stencil is filled: at a patch's edge without neighbour only kEdgeLayers are
    /// filled, and a band cell's psi reaches further only where psi is far from a distance.
    Real3 foot_point(const Real3& x, real s, const Real3& n, real gradient, int half,
                     real& to_foot) const;

    const HaloFiller& halos_;
    real eps_cells_;
    real core_cells_;
    real reach_cells_;
    bool cubic_map_;
    bool area_filter_;
    bool newton_foot_;
    int wide_halo_;
    /// The cells of the wide copies filled by prepare() (block-local, inclusive): the wide
    /// halo across a neighbour's boundary, kEdgeLayers at the patch's own edges.
    std::array<int, 3> filled_lo_{}, filled_hi_{};
    Field psi_;                 ///< eps atanh(1 - 2 phi), halo 1
    std::vector<Field> src_;    ///< Gs (or X - x) after the transport, wide halos
    Field psi_wide_;            ///< psi with the wide halo (foot points are checked on it)
    Field valid_;               ///< reference map: 1 where Gs from X is valid, else 0
    Field area_ratio_;          ///< area_filter: J of the rebuilt Gs on valid cells, halo 1
    Field filtered_area_ratio_; ///< area_filter: its low-passed value on valid cells
};

} // namespace efsi
