// Physical boundary conditions per face of the box, and the one call that fills halos.
//
// Every face of the box is periodic, a no-slip wall (possibly moving tangentially, for
// shear flow) or a free-slip wall. Walls are impermeable: the normal velocity on the
// wall face is zero. Ghost values mirror the interior so that the second-order stencils
// see the boundary value exactly on the wall:
//   tangential velocity, no-slip/moving:  u_ghost = 2 U_wall - u_mirror (odd about U_wall)
//   tangential velocity, free-slip:       u_ghost = u_mirror            (even)
//   normal velocity (any wall):           u_wall_face = 0, u_ghost = -u_mirror
//   cell scalars (pressure, phi, ...):    zero normal gradient, s_ghost = s_mirror
#pragma once

#include "bodies/patch.hpp"
#include "core/types.hpp"
#include "grid/field.hpp"
#include "parallel/decomposition.hpp"

#include <array>
#include <limits>
#include <span>
#include <string>

namespace efsi {

enum class BoundaryType { Periodic, Wall, FreeSlip };

struct FaceBoundary {
    BoundaryType type = BoundaryType::Periodic;
    Real3 velocity{0, 0, 0}; ///< wall velocity [m/s] (tangential only), for Wall
    real frequency = 0;      ///< angular frequency [rad/s]: velocity * sin(frequency t); 0 = steady
    /// time [s] from which the wall stands still (velocity 0); infinity = never
    real stop_time = std::numeric_limits<real>::infinity();

    /// Wall velocity component c at time t.
    real velocity_at(int c, real t) const;
};

/// [direction][side]: side 0 is the low face (x = origin), side 1 the high face.
using BoxBoundaries = std::array<std::array<FaceBoundary, 2>, 3>;

std::string to_string(BoundaryType t);

inline Bool3 periodic_directions(const BoxBoundaries& bc) {
    return {bc[0][0].type == BoundaryType::Periodic, bc[1][0].type == BoundaryType::Periodic,
            bc[2][0].type == BoundaryType::Periodic};
}

/// Fills every halo of a field in one call: neighbour exchange and periodic wrap through
/// the decomposition, then the physical boundary rule of each wall face.
class HaloFiller {
  public:
    HaloFiller(const Decomposition& decomposition, const BoxBoundaries& boundaries)
        : dec_(decomposition), bc_(boundaries) {}

    /// Scalar at cell centres: zero normal gradient at walls.
    void fill(Field& f) const;
    /// Cell field on a body's patch: exchange where the patch continues on the
    /// neighbouring rank; elsewhere (patch edge or wall) mirror the owned values (zero
    /// normal gradient), which extends body fields into the halo.
    void fill(Field& f, const Patch& patch) const;
    /// fill(fields[q], *patches[q]) for several patch fields at once (say one per body):
    /// each direction's messages of all of them are posted before any is waited for
    /// (Decomposition::exchange_all), so a rank waits once per direction, not per field.
    /// Every rank must pass the fields in the same order.
    /// `edge_layers`: at a patch's own edge (no neighbour across it, a wall included) only
    /// the first `edge_layers` halo layers mirror the owned values; the deeper ones keep
    /// what they held (for wide halos whose readers need the neighbours' values but, at
    /// the patch's edge, only a stencil's width: NormalExtension). Negative (the default):
    /// every layer.
    void fill(std::span<Field* const> fields, std::span<const Patch* const> patches,
              int edge_layers = -1) const;
    /// Velocity: wall rules for normal and tangential components.
    void fill(VelocityField& v) const;
    /// Velocity, each component's halos along its own direction only, at the owned
    /// positions across it (the faces a divergence reads): one exchange per component, not
    /// one per component and direction. Those halos equal fill(v)'s; the others are left.
    void fill_normal(VelocityField& v) const;

    /// Time at which moving walls are evaluated (oscillating walls depend on it).
    void set_time(real t) { time_ = t; }
    real time() const { return time_; }

    const BoxBoundaries& boundaries() const { return bc_; }
    const Decomposition& decomposition() const { return dec_; }

    /// True when face index `i` (local, along the normal of component d) is a wall face
    /// whose velocity is fixed at zero (only the low wall face is owned).
    bool is_fixed_wall_face(int d, int i_local) const {
        return bc_[d][0].type != BoundaryType::Periodic && dec_.at_boundary(d, 0) && i_local == 0;
    }

  private:
    /// How ghosts mirror the interior across one wall face.
    enum class Mirror { Even, Odd, NormalFace };
    void apply_wall(Field& f, int d, int side, Mirror mirror, real wall_value) const;

    const Decomposition& dec_;
    BoxBoundaries bc_;
    real time_ = 0;
};

} // namespace efsi
