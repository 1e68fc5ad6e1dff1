#include "membrane/surface_velocity.hpp"

#include "core/error.hpp"
#include "interface/geometry.hpp"
#include "operators/flow_operators.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace efsi {

namespace {

/// Catmull-Rom weights of the points -1, 0, 1, 2 at t in [0, 1).
inline std::array<real, 4> catmull_rom(real t) {
    const real t2 = t * t, t3 = t2 * t;
    return {0.5 * (-t3 + 2 * t2 - t), 0.5 * (3 * t3 - 5 * t2 + 2), 0.5 * (-3 * t3 + 4 * t2 + t),
            0.5 * (t3 - t2)};
}

/// Their derivatives with respect to t.
inline std::array<real, 4> catmull_rom_slope(real t) {
    const real t2 = t * t;
    return {0.5 * (-3 * t2 + 4 * t - 1), 0.5 * (9 * t2 - 10 * t), 0.5 * (-9 * t2 + 8 * t + 1),
            0.5 * (3 * t2 - 2 * t)};
}

/// f's values on the points of `box` (block-local, within both fields' storage) into `to`,
/// row by row.
void copy_rows(const Field& f, Field& to, const Box& box) {
    if (box.empty()) return;
    const int nx = box.hi[0] - box.lo[0];
    for (int k = box.lo[2]; k < box.hi[2]; ++k)
        for (int j = box.lo[1]; j < box.hi[1]; ++j) {
            const real* from = f.data().data() + f.index(box.lo[0], j, k);
            std::copy(from, from + nx, to.data().data() + to.index(box.lo[0], j, k));
        }
}

struct ValueAndGradient {
    real value = 0;
    Real3 gradient{0, 0, 0};
};

/// The tensor-product sum over the 4^Dim points from `base` - 1 of `f` with the weights `w`
/// and their slopes `dw` (per direction): the value and its gradient, one direction at a
/// time (along x each row's sums with w_x and dw_x, then along y, then z): 2 x 16 + 3 x 4 +
/// 4 products per point set in 3D against 4 x 64 for the sums term by term.
template <int Dim>
ValueAndGradient stencil_sum(const Field& f, const Int3& base,
                             const std::array<std::array<real, 4>, 3>& w,
                             const std::array<std::array<real, 4>, 3>& dw) {
    const std::ptrdiff_t s1 = f.extent()[0], s2 = std::ptrdiff_t(f.extent()[0]) * f.extent()[1];
    const real* const p0 =
        f.data().data() + f.index(base[0] - 1, base[1] - 1, Dim == 3 ? base[2] - 1 : 0);
    real value = 0, gx = 0, gy = 0, gz = 0;
    for (int kk = 0; kk < (Dim == 3 ? 4 : 1); ++kk) {
        // Along y: the x sums of the plane's rows weighted by w_y (value, d/dx) and dw_y (d/dy).
        real a = 0, b = 0, c = 0;
        for (int jj = 0; jj < 4; ++jj) {
            const real* row = p0 + jj * s1 + kk * s2;
            const real x =
                w[0][0] * row[0] + w[0][1] * row[1] + w[0][2] * row[2] + w[0][3] * row[3];
            const real dx =
                dw[0][0] * row[0] + dw[0][1] * row[1] + dw[0][2] * row[2] + dw[0][3] * row[3];
            a += w[1][jj] * x;
            b += w[1][jj] * dx;
            c += dw[1][jj] * x;
        }
        const real wz = Dim == 3 ? w[2][kk] : 1.0;
        value += wz * a;
        gx += wz * b;
        gy += wz * c;
        if (Dim == 3) gz += dw[2][kk] * a;
    }
    return {value, {gx, gy, gz}};
}

} // namespace

SurfaceVelocity::SurfaceVelocity(const HaloFiller& halos, const std::string& body_name,
                                 real max_reach)
    : halos_(halos), max_reach_(max_reach) {
    // The interpolated copy of u needs reach + 3 halo layers (foot displacement, cubic
    // stencil, face offset), and a neighbour can only send the layers it owns.
    const Decomposition& dec = halos.decomposition();
    wide_halo_ = int(std::ceil(max_reach_)) + 3;
    for (int d = 0; d < dec.dim(); ++d) {
        const int thinnest = int(std::lround(dec.min(real(dec.block().cells[d]))));
        if (thinnest < wide_halo_)
            throw InputError(fmt::format(
                "body '{}': strain_velocity = \"surface\" needs every rank's block to be at "
                "least {} cells wide, but one is {} cells wide along {} ({} ranks along it); "
                "run on fewer ranks or set body.strain_velocity = \"local\"",
                body_name, wide_halo_, thinnest, "xyz"[d], dec.ranks_per_dim()[d]));
    }
}

void SurfaceVelocity::load(const VelocityField& u) {
    const Decomposition& dec = halos_.decomposition();
    const int dim = dec.dim();
    if (wide_.dim != dim || wide_[0].data().empty())
        wide_ = VelocityField("u_wide", dec.block(), dim, wide_halo_);
    for (int c = 0; c < dim; ++c)
        copy_rows(u[c], wide_[c], u[c].owned());
    finish_load(u);
}

void SurfaceVelocity::load(const VelocityField& u, std::span<const Box> patches) {
    const Decomposition& dec = halos_.decomposition();
    const GlobalGrid& g = dec.grid();
    const LocalBlock& block = dec.block();
    const int dim = dec.dim();
    if (wide_.dim != dim || wide_[0].data().empty())
        wide_ = VelocityField("u_wide", dec.block(), dim, wide_halo_);
    // compute() reads the source within its region (the patch and three layers) and at the
    // stencils of foot points less than the reach from the patch's faces: all within the
    // patch widened by the wide halo (reach + 3), one more layer for the high faces. A
    // halo cell there is a neighbour's (or, across a periodic direction, this rank's)
    // owned cell in the same widened box or one of its images a period away.
    const int m = wide_halo_ + 1;
    for (const Box& patch : patches) {
        if (patch.empty()) continue;
        Box widened = patch;
        for (int d = 0; d < dim; ++d) {
            widened.lo[d] -= m;
            widened.hi[d] += m;
        }
        for (int a = -1; a <= 1; ++a)
            for (int b = -1; b <= 1; ++b)
                for (int e = -1; e <= 1; ++e) {
                    const Int3 image{a * g.cells[0], dim > 1 ? b * g.cells[1] : 0,
                                     dim > 2 ? e * g.cells[2] : 0};
                    if ((dim < 2 && b != 0) || (dim < 3 && e != 0)) continue;
                    const Box local =
                        shifted(shifted(widened, image),
                                {-block.offset[0], -block.offset[1], -block.offset[2]});
                    for (int c = 0; c < dim; ++c)
                        copy_rows(u[c], wide_[c], intersect(local, u[c].owned()));
                }
    }
    finish_load(u);
}

void SurfaceVelocity::finish_load(const VelocityField& u) {
    const int dim = halos_.decomposition().dim();
    halos_.fill(wide_); // collective
    // The layout of the result; compute() sets u on each body's own region of it.
    if (out_.dim != dim || out_[0].data().empty()) out_ = u;
}

const VelocityField& SurfaceVelocity::compute(const Body& body, real eps_cells, real reach_cells) {
    const Decomposition& dec = halos_.decomposition();
    const GlobalGrid& g = dec.grid();
    const LocalBlock& block = dec.block();
    const int dim = g.dim;
    if (wide_.dim != dim || wide_[0].data().empty())
        throw std::logic_error("SurfaceVelocity::compute before load");
    if (reach_cells > max_reach_)
        throw std::logic_error("SurfaceVelocity::compute: reach beyond the halo's");
    // u (which wide_ holds on the owned faces) on the body's patch and three layers around
    // it, the faces its transport reads (the patch's faces and one layer past them), on every
    // rank's part of that box, so that the halos the fill below brings hold u there too. Out
    // of it the faces keep what an earlier body left: nothing reads them.
    Box region = body.patch().global;
    for (int d = 0; d < dim; ++d) {
        region.lo[d] -= 3;
        region.hi[d] += 3;
    }
    const Box own_global{block.offset,
                         {block.offset[0] + block.cells[0], block.offset[1] + block.cells[1],
                          block.offset[2] + block.cells[2]}};
    region = shifted(intersect(region, own_global),
                     {-block.offset[0], -block.offset[1], -block.offset[2]});
    for (int c = 0; c < dim; ++c)
        copy_rows(wide_[c], out_[c], region);
    if (body.patch().empty()) {
        halos_.fill(out_); // collective: every rank takes part, with or without the body
        return out_;
    }

    // psi = eps atanh(1 - 2 phi) on the patch, halos from the neighbours (phi's own halos
    // may be stale, e.g. right after a restart).
    const Field& phi = body.phi();
    const real h = g.dx(0);
    const real eps = eps_cells * h;
    if (psi_.data().empty() || psi_.begin() != phi.begin() || psi_.cells() != phi.cells())
        psi_ = Field::on_patch("psi", Location::Cell, phi.begin(), phi.cells(), dim);
    for_each_in(phi.owned(),
                [&](int i, int j, int k) { psi_(i, j, k) = profile_distance(phi(i, j, k), eps); });
    halos_.fill(psi_, body.patch());
    // Gradient of psi at a cell (central differences; one cell inside the stored box).
    auto grad_psi = [&](const Int3& p) { return central_gradient(psi_, g, p); };
    // Component c and its gradient at a point x, from the staggered grid of c in `wide_`.
    auto interpolate = [&](int c, const Real3& x) {
        Int3 base{0, 0, 0};
        std::array<std::array<real, 4>, 3> w{}, dw{};
        for (int d = 0; d < 3; ++d) {
            if (d >= dim) {
                w[d] = {0, 1, 0, 0};
                continue;
            }
            const real shift = d == c ? 0.0 : 0.5;
            const real t = (x[d] - g.origin[d]) / g.dx(d) - block.offset[d] - shift;
            base[d] = int(std::floor(t));
            w[d] = catmull_rom(t - base[d]);
            dw[d] = catmull_rom_slope(t - base[d]);
            for (real& v : dw[d])
                v /= g.dx(d);
        }
        return dim == 3 ? stencil_sum<3>(wide_[c], base, w, dw)
                        : stencil_sum<2>(wide_[c], base, w, dw);
    };
    // Owned faces of the patch's cells (both faces of each: the high one is the next
    // cell's low face). The band lies m >= 2 cells inside the patch, so the faces the
    // transport's stencil reaches past them are far from the surface and keep u.
    Box faces = body.patch().local;
    for (int d = 0; d < dim; ++d)
        faces.hi[d] = std::min(faces.hi[d] + 1, block.cells[d]);
    for (int c = 0; c < dim; ++c)
        for_each_in(faces, [&](int i, int j, int k) {
            const Int3 hi_cell{i, j, k}, lo_cell = shifted(hi_cell, c, -1);
            // The face's psi and grad psi from its two cells.
            const real s = 0.5 * (psi_(lo_cell) + psi_(hi_cell));
            // Full weight to reach - 1 cells, then a linear ramp to u: a switch would turn
            // round-off differences (another decomposition) into O(1) ones.
            const real weight = std::clamp(reach_cells - std::abs(s) / h, 0.0, 1.0);
            if (weight == 0) return;
            const Real3 ga = grad_psi(lo_cell), gb = grad_psi(hi_cell);
            Real3 gf{0, 0, 0};
            real g2 = 0;
            for (int d = 0; d < dim; ++d) {
                gf[d] = 0.5 * (ga[d] + gb[d]);
                g2 += gf[d] * gf[d];
            }
            // |grad psi| = 1 in a resolved band; where psi is not a distance (the centre of a
            // body under 5 cells in radius, sheared-off tails) the foot point means nothing:
            // u_e's weight falls linearly from |grad psi|^2 = 1/2 to 1/4.
            const real weight_g = std::clamp(4 * g2 - 1, 0.0, 1.0);
            if (weight_g == 0) return;
            // Foot point y = x - s n: |x - y| = |s| < reach, so the interpolation stencil
            // stays inside the wide halo.
            Real3 n{0, 0, 0};
            for (int d = 0; d < dim; ++d)
                n[d] = gf[d] / std::sqrt(g2);
            Real3 y = position(g, block, face_location(c), i, j, k);
            for (int d = 0; d < dim; ++d)
                y[d] -= s * n[d];
            // u(y) + s dn/dt, dn/dt = -P (grad u)^T n: only tangential derivatives of u at
            // the surface enter (those do not see the kink across the membrane).
            const ValueAndGradient uc = interpolate(c, y);
            Real3 gtn{0, 0, 0}; // (grad u)^T n at y
            for (int a = 0; a < dim; ++a) {
                const ValueAndGradient ua = a == c ? uc : interpolate(a, y);
                for (int d = 0; d < dim; ++d)
                    gtn[d] += n[a] * ua.gradient[d];
            }
            real ngtn = 0;
            for (int d = 0; d < dim; ++d)
                ngtn += n[d] * gtn[d];
            const real ue = uc.value - s * (gtn[c] - n[c] * ngtn);
            out_[c](i, j, k) += weight * weight_g * (ue - out_[c](i, j, k));
        });
    halos_.fill(out_);
    return out_;
}

} // namespace efsi
