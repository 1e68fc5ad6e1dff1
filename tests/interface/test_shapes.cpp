// Initial volume fractions from implicit shapes: volumes against closed forms, bounds,
// which cells are sub-sampled, and independence from the rank count.
#include "interface/geometry.hpp"
#include "interface/shapes.hpp"
#include "parallel/decomposition.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <tuple>

using namespace efsi;

namespace {

constexpr real pi = std::numbers::pi;

/// Uniform spacing h on an anisotropic box of `cells`.
GlobalGrid box_grid(const Int3& cells, real h, int dim = 3) {
    GlobalGrid g;
    g.dim = dim;
    g.cells = cells;
    for (int d = 0; d < 3; ++d)
        g.length[d] = cells[d] * h;
    return g;
}

struct Filled {
    real volume = 0;
    real min = 1, max = 0;
    std::int64_t sampled = 0;
};

Filled fill_shape(const Shape& s, const GlobalGrid& g, int subsamples = 8) {
    Decomposition dec(MPI_COMM_WORLD, g, {true, true, true});
    Field phi("phi", Location::Cell, dec.block(), g.dim);
    const VolumeFractionStats st = initial_volume_fraction(s, g, dec.block(), phi, subsamples);
    Filled f;
    for_each_cell(dec.block().cells, [&](int i, int j, int k) {
        f.min = std::min(f.min, phi(i, j, k));
        f.max = std::max(f.max, phi(i, j, k));
    });
    f.min = dec.min(f.min);
    f.max = dec.max(f.max);
    f.volume = dec.sum(st.volume);
    f.sampled = dec.sum(st.sampled_cells);
    return f;
}

} // namespace

TEST(Shapes, SphereVolumeAt32CellsAcross) {
    // Radius 0.5 with h = 1/32: 32 cells across the diameter; centre off the grid lines.
    const GlobalGrid g = box_grid({40, 36, 34}, 1.0 / 32);
    const auto s = make_sphere({0.61, 0.57, 0.53}, 0.5);
    const Filled f = fill_shape(*s, g);
    const real exact = 4.0 / 3.0 * pi * 0.125;
    EXPECT_LT(std::abs(f.volume - exact) / exact, 1e-3);
    EXPECT_EQ(f.min, 0.0);
    EXPECT_EQ(f.max, 1.0);
    // Only a band of cells about the surface is sub-sampled: the surface area over h^2
    // times a band of at most ~2 cells (the half-diagonal test), far fewer than all cells.
    const real band = 4 * pi * 0.25 * 32 * 32 * 2.5;
    EXPECT_GT(f.sampled, 0);
    EXPECT_LT(real(f.sampled), band);
    EXPECT_LT(f.sampled, g.total_cells() / 4);
}

TEST(Shapes, SubsamplingConvergesAtSecondOrder) {
    // Error of the sub-sampled volume with 4 and 16 points per direction: the midpoint rule
    // on sub-cells gives ~ n^-2 per cut cell; demand at least a factor 4 from 4 to 16.
    const GlobalGrid g = box_grid({26, 22, 20}, 1.0 / 16);
    const auto s = make_sphere({0.8, 0.7, 0.62}, 0.45);
    const real exact = s->exact_volume();
    const real e4 = std::abs(fill_shape(*s, g, 4).volume - exact);
    const real e16 = std::abs(fill_shape(*s, g, 16).volume - exact);
    EXPECT_LT(e16, e4 / 4);
}

TEST(Shapes, RotatedEllipsoidVolume) {
    const GlobalGrid g = box_grid({44, 40, 36}, 1.0 / 32);
    const auto s =
        make_ellipsoid({0.7, 0.62, 0.56}, {0.45, 0.3, 0.2}, axis_angle_rotation({1, 2, 0.5}, 0.7));
    const Filled f = fill_shape(*s, g);
    const real exact = 4.0 / 3.0 * pi * 0.45 * 0.3 * 0.2;
    EXPECT_DOUBLE_EQ(s->exact_volume(), exact);
    EXPECT_LT(std::abs(f.volume - exact) / exact, 1e-3);
}

TEST(Shapes, BiconcaveDiscIsTheRedCell) {
    const auto s = make_biconcave_disc({0, 0, 0});
    // Evans & Fung (1972): volume about 94 um^3.
    EXPECT_NEAR(s->exact_volume(), 94e-18, 1e-18);
    // Thickness at the centre 2 (R0/2) C0 = R0 C0 and the dimple: the thickest point is
    // off-centre, so a point on the axis just inside R0 C0 / 2 is inside and one beyond is not.
    const real r0 = 3.91e-6, c0 = 0.207161;
    EXPECT_TRUE(s->inside({0, 0, 0.49 * r0 * c0}));
    EXPECT_FALSE(s->inside({0, 0, 0.51 * r0 * c0}));
    EXPECT_TRUE(s->inside({0.6 * r0, 0, 0.8 * r0 * c0}));
    EXPECT_FALSE(s->inside({1.01 * r0, 0, 0}));
    // Tilted cell on a grid of h = R0 / 16: sampled volume against the closed form.
    const GlobalGrid g = box_grid({40, 38, 36}, r0 / 16);
    const auto t = make_biconcave_disc({20.3 * r0 / 16, 19.1 * r0 / 16, 18.2 * r0 / 16},
                                       axis_angle_rotation({1, 0.3, 0}, 0.5));
    const Filled f = fill_shape(*t, g);
    EXPECT_LT(std::abs(f.volume - t->exact_volume()) / t->exact_volume(), 2e-3);
}

TEST(Shapes, BiconcaveDistanceIsTheSignedDistanceOfTheDisc) {
    const real r0 = 3.91e-6, c0 = 0.207161;
    const auto disc = make_biconcave_disc({0, 0, 0});
    const auto s = make_biconcave_distance({0, 0, 0});
    EXPECT_TRUE(s->level_bounds_distance());
    EXPECT_DOUBLE_EQ(s->exact_volume(), disc->exact_volume());
    // Beside the rim and just above the dimple the nearest point is known.
    EXPECT_NEAR(s->level({r0 + 0.1 * r0, 0, 0}), 0.1 * r0, 1e-12 * r0);
    EXPECT_NEAR(s->level({0, 0, 0.5 * r0 * c0 + 0.01 * r0}), 0.01 * r0, 1e-12 * r0);
    EXPECT_NEAR(s->level({0, 0, 0.5 * r0 * c0 - 0.01 * r0}), -0.01 * r0, 1e-12 * r0);
    // The same sign as the disc, and |grad L| = 1 (central differences) off the medial axis,
    // for a tilted, shifted cell.
    const Matrix3 rot = axis_angle_rotation({1, 0.3, -0.2}, 0.7);
    const Real3 c{1e-6, -2e-6, 0.5e-6};
    const auto sd = make_biconcave_distance(c, rot), sh = make_biconcave_disc(c, rot);
    int n = 0;
    for (int q = 0; q < 400; ++q) {
        const Real3 x{c[0] + r0 * (1.4 * std::sin(1.3 * q)), c[1] + r0 * 1.4 * std::cos(0.7 * q),
                      c[2] + r0 * 0.8 * std::sin(2.9 * q + 1)};
        const real l = sd->level(x);
        EXPECT_EQ(l < 0, sh->inside(x));
        if (l < 0.05 * r0) continue; // outside only: no medial axis there
        const real e = 1e-4 * r0;
        real g2 = 0;
        for (int d = 0; d < 3; ++d) {
            Real3 xp = x, xm = x;
            xp[d] += e;
            xm[d] -= e;
            g2 += std::pow((sd->level(xp) - sd->level(xm)) / (2 * e), 2);
        }
        EXPECT_NEAR(std::sqrt(g2), 1.0, 1e-5);
        ++n;
    }
    EXPECT_GT(n, 100);
}

// Shape::bounding_radius is a promise the first phi of a smoothed body relies on to skip
// cells: level(x) >= |x - c| - r_b everywhere. Checked for the tilted, shifted red cell at
// points all round it, near and far; no point of the surface lies outside the ball, and the
// ball is not needlessly large: it holds the cylinder rho <= R0, |z| <= the disc's largest
// half-thickness (1.29 um), whose edge lies 5.3 % beyond the rim, so within 6 % of the
// farthest surface point (the rim).
TEST(Shapes, BiconcaveDistanceBoundingBallHoldsTheCell) {
    const real r0 = 3.91e-6;
    const Matrix3 rot = axis_angle_rotation({1, 0.3, -0.2}, 0.7);
    const Real3 c{1e-6, -2e-6, 0.5e-6};
    const auto s = make_biconcave_distance(c, rot);
    const real rb = s->bounding_radius();
    EXPECT_TRUE(std::isfinite(rb));
    EXPECT_TRUE(std::isinf(make_ellipsoid(c, {r0, r0, r0})->bounding_radius()));
    real farthest = 0;
    for (int q = 0; q < 4000; ++q) {
        const real scale = 0.2 + 2.5 * (q % 50) / 50.0; // 0.2 .. 2.7 r0 from the centre
        const Real3 dir{std::sin(1.3 * q) * std::cos(0.37 * q),
                        std::sin(1.3 * q) * std::sin(0.37 * q), std::cos(1.3 * q)};
        Real3 x;
        for (int d = 0; d < 3; ++d)
            x[d] = c[d] + scale * r0 * dir[d];
        const real dist = std::hypot(x[0] - c[0], x[1] - c[1], x[2] - c[2]);
        EXPECT_GE(s->level(x), dist - rb - 1e-12 * r0);
        const Real3 y = s->closest_point(x);
        farthest = std::max(farthest, std::hypot(y[0] - c[0], y[1] - c[1], y[2] - c[2]));
    }
    EXPECT_LE(farthest, rb);
    EXPECT_GT(farthest, rb / 1.06);
}

namespace {
/// A tilted, shifted red cell (its distance), a sphere and an ellipsoid of the cell's size.
struct TiltedShapes {
    const real r0 = 3.91e-6;
    const Matrix3 rot = axis_angle_rotation({1, 0.3, -0.2}, 0.7);
    const Real3 c{1e-6, -2e-6, 0.5e-6};
    const std::unique_ptr<Shape> disc = make_biconcave_distance(c, rot);
    const std::unique_ptr<Shape> sphere = make_sphere(c, r0);
    const std::unique_ptr<Shape> ell = make_ellipsoid(c, {r0, 0.8 * r0, 0.5 * r0}, rot);
};
} // namespace

// The nearest surface point (the membrane's map projection): on the surface, and where the
// level is a distance exactly |level| away from the point; the biconcave disc's by its
// meridian search, the sphere's in closed form, the ellipsoid's by Newton steps on its level.
TEST(Shapes, ClosestPointIsOnTheSurfaceAtTheDistance) {
    const TiltedShapes shapes;
    const real r0 = shapes.r0;
    const Real3& c = shapes.c;
    const auto& [disc, sphere, ell] = std::tie(shapes.disc, shapes.sphere, shapes.ell);
    int n = 0;
    for (int q = 0; q < 300; ++q) {
        const Real3 dir{std::sin(1.3 * q) * std::cos(0.4 * q), std::cos(0.7 * q),
                        std::sin(2.9 * q + 1)};
        for (const Shape* s : {disc.get(), sphere.get(), ell.get()}) {
            // A point near the surface: from the centre along dir to the surface (bisection on
            // the sign), then 0.05 r0 off it along dir.
            real lo = 0, hi = 2 * r0;
            for (int it = 0; it < 80; ++it) {
                const real mid = 0.5 * (lo + hi);
                const Real3 x{c[0] + mid * dir[0], c[1] + mid * dir[1], c[2] + mid * dir[2]};
                (s->level(x) < 0 ? lo : hi) = mid;
            }
            const real off = (q % 2 ? 0.05 : -0.03) * r0;
            const real t =
                lo + off / std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
            const Real3 x{c[0] + t * dir[0], c[1] + t * dir[1], c[2] + t * dir[2]};
            const Real3 p = s->closest_point(x);
            EXPECT_LT(std::abs(s->level(p)), 1e-12 * r0) << s->describe() << " q " << q;
            if (s != ell.get()) {
                const real d = std::hypot(x[0] - p[0], x[1] - p[1], x[2] - p[2]);
                EXPECT_NEAR(d, std::abs(s->level(x)), 1e-10 * r0) << s->describe() << " q " << q;
            }
            ++n;
        }
    }
    EXPECT_EQ(n, 900);
}

// The closed-form curvature of the level sets (the membrane's reference curvature) against
// central differences of the level function, near a tilted red cell and a sphere.
TEST(Shapes, LevelSetCurvatureInClosedFormMatchesDifferences) {
    const TiltedShapes shapes;
    const real r0 = shapes.r0;
    const Real3& c = shapes.c;
    const auto& [disc, sphere, ell] = std::tie(shapes.disc, shapes.sphere, shapes.ell);
    EXPECT_TRUE(std::isnan(ell->level_set_mean_curvature({0, 0, 0})));
    int n = 0;
    for (int q = 0; q < 2000; ++q) {
        const Real3 x{c[0] + r0 * 1.2 * std::sin(1.3 * q), c[1] + r0 * 1.2 * std::cos(0.7 * q),
                      c[2] + r0 * 0.6 * std::sin(2.9 * q + 1)};
        for (const Shape* s : {disc.get(), sphere.get()}) {
            const real l = s->level(x);
            if (std::abs(l) > 0.1 * r0 || (s == disc.get() && l < -0.02 * r0)) continue;
            const real e = 1e-3 * r0;
            auto L = [&](int d1, int s1, int d2, int s2) {
                Real3 y = x;
                y[d1] += s1 * e;
                y[d2] += s2 * e;
                return s->level(y);
            };
            Real3 grad{0, 0, 0};
            Matrix3 H{};
            for (int d = 0; d < 3; ++d) {
                grad[d] = (L(d, 1, d, 0) - L(d, -1, d, 0)) / (2 * e);
                H[d][d] = (L(d, 1, d, 0) - 2 * l + L(d, -1, d, 0)) / (e * e);
                for (int f = d + 1; f < 3; ++f)
                    H[d][f] = H[f][d] =
                        (L(d, 1, f, 1) - L(d, 1, f, -1) - L(d, -1, f, 1) + L(d, -1, f, -1)) /
                        (4 * e * e);
            }
            const real fd = level_set_curvature(H, grad, 3);
            const real k = s->level_set_mean_curvature(x);
            EXPECT_NEAR(k, fd, 1e-4 * std::abs(fd) + 1e-3 / r0) << s->describe() << " q " << q;
            ++n;
        }
    }
    EXPECT_GT(n, 100);
}

TEST(Shapes, TubeIsTheWallAroundALumenAlongX) {
    const auto t = make_tube({0, 1.0, 2.0}, 0.5);
    EXPECT_TRUE(t->level_bounds_distance());
    EXPECT_NEAR(t->level({7.0, 1.0, 2.0}), 0.5, 1e-15);     // on the axis: in the lumen
    EXPECT_NEAR(t->level({-3.0, 1.0, 2.75}), -0.25, 1e-15); // in the wall
    EXPECT_FALSE(t->inside({0.0, 1.3, 2.3}));
    // On an anisotropic grid, the wall's volume is the box minus the lumen's cylinder.
    const GlobalGrid g = box_grid({6, 26, 22}, 1.0 / 20);
    const auto w = make_tube({0.15, 0.65, 0.55}, 0.5);
    const real wall = 0.3 * (1.3 * 1.1 - pi * 0.25);
    EXPECT_LT(std::abs(fill_shape(*w, g).volume - wall) / wall, 2e-3);
}

TEST(Shapes, TwoDimensionalDiscArea) {
    // dim = 2: a cylinder (or sphere through its centre) gives a disc; measure per unit depth.
    const real h = 1.0 / 64;
    GlobalGrid g = box_grid({70, 66, 1}, h, 2);
    const auto s = make_cylinder({0.52, 0.49, 0}, 0.3);
    const Filled f = fill_shape(*s, g);
    const real area = f.volume / g.dx(2);
    EXPECT_LT(std::abs(area - pi * 0.09) / (pi * 0.09), 1e-3);
}

TEST(Shapes, BoxSlabAndDifference) {
    const GlobalGrid g = box_grid({24, 20, 18}, 1.0 / 16);
    // A box aligned with the grid lines is resolved exactly (every cell is full or empty,
    // or split at a sub-sample boundary).
    const auto b = make_box({0.75, 0.625, 0.5625}, {0.25, 0.125, 0.25});
    EXPECT_NEAR(fill_shape(*b, g).volume, 0.5 * 0.25 * 0.5, 1e-14);
    const auto slab = make_slab({0.7, 0.6, 0.5}, {0, 0, 1}, 0.375);
    EXPECT_NEAR(fill_shape(*slab, g).volume, 0.375 * 1.5 * 1.25, 1e-14);
    // Zalesak-like: box minus a smaller box inside it.
    const auto d = make_difference(make_box({0.75, 0.625, 0.5625}, {0.25, 0.125, 0.25}),
                                   make_box({0.75, 0.625, 0.5625}, {0.125, 0.0625, 0.125}));
    EXPECT_NEAR(fill_shape(*d, g).volume, 0.5 * 0.25 * 0.5 - 0.25 * 0.125 * 0.25, 1e-14);
}

TEST(Shapes, BadInputIsAnInputError) {
    EXPECT_THROW(make_sphere({0, 0, 0}, -1), InputError);
    EXPECT_THROW(make_ellipsoid({0, 0, 0}, {1, 0, 1}), InputError);
    EXPECT_THROW(axis_angle_rotation({0, 0, 0}, 1), InputError);
}
