// Four reals in one vector, for kernels that evaluate four independent points at once
// (interface/thinc.hpp, mthinc_slab_integrals), and the functions such a kernel needs
// written once for one real and once for four, so that one template serves both.
//
// real4 is a GCC vector type: one AVX2 register on x86-64-v3, two SSE registers on older
// targets; its +, -, *, / and comparisons act lane by lane with IEEE rounding, so lane l
// of a real4 expression is bit for bit the same expression in reals. The same holds for
// exp and log here: the 4-lane and the one-real versions return the same value for the
// same argument (lanes.cpp).
#pragma once

#include "core/types.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace efsi {

using real4 = real __attribute__((vector_size(4 * sizeof(real))));
/// The result of comparing two real4: all bits set in a lane where it holds.
using mask4 = decltype(real4{} < real4{});

/// Number of lanes of a value type: 1 for real, 4 for real4.
template <class V>
inline constexpr int lane_count = sizeof(V) / sizeof(real);

/// The type of a comparison of two V: bool, or mask4.
template <class V>
using lane_mask = decltype(V{} < V{});

/// x in every lane.
template <class V>
V splat(real x) {
    if constexpr (lane_count<V> == 1)
        return x;
    else
        return V{x, x, x, x};
}

/// `yes ? x : y` lane by lane. For one real by bit masks: the compiler turns a plain
/// conditional into a branch, which in an iteration goes either way at random and costs a
/// pipeline flush when mispredicted. For real4 a blend.
inline real select(bool yes, real x, real y) {
    const std::uint64_t mask = -std::uint64_t(yes);
    return std::bit_cast<real>((std::bit_cast<std::uint64_t>(x) & mask) |
                               (std::bit_cast<std::uint64_t>(y) & ~mask));
}
inline real4 select(mask4 yes, real4 x, real4 y) {
    return yes ? x : y;
}

/// std::min lane by lane: (b < a) ? b : a.
template <class V>
V lane_min(V a, V b) {
    return select(b < a, b, a);
}

/// |x| and sqrt(x) lane by lane (|x| clears the sign bit, as std::abs).
inline real lane_abs(real x) {
    return std::abs(x);
}
inline real4 lane_abs(real4 x) {
    return real4(mask4(x) & std::numeric_limits<std::int64_t>::max());
}
inline real lane_sqrt(real x) {
    return std::sqrt(x);
}
inline real4 lane_sqrt(real4 x) {
    return real4{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
}

/// Whether a comparison holds in every lane.
inline bool all_lanes(bool m) {
    return m;
}
inline bool all_lanes(mask4 m) {
    return (m[0] & m[1] & m[2] & m[3]) != 0;
}

/// Lane l of v (a real has one lane).
inline real lane(real v, int) {
    return v;
}
inline real lane(const real4& v, int l) {
    return v[l];
}
inline bool lane(bool v, int) {
    return v;
}
inline bool lane(const mask4& v, int l) {
    return v[l] != 0;
}
/// exp and log of each lane. With glibc's vector math library (libmvec, AVX2 builds) both
/// versions evaluate its 4-lane functions (the one-real version in lane 0), whose result
/// in a lane depends on that lane's argument only; without it both are std::exp and
/// std::log. Either way lane_exp(x)[l] == lane_exp(x[l]) bit for bit.
real lane_exp(real x);
real4 lane_exp(real4 x);
real lane_log(real x);
real4 lane_log(real4 x);

} // namespace efsi
