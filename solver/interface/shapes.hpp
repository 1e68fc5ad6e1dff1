// Implicit body shapes and their exact (sub-sampled) cell volume fractions.
//
// A shape is an implicit function L(x), negative inside, zero on the surface. Shapes
// whose L is a lower bound of the distance to the surface (|L(x)| <= dist(x, surface),
// i.e. L is 1-Lipschitz) say so with `level_bounds_distance()`; then a cell whose centre
// has |L| > half its diagonal is certainly full or empty and is never sub-sampled. For the
// other shapes (the biconcave disc, whose thickness profile has an infinite slope at the
// rim) a cell is sub-sampled when the 3^dim lattice of its corners, edge/face midpoints
// and centre does not agree in sign, which misses only features thinner than half a cell.
//
// Every shape has a centre and an orientation (a rotation R whose columns are the body
// axes in the lab frame); L is evaluated in body coordinates y = R^T (x - centre).
#pragma once

#include "core/types.hpp"
#include "grid/field.hpp"
#include "grid/grid.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <string>

namespace efsi {

// Rotations are Matrix3 (core/types.hpp), row-major R[a][b]: the columns are the body axes
// in lab coordinates.

/// Identity orientation.
Matrix3 identity_rotation();
/// Rotation by `angle` [rad] about the (not necessarily unit) lab-frame `axis`.
Matrix3 axis_angle_rotation(const Real3& axis, real angle);

/// Newton steps onto the zero level of `level` (a callable Real3 -> real) moving only the
/// first `dirs` coordinates: y <- y - L g / |g|^2, g the gradient by central differences with
/// step 1e-6 `scale`, until |L| < 1e-13 `scale` (at most 20 steps). The closest point where L
/// is a distance; a surface point within O(L^2 curvature) of it otherwise.
template <class Level>
Real3 newton_onto_zero_level(const Level& level, Real3 y, int dirs, real scale) {
    const real step = 1e-6 * scale;
    for (int it = 0; it < 20; ++it) {
        const real l = level(y);
        Real3 g{0, 0, 0};
        real g2 = 0;
        for (int d = 0; d < dirs; ++d) {
            Real3 p = y, m = y;
            p[d] += step;
            m[d] -= step;
            g[d] = (level(p) - level(m)) / (2 * step);
            g2 += g[d] * g[d];
        }
        if (!(g2 > 0)) break;
        for (int d = 0; d < dirs; ++d)
            y[d] -= l * g[d] / g2;
        if (std::abs(l) < 1e-13 * scale) break;
    }
    return y;
}

class Shape {
  public:
    Shape(const Real3& centre, const Matrix3& rotation) : centre_(centre), rot_(rotation) {}
    virtual ~Shape() = default;

    const Real3& centre() const { return centre_; }
    /// Implicit function at lab point x: negative inside.
    real level(const Real3& x) const { return body_level(to_body(x)); }
    bool inside(const Real3& x) const { return body_inside(to_body(x)); }
    /// The surface point nearest to lab point x (near the surface: within a fraction of the
    /// body's smallest radius of curvature, where that point is unique).
    Real3 closest_point(const Real3& x) const { return to_lab(body_closest_point(to_body(x))); }
    /// 3D: the mean of the principal curvatures of the level set through lab point x (1/r
    /// around a sphere), in closed form where the shape has one; NaN otherwise (then the
    /// caller differences the level function).
    real level_set_mean_curvature(const Real3& x) const {
        return body_level_set_mean_curvature(to_body(x));
    }
    /// True when |level| never exceeds the distance to the surface.
    virtual bool level_bounds_distance() const = 0;
    /// A radius r_b with level(x) >= |x - centre()| - r_b everywhere (the level function is
    /// at least the distance to the ball that holds the body), so that a caller can skip
    /// points far from the body without evaluating an expensive level; infinite (the
    /// default) where the shape offers no such bound.
    virtual real bounding_radius() const { return std::numeric_limits<real>::infinity(); }
    /// Exact volume (3D) for checks; 2D shapes return their area.
    virtual real exact_volume() const = 0;
    virtual std::string describe() const = 0;

  protected:
    /// Implicit function in body coordinates.
    virtual real body_level(const Real3& y) const = 0;
    /// Whether body point y is inside: body_level(y) < 0, or a cheaper test of the same sign.
    virtual bool body_inside(const Real3& y) const { return body_level(y) < 0; }
    /// The surface point nearest to body point y. By default newton_onto_zero_level on the
    /// level function, scaled by y's largest coordinate.
    virtual Real3 body_closest_point(const Real3& y) const;
    virtual real body_level_set_mean_curvature(const Real3&) const {
        return std::numeric_limits<real>::quiet_NaN();
    }

  private:
    Real3 to_body(const Real3& x) const;
    Real3 to_lab(const Real3& y) const;
    Real3 centre_;
    Matrix3 rot_;
};

/// Sphere of radius r (a disc of radius r in a 2D run through the sphere's centre plane).
std::unique_ptr<Shape> make_sphere(const Real3& centre, real radius);
/// Ellipsoid with semi-axes a along the body axes (a spheroid when two are equal).
std::unique_ptr<Shape> make_ellipsoid(const Real3& centre, const Real3& semi_axes,
                                      const Matrix3& rotation = identity_rotation());
/// Evans-Fung biconcave disc, symmetry axis along body z:
///   |z| < (R0/2) sqrt(1 - r^2) (C0 + C1 r^2 + C2 r^4),  r = rho / R0 < 1.
/// Defaults are the human red cell (R0 = 3.91 um; volume ~94 um^3).
struct EvansFungCoefficients {
    real r0 = 3.91e-6;
    real c0 = 0.207161;
    real c1 = 2.002558;
    real c2 = -1.122762;
};
std::unique_ptr<Shape> make_biconcave_disc(const Real3& centre,
                                           const Matrix3& rotation = identity_rotation(),
                                           const EvansFungCoefficients& c = {});
/// The same disc with its exact signed distance as the level function (slower; for the
/// smoothed interface of a membrane, whose tanh profile needs a distance).
std::unique_ptr<Shape> make_biconcave_distance(const Real3& centre,
                                               const Matrix3& rotation = identity_rotation(),
                                               const EvansFungCoefficients& c = {});
/// A vessel wall around a straight lumen: the region farther than `lumen_radius` from the
/// line along x through `centre` (level r - dist(x, axis), a signed distance). Its volume
/// is unbounded: exact_volume() returns NaN.
std::unique_ptr<Shape> make_tube(const Real3& centre, real lumen_radius);
/// Circular cylinder of radius r, infinite along body z (the disc of a 2D run).
std::unique_ptr<Shape> make_cylinder(const Real3& centre, real radius,
                                     const Matrix3& rotation = identity_rotation());
/// Box with half-sizes h along the body axes. A slab is a box with huge half-sizes in
/// the two directions along it (see make_slab).
std::unique_ptr<Shape> make_box(const Real3& centre, const Real3& half_sizes,
                                const Matrix3& rotation = identity_rotation());
/// Slab {x : |n . (x - centre)| < thickness / 2}, n the (normalised) `normal`.
std::unique_ptr<Shape> make_slab(const Real3& centre, const Real3& normal, real thickness);
/// Set difference a minus b (e.g. Zalesak's slotted disc): level max(L_a, -L_b), a distance
/// bound when both are. exact_volume() is not known and returns NaN.
std::unique_ptr<Shape> make_difference(std::unique_ptr<Shape> a, std::unique_ptr<Shape> b);

/// Statistics of one initialisation, for logs and tests.
struct VolumeFractionStats {
    std::int64_t sampled_cells = 0; ///< cells of this rank that were sub-sampled
    real volume = 0;                ///< sum phi dV over this rank's cells
};

/// Cell volume fraction of `shape` on the owned cells of phi (the whole `block`, or a
/// body's patch of it): 1 inside, 0 outside,
/// and in cells the surface may cut, the fraction of `subsamples`^dim uniformly placed
/// points (cell-centred sub-cells) that lie inside. Error per cut cell ~ 1/subsamples^2
/// for a smooth surface (midpoint rule on the sub-cells, the surface crossing each
/// sub-cell row once). Halos are left untouched; fill them afterwards. `volume` in the
/// returned stats is the local sum; reduce it over ranks if needed. `periodic` (optional):
/// each cell takes the shape at its image nearest the shape's centre along the periodic
/// directions (a body across a periodic seam).
VolumeFractionStats initial_volume_fraction(const Shape& shape, const GlobalGrid& grid,
                                            const LocalBlock& block, Field& phi, int subsamples = 8,
                                            const Bool3* periodic = nullptr);

} // namespace efsi
