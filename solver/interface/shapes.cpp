#include "interface/shapes.hpp"

#include "core/error.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace efsi {

Matrix3 identity_rotation() {
    return {Real3{1, 0, 0}, Real3{0, 1, 0}, Real3{0, 0, 1}};
}

Matrix3 axis_angle_rotation(const Real3& axis, real angle) {
    const real len = std::hypot(axis[0], axis[1], axis[2]);
    if (!(len > 0)) throw InputError("axis_angle_rotation: zero rotation axis");
    const Real3 a{axis[0] / len, axis[1] / len, axis[2] / len};
    const real c = std::cos(angle), s = std::sin(angle);
    // Rodrigues: R = c I + s [a]_x + (1 - c) a a^T.
    Matrix3 r{};
    for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q)
            r[p][q] = (p == q ? c : 0.0) + (1 - c) * a[p] * a[q];
    r[0][1] -= s * a[2];
    r[0][2] += s * a[1];
    r[1][0] += s * a[2];
    r[1][2] -= s * a[0];
    r[2][0] -= s * a[1];
    r[2][1] += s * a[0];
    return r;
}

Real3 Shape::to_body(const Real3& x) const {
    // y = R^T (x - c): the components of x - c along the body axes (columns of R).
    Real3 y{0, 0, 0};
    for (int b = 0; b < 3; ++b)
        for (int a = 0; a < 3; ++a)
            y[b] += rot_[a][b] * (x[a] - centre_[a]);
    return y;
}

Real3 Shape::to_lab(const Real3& y) const {
    // x = c + R y.
    Real3 x = centre_;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            x[a] += rot_[a][b] * y[b];
    return x;
}

Real3 Shape::body_closest_point(const Real3& y0) const {
    // The difference step: small against any body, large against round-off in the level.
    const real scale = std::max({std::abs(y0[0]), std::abs(y0[1]), std::abs(y0[2]), 1e-300});
    return newton_onto_zero_level([this](const Real3& y) { return body_level(y); }, y0, 3, scale);
}

namespace {

real norm3(const Real3& y) {
    return std::hypot(y[0], y[1], y[2]);
}

class Sphere final : public Shape {
  public:
    Sphere(const Real3& c, real r) : Shape(c, identity_rotation()), r_(r) {}
    bool level_bounds_distance() const override { return true; }
    real exact_volume() const override { return 4.0 / 3.0 * std::numbers::pi * r_ * r_ * r_; }
    std::string describe() const override { return fmt::format("sphere(r={:.6g})", r_); }

  protected:
    real body_level(const Real3& y) const override { return norm3(y) - r_; }
    real body_level_set_mean_curvature(const Real3& y) const override {
        const real r = norm3(y);
        return r > 0 ? 1 / r : std::numeric_limits<real>::quiet_NaN();
    }
    Real3 body_closest_point(const Real3& y) const override {
        const real r = norm3(y);
        if (!(r > 0)) return Real3{r_, 0, 0}; // the centre: every surface point is nearest
        return Real3{y[0] * r_ / r, y[1] * r_ / r, y[2] * r_ / r};
    }

  private:
    real r_;
};

class Ellipsoid final : public Shape {
  public:
    Ellipsoid(const Real3& c, const Real3& a, const Matrix3& rot) : Shape(c, rot), a_(a) {}
    bool level_bounds_distance() const override { return true; }
    real exact_volume() const override {
        return 4.0 / 3.0 * std::numbers::pi * a_[0] * a_[1] * a_[2];
    }
    std::string describe() const override {
        return fmt::format("ellipsoid(a={:.6g},{:.6g},{:.6g})", a_[0], a_[1], a_[2]);
    }

  protected:
    // y -> (y_a / a_a) stretches lengths by at most 1/min(a), so
    // min(a) (|y/a| - 1) changes no faster than the distance: a distance lower bound.
    real body_level(const Real3& y) const override {
        const Real3 s{y[0] / a_[0], y[1] / a_[1], y[2] / a_[2]};
        return std::min({a_[0], a_[1], a_[2]}) * (norm3(s) - 1);
    }

  private:
    Real3 a_;
};

class BiconcaveDisc final : public Shape {
  public:
    BiconcaveDisc(const Real3& c, const Matrix3& rot, const EvansFungCoefficients& k)
        : Shape(c, rot), k_(k) {}
    bool level_bounds_distance() const override { return false; }
    real exact_volume() const override {
        // V = int_0^R0 2 h(rho) 2 pi rho drho = 2 pi R0^3 int_0^1 sqrt(1-r^2)(C0+C1 r^2+C2 r^4) r
        // dr and int_0^1 sqrt(1-r^2) r^(2m+1) dr = 1/3, 2/15, 8/105 for m = 0, 1, 2.
        const real i = k_.c0 / 3.0 + k_.c1 * 2.0 / 15.0 + k_.c2 * 8.0 / 105.0;
        return 2 * std::numbers::pi * k_.r0 * k_.r0 * k_.r0 * i;
    }
    std::string describe() const override {
        return fmt::format("biconcave_disc(R0={:.6g})", k_.r0);
    }

  protected:
    real body_level(const Real3& y) const override {
        const real rho = std::hypot(y[0], y[1]);
        const real r = std::min(rho / k_.r0, 1.0);
        const real r2 = r * r;
        const real h = 0.5 * k_.r0 * std::sqrt(1 - r2) * (k_.c0 + k_.c1 * r2 + k_.c2 * r2 * r2);
        return std::max(rho - k_.r0, std::abs(y[2]) - h);
    }

  private:
    EvansFungCoefficients k_;
};

/// The Evans-Fung disc with its exact signed distance as level function (for the smoothed
/// interface of a red cell's membrane, phi = (1 - tanh(L / eps)) / 2 needs L to be a
/// distance). By symmetry the nearest surface point of (rho, z) lies on the upper meridian
/// c(t) = (R0 sin t, (R0/2) cos t (C0 + C1 sin^2 t + C2 sin^4 t)), t in [0, pi/2] (smooth
/// in t, unlike in r at the rim): |q - c(t)| is minimised over 128 samples, then by Newton's
/// method (safeguarded by bisection) on the bracket of the best one to round-off (the
/// distance is stationary there, so its error is second order in the parameter: ~1e-16 R0).
/// The sign is the disc's.
class BiconcaveDistance final : public Shape {
  public:
    BiconcaveDistance(const Real3& c, const Matrix3& rot, const EvansFungCoefficients& k)
        : Shape(c, rot), k_(k), disc_(Real3{0, 0, 0}, identity_rotation(), k),
          sample_(samples_for(k)) {}
    bool level_bounds_distance() const override { return true; }
    // The level is the distance, and the disc lies within rho <= R0, |z| <= the meridian's
    // largest height (its samples' largest, 1 % added for the curve between them).
    real bounding_radius() const override {
        real zmax = 0;
        for (const auto& c : *sample_)
            zmax = std::max(zmax, c[1]);
        return std::hypot(k_.r0, 1.01 * zmax);
    }
    real exact_volume() const override { return disc_.exact_volume(); }
    std::string describe() const override {
        return fmt::format("biconcave_disc_distance(R0={:.6g})", k_.r0);
    }

  protected:
    real body_level(const Real3& y) const override {
        const real rho = std::hypot(y[0], y[1]), z = std::abs(y[2]);
        const real dist = std::sqrt(nearest(rho, z).d2);
        return disc_.level(y) < 0 ? -dist : dist;
    }
    // The level set at signed distance s from a surface with principal curvatures k has
    // curvatures k / (1 + s k); those of the surface of revolution at the nearest meridian
    // point: the meridian's, (z' r'' - r' z'') / |c'|^3, and the parallel's, -z' / (r |c'|)
    // (the meridian's at the pole, where both are equal).
    real body_level_set_mean_curvature(const Real3& y) const override {
        const real rho = std::hypot(y[0], y[1]), z = std::abs(y[2]);
        const Nearest q = nearest(rho, z);
        const real s = disc_.level(y) < 0 ? -std::sqrt(q.d2) : std::sqrt(q.d2);
        const Derivatives m = meridian_derivatives(q.t);
        const real speed = std::hypot(m.d1[0], m.d1[1]);
        const real km = (m.d1[1] * m.d2[0] - m.d1[0] * m.d2[1]) / (speed * speed * speed);
        const real kp = m.c[0] > 1e-9 * k_.r0 ? -m.d1[1] / (m.c[0] * speed) : km;
        return 0.5 * (km / (1 + s * km) + kp / (1 + s * kp));
    }
    Real3 body_closest_point(const Real3& y) const override {
        const real rho = std::hypot(y[0], y[1]), z = std::abs(y[2]);
        const std::array<real, 2> c = meridian_derivatives(nearest(rho, z).t).c;
        // On the axis every azimuth is as near: take x.
        const real cx = rho > 0 ? y[0] / rho : 1.0, cy = rho > 0 ? y[1] / rho : 0.0;
        return Real3{c[0] * cx, c[0] * cy, y[2] < 0 ? -c[1] : c[1]};
    }
    /// The sign of body_level without the distance.
    bool body_inside(const Real3& y) const override { return disc_.level(y) < 0; }

  private:
    struct Nearest {
        real t = 0;  ///< the meridian parameter of the nearest point
        real d2 = 0; ///< the squared distance to it
    };
    /// The nearest point of the upper meridian to (rho, z), z >= 0.
    Nearest nearest(real rho, real z) const {
        auto d2 = [&](const std::array<real, 2>& c) {
            return (rho - c[0]) * (rho - c[0]) + (z - c[1]) * (z - c[1]);
        };
        int best = 0;
        const Samples& sample = *sample_;
        real dbest = d2(sample[0]);
        for (int i = 1; i <= samples; ++i)
            if (const real d = d2(sample[i]); d < dbest) {
                dbest = d;
                best = i;
            }
        // Newton's method on f'(t) = 0, f = |q - c(t)|^2, safeguarded by bisection on the
        // bracket of the best sample (f' changes sign there), to a parameter step of 1e-12
        // (the distance, stationary there, is then exact to round-off): 3-5 evaluations
        // of c, c' and c'' where golden sections took ~40 of c.
        real a = std::max(0, best - 1) * step, b = std::min(samples, best + 1) * step;
        real t = best * step, t_f = t, f_t = dbest;
        for (int it = 0; it < 100; ++it) {
            const Derivatives m = meridian_derivatives(t);
            const real dr = rho - m.c[0], dz = z - m.c[1];
            f_t = dr * dr + dz * dz;
            t_f = t;
            const real g = -(dr * m.d1[0] + dz * m.d1[1]); // f'(t) / 2
            const real h = m.d1[0] * m.d1[0] + m.d1[1] * m.d1[1] - (dr * m.d2[0] + dz * m.d2[1]);
            if (g > 0)
                b = t;
            else
                a = t;
            real next = h > 0 ? t - g / h : 0.5 * (a + b);
            if (!(next > a && next < b)) next = 0.5 * (a + b);
            const real moved = std::abs(next - t);
            t = next;
            if (moved < 1e-12 || b - a < 1e-12) break;
        }
        // The least of the best sample, the last iterate and the final parameter.
        Nearest r{best * step, dbest};
        if (f_t < r.d2) r = {t_f, f_t};
        if (const real f = d2(meridian_derivatives(t).c); f < r.d2) r = {t, f};
        return r;
    }
    static constexpr int samples = 128;
    static constexpr real step = 0.5 * std::numbers::pi / samples;
    /// The meridian point c(t) and its first and second derivatives in t.
    struct Derivatives {
        std::array<real, 2> c, d1, d2;
    };
    Derivatives meridian_derivatives(real t) const {
        const real s = std::sin(t), co = std::cos(t), u = s * s;
        const real P = k_.c0 + k_.c1 * u + k_.c2 * u * u, dP = k_.c1 + 2 * k_.c2 * u,
                   ddP = 2 * k_.c2; // P(u), dP/du, d2P/du2, u = sin^2 t
        const real hr = 0.5 * k_.r0;
        Derivatives m;
        m.c = {k_.r0 * s, hr * co * P};
        m.d1 = {k_.r0 * co, hr * (-s * P + 2 * s * co * co * dP)};
        m.d2 = {-k_.r0 * s, hr * (-co * P - 2 * u * co * dP + 2 * (co * co * co - 2 * u * co) * dP +
                                  4 * u * co * co * co * ddP)};
        return m;
    }
    EvansFungCoefficients k_;
    BiconcaveDisc disc_; ///< the sign (inside or not), at the body origin
    using Samples = std::array<std::array<real, 2>, samples + 1>;
    /// The meridian's samples for coefficients k, made once per coefficient set (the
    /// seeding makes a shape for every candidate pose of every cell).
    static std::shared_ptr<const Samples> samples_for(const EvansFungCoefficients& k) {
        static std::vector<std::pair<std::array<real, 4>, std::shared_ptr<const Samples>>> made;
        const std::array<real, 4> key{k.r0, k.c0, k.c1, k.c2};
        for (const auto& [kk, v] : made)
            if (kk == key) return v;
        auto v = std::make_shared<Samples>();
        for (int i = 0; i <= samples; ++i) {
            const real t = i * step, sn = std::sin(t), s2 = sn * sn;
            (*v)[i] = {k.r0 * sn, 0.5 * k.r0 * std::cos(t) * (k.c0 + k.c1 * s2 + k.c2 * s2 * s2)};
            // the upper meridian (rho, z) at parameter t
        }
        made.emplace_back(key, v);
        return v;
    }
    std::shared_ptr<const Samples> sample_;
};

/// A vessel wall: everything farther than r from the body x axis through the centre.
class Tube final : public Shape {
  public:
    Tube(const Real3& c, real r) : Shape(c, identity_rotation()), r_(r) {}
    bool level_bounds_distance() const override { return true; }
    real exact_volume() const override { return std::numeric_limits<real>::quiet_NaN(); }
    std::string describe() const override { return fmt::format("tube(lumen r={:.6g})", r_); }

  protected:
    real body_level(const Real3& y) const override { return r_ - std::hypot(y[1], y[2]); }

  private:
    real r_;
};

class Cylinder final : public Shape {
  public:
    Cylinder(const Real3& c, real r, const Matrix3& rot) : Shape(c, rot), r_(r) {}
    bool level_bounds_distance() const override { return true; }
    real exact_volume() const override { return std::numbers::pi * r_ * r_; } // per unit length
    std::string describe() const override { return fmt::format("cylinder(r={:.6g})", r_); }

  protected:
    real body_level(const Real3& y) const override { return std::hypot(y[0], y[1]) - r_; }

  private:
    real r_;
};

class BoxShape final : public Shape {
  public:
    BoxShape(const Real3& c, const Real3& h, const Matrix3& rot) : Shape(c, rot), h_(h) {}
    bool level_bounds_distance() const override { return true; }
    real exact_volume() const override { return 8 * h_[0] * h_[1] * h_[2]; }
    std::string describe() const override {
        return fmt::format("box(h={:.6g},{:.6g},{:.6g})", h_[0], h_[1], h_[2]);
    }

  protected:
    // Exact signed distance of a box: q = |y| - h; outside |max(q, 0)|, inside max(q).
    real body_level(const Real3& y) const override {
        real out2 = 0, in = -std::numeric_limits<real>::max();
        for (int a = 0; a < 3; ++a) {
            const real q = std::abs(y[a]) - h_[a];
            out2 += q > 0 ? q * q : 0;
            in = std::max(in, q);
        }
        return out2 > 0 ? std::sqrt(out2) : in;
    }

  private:
    Real3 h_;
};

class Slab final : public Shape {
  public:
    Slab(const Real3& c, const Real3& n, real t) : Shape(c, identity_rotation()), n_(n), t_(t) {}
    bool level_bounds_distance() const override { return true; }
    real exact_volume() const override { return t_; } // per unit area
    std::string describe() const override { return fmt::format("slab(t={:.6g})", t_); }

  protected:
    real body_level(const Real3& y) const override {
        return std::abs(n_[0] * y[0] + n_[1] * y[1] + n_[2] * y[2]) - 0.5 * t_;
    }

  private:
    Real3 n_;
    real t_;
};

class Difference final : public Shape {
  public:
    Difference(std::unique_ptr<Shape> a, std::unique_ptr<Shape> b)
        : Shape(Real3{0, 0, 0}, identity_rotation()), a_(std::move(a)), b_(std::move(b)) {}
    bool level_bounds_distance() const override {
        return a_->level_bounds_distance() && b_->level_bounds_distance();
    }
    real exact_volume() const override { return std::numeric_limits<real>::quiet_NaN(); }
    std::string describe() const override { return a_->describe() + " minus " + b_->describe(); }

  protected:
    // The body frame is the lab frame (centre 0, identity), so y = x here.
    real body_level(const Real3& y) const override { return std::max(a_->level(y), -b_->level(y)); }

  private:
    std::unique_ptr<Shape> a_, b_;
};

void require_positive(real v, const char* what) {
    if (!(v > 0)) throw InputError(fmt::format("shape: {} must be positive (got {})", what, v));
}

} // namespace

std::unique_ptr<Shape> make_sphere(const Real3& centre, real radius) {
    require_positive(radius, "sphere radius");
    return std::make_unique<Sphere>(centre, radius);
}

std::unique_ptr<Shape> make_ellipsoid(const Real3& centre, const Real3& semi_axes,
                                      const Matrix3& rotation) {
    for (real a : semi_axes)
        require_positive(a, "ellipsoid semi-axis");
    return std::make_unique<Ellipsoid>(centre, semi_axes, rotation);
}

std::unique_ptr<Shape> make_biconcave_disc(const Real3& centre, const Matrix3& rotation,
                                           const EvansFungCoefficients& c) {
    require_positive(c.r0, "biconcave disc R0");
    return std::make_unique<BiconcaveDisc>(centre, rotation, c);
}

std::unique_ptr<Shape> make_biconcave_distance(const Real3& centre, const Matrix3& rotation,
                                               const EvansFungCoefficients& c) {
    require_positive(c.r0, "biconcave disc R0");
    return std::make_unique<BiconcaveDistance>(centre, rotation, c);
}

std::unique_ptr<Shape> make_tube(const Real3& centre, real lumen_radius) {
    require_positive(lumen_radius, "tube lumen radius");
    return std::make_unique<Tube>(centre, lumen_radius);
}

std::unique_ptr<Shape> make_cylinder(const Real3& centre, real radius, const Matrix3& rotation) {
    require_positive(radius, "cylinder radius");
    return std::make_unique<Cylinder>(centre, radius, rotation);
}

std::unique_ptr<Shape> make_box(const Real3& centre, const Real3& half_sizes,
                                const Matrix3& rotation) {
    for (real h : half_sizes)
        require_positive(h, "box half-size");
    return std::make_unique<BoxShape>(centre, half_sizes, rotation);
}

std::unique_ptr<Shape> make_slab(const Real3& centre, const Real3& normal, real thickness) {
    require_positive(thickness, "slab thickness");
    const real len = norm3(normal);
    require_positive(len, "slab normal length");
    return std::make_unique<Slab>(centre, Real3{normal[0] / len, normal[1] / len, normal[2] / len},
                                  thickness);
}

std::unique_ptr<Shape> make_difference(std::unique_ptr<Shape> a, std::unique_ptr<Shape> b) {
    if (!a || !b) throw InputError("make_difference: missing shape");
    return std::make_unique<Difference>(std::move(a), std::move(b));
}

namespace {

/// True when the cell around `xc` (half-widths hw, only the first dim directions) may be
/// cut by the surface and must be sub-sampled; otherwise `full` tells which side it is.
bool may_be_cut(const Shape& s, const Real3& xc, const Real3& hw, int dim, bool& full) {
    const real lc = s.level(xc);
    full = lc < 0;
    if (s.level_bounds_distance()) {
        real hd2 = 0;
        for (int d = 0; d < dim; ++d)
            hd2 += hw[d] * hw[d];
        return std::abs(lc) <= std::sqrt(hd2);
    }
    // Sign test on the 3^dim lattice {-1, 0, 1}^dim of corners, midpoints and centre.
    int npts = 1;
    for (int d = 0; d < dim; ++d)
        npts *= 3;
    for (int q = 0; q < npts; ++q) {
        Real3 x = xc;
        int code = q;
        for (int d = 0; d < dim; ++d, code /= 3)
            x[d] += (code % 3 - 1) * hw[d];
        if (s.inside(x) != full) return true;
    }
    return false;
}

} // namespace

VolumeFractionStats initial_volume_fraction(const Shape& shape, const GlobalGrid& grid,
                                            const LocalBlock& block, Field& phi, int subsamples,
                                            const Bool3* periodic) {
    if (subsamples < 1) throw InputError("initial_volume_fraction: subsamples must be >= 1");
    const int dim = grid.dim;
    Real3 hw{0, 0, 0};
    for (int d = 0; d < dim; ++d)
        hw[d] = 0.5 * grid.dx(d);
    Int3 ns{1, 1, 1};
    for (int d = 0; d < dim; ++d)
        ns[d] = subsamples;
    const real inv_count = 1.0 / (real(ns[0]) * ns[1] * ns[2]);

    VolumeFractionStats st;
    real vol = 0;
    // The owned points of phi: the whole block, or a body's patch of it.
    for_each_in(phi.owned(), [&](int i, int j, int k) {
        Real3 xc = position(grid, block, Location::Cell, i, j, k);
        if (periodic) xc = image_near(xc, shape.centre(), grid, *periodic);
        bool full = false;
        if (!may_be_cut(shape, xc, hw, dim, full)) {
            phi(i, j, k) = full ? 1.0 : 0.0;
        } else {
            ++st.sampled_cells;
            std::int64_t in = 0;
            // Sub-cell centres: x = xc + ((s + 1/2)/n - 1/2) dx per direction.
            for_each_cell(ns, [&](int a, int b, int c) {
                const Int3 s{a, b, c};
                Real3 x = xc;
                for (int d = 0; d < dim; ++d)
                    x[d] += ((s[d] + 0.5) / ns[d] - 0.5) * 2 * hw[d];
                in += shape.inside(x) ? 1 : 0;
            });
            phi(i, j, k) = real(in) * inv_count;
        }
        vol += phi(i, j, k);
    });
    st.volume = vol * grid.cell_volume();
    return st;
}

} // namespace efsi
