// Receptors on a body's initial surface (a sphere or an ellipsoid: the platelet as an
// oblate spheroid), placed uniformly in area and deterministically from the seed.
//
// Receptor k of a body has the global id first_id + k. Its position is drawn by rejection
// with counter-based numbers (counter_rng.hpp, purposes `place` and `place_accept`, the
// attempt number as the counter's step): a point p uniform on the unit sphere is mapped to
// x = centre + R diag(a, b, c) p and kept with probability g(p) / max g, where
// g(p) = sqrt((b c p_x)^2 + (a c p_y)^2 + (a b p_z)^2) is the ratio of the ellipsoid's area
// element to the sphere's. The kept points are uniform in area on the ellipsoid. A
// receptor's position is a pure function of (seed, id, shape): the same on every rank, for
// any rank count, whichever receptors other ranks place.
#pragma once

#include "adhesion/receptor.hpp"
#include "interface/shapes.hpp"

#include <cstdint>
#include <vector>

namespace efsi::adhesion {

/// The surface receptors are placed on: x = centre + rotation diag(semi_axes) p, |p| = 1.
struct SurfaceEllipsoid {
    Real3 centre{};
    Real3 semi_axes{}; ///< a, b, c along the body axes [m]
    Matrix3 rotation = identity_rotation();
};

/// Surface area [m^2] of the ellipsoid with these semi-axes: the integral of g over the unit
/// sphere by the midpoint rule in cos(theta) (2048 points) and the periodic trapezoid rule
/// in phi (256 points); relative error below 1e-6 for axis ratios up to 10 (tested against
/// the sphere and the closed form of the spheroids).
real ellipsoid_area(const Real3& semi_axes);

/// `count` receptors with ids first_id .. first_id + count - 1, all free. Throws
/// InputError for non-positive semi-axes or ids beyond the counter layout.
std::vector<Receptor> place_receptors(const SurfaceEllipsoid& surface, std::uint64_t count,
                                      std::uint64_t first_id, std::uint64_t seed);

} // namespace efsi::adhesion
