#include "adhesion/placement.hpp"

#include "adhesion/counter_rng.hpp"
#include "core/error.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace efsi::adhesion {

namespace {

/// Area element of the ellipsoid over that of the unit sphere at the sphere point p.
real area_ratio(const Real3& s, const Real3& p) {
    const real gx = s[1] * s[2] * p[0], gy = s[0] * s[2] * p[1], gz = s[0] * s[1] * p[2];
    return std::sqrt(gx * gx + gy * gy + gz * gz);
}

void check_axes(const Real3& s) {
    for (int a = 0; a < 3; ++a)
        if (!(s[a] > 0) || !std::isfinite(s[a]))
            throw InputError(fmt::format("adhesion: receptor surface semi-axes ({:g}, {:g}, {:g}) "
                                         "m must be positive",
                                         s[0], s[1], s[2]));
}

} // namespace

real ellipsoid_area(const Real3& semi_axes) {
    check_axes(semi_axes);
    constexpr int nu = 2048, nphi = 256;
    const real dphi = 2 * std::numbers::pi / nphi, du = 2.0 / nu;
    real sum = 0;
    for (int i = 0; i < nu; ++i) {
        const real u = -1 + (i + 0.5) * du, s = std::sqrt(1 - u * u);
        real ring = 0;
        for (int j = 0; j < nphi; ++j) {
            const real phi = j * dphi;
            ring += area_ratio(semi_axes, {s * std::cos(phi), s * std::sin(phi), u});
        }
        sum += ring;
    }
    return sum * du * dphi;
}

std::vector<Receptor> place_receptors(const SurfaceEllipsoid& surface, std::uint64_t count,
                                      std::uint64_t first_id, std::uint64_t seed) {
    check_axes(surface.semi_axes);
    if (count > 0 && first_id + (count - 1) > max_receptor_id)
        throw InputError(fmt::format("adhesion: receptor ids up to {} exceed the counter layout "
                                     "(ids must be < 2^56)",
                                     first_id + count - 1));
    const Real3& s = surface.semi_axes;
    const real g_max = std::max({s[1] * s[2], s[0] * s[2], s[0] * s[1]});
    // The acceptance probability is at least min g / max g >= (min axis / max axis): with
    // the validated axis ratios a receptor needs a handful of attempts; 1e5 is never reached
    // unless the shape is degenerate.
    constexpr std::uint64_t max_attempts = 100000;
    std::vector<Receptor> out;
    out.reserve(count);
    for (std::uint64_t k = 0; k < count; ++k) {
        const std::uint64_t id = first_id + k;
        Real3 p{};
        bool kept = false;
        for (std::uint64_t attempt = 0; attempt < max_attempts && !kept; ++attempt) {
            const UniformPair u = uniform_pair(seed, id, attempt, Purpose::place);
            const real z = 2 * u.u0 - 1, rho = std::sqrt(std::max(real(0), 1 - z * z));
            const real phi = 2 * std::numbers::pi * u.u1;
            p = {rho * std::cos(phi), rho * std::sin(phi), z};
            kept = uniform_pair(seed, id, attempt, Purpose::place_accept).u0 * g_max <=
                   area_ratio(s, p);
        }
        if (!kept)
            throw InputError(fmt::format("adhesion: could not place receptor {} on the ellipsoid "
                                         "with semi-axes ({:g}, {:g}, {:g}) m",
                                         id, s[0], s[1], s[2]));
        const Real3 y{s[0] * p[0], s[1] * p[1], s[2] * p[2]};
        Receptor r;
        r.id = id;
        for (int a = 0; a < 3; ++a)
            r.x[a] = surface.centre[a] + surface.rotation[a][0] * y[0] +
                     surface.rotation[a][1] * y[1] + surface.rotation[a][2] * y[2];
        out.push_back(r);
    }
    return out;
}

} // namespace efsi::adhesion
