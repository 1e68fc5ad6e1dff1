// Counter-based random numbers for the adhesion kinetics: Philox-4x32-10 (Salmon, Moraes,
// Dror & Shaw, "Parallel random numbers: as easy as 1, 2, 3", SC'11), a keyed bijection of a
// 128-bit counter. A draw is a pure function of (seed, receptor id, step, purpose): there is
// no generator state, so a receptor's draws are the same whichever rank owns it, in whatever
// order the receptors are processed, and however many draws other receptors made.
//
// Layout: key = the 64-bit seed; counter = (id low 32 bits, id high 24 bits | purpose << 24,
// step low 32 bits, step high 32 bits). Receptor ids must be < 2^56 (checked), purposes < 256.
#pragma once

#include "core/error.hpp"

#include <array>
#include <cstdint>
#include <string>

namespace efsi::adhesion {

using Philox4x32 = std::array<std::uint32_t, 4>;

/// Philox-4x32 with 10 rounds (the Random123 reference variant; its known-answer vectors
/// are in tests/adhesion/test_adhesion_rng.cpp).
constexpr Philox4x32 philox4x32_10(Philox4x32 ctr, std::array<std::uint32_t, 2> key) {
    constexpr std::uint32_t M0 = 0xD2511F53u, M1 = 0xCD9E8D57u;
    constexpr std::uint32_t W0 = 0x9E3779B9u, W1 = 0xBB67AE85u;
    for (int round = 0; round < 10; ++round) {
        const std::uint64_t p0 = std::uint64_t{M0} * ctr[0];
        const std::uint64_t p1 = std::uint64_t{M1} * ctr[2];
        const auto hi0 = static_cast<std::uint32_t>(p0 >> 32), lo0 = static_cast<std::uint32_t>(p0);
        const auto hi1 = static_cast<std::uint32_t>(p1 >> 32), lo1 = static_cast<std::uint32_t>(p1);
        ctr = {hi1 ^ ctr[1] ^ key[0], lo1, hi0 ^ ctr[3] ^ key[1], lo0};
        key[0] += W0;
        key[1] += W1;
    }
    return ctr;
}

/// What a draw is for: distinct purposes give independent numbers for the same receptor
/// and step.
enum class Purpose : std::uint32_t {
    bind = 1,         ///< does a free receptor bind this step; which ligand it picks
    priority = 2,     ///< who wins when several receptors pick the same ligand
    rupture = 3,      ///< does a bond break this step
    place = 4,        ///< receptor placement: a point on the unit sphere (step = attempt)
    place_accept = 5, ///< receptor placement: is that point kept (uniform area)
    test = 255,       ///< reserved for the tests
};

inline constexpr std::uint64_t max_receptor_id = (std::uint64_t{1} << 56) - 1;

/// Two independent uniform doubles in the open interval (0, 1): 52 random bits each, as
/// (2k + 1) 2^-53 with k < 2^52, exact in double, never 0 or 1 (so log(u) is always finite).
struct UniformPair {
    double u0;
    double u1;
};

constexpr double to_unit_open(std::uint32_t hi, std::uint32_t lo) {
    const std::uint64_t bits = ((std::uint64_t{hi} << 32) | lo) >> 12; // 52 bits
    return (static_cast<double>(bits) + 0.5) * 0x1.0p-52;
}

/// The draw of receptor `id` at `step` for `purpose` under `seed`.
inline UniformPair uniform_pair(std::uint64_t seed, std::uint64_t id, std::uint64_t step,
                                Purpose purpose) {
    if (id > max_receptor_id)
        throw InputError("adhesion: receptor id " + std::to_string(id) +
                         " exceeds the counter layout (ids must be < 2^56)");
    const Philox4x32 ctr{static_cast<std::uint32_t>(id),
                         static_cast<std::uint32_t>(id >> 32) |
                             (static_cast<std::uint32_t>(purpose) << 24),
                         static_cast<std::uint32_t>(step), static_cast<std::uint32_t>(step >> 32)};
    const Philox4x32 r = philox4x32_10(
        ctr, {static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)});
    return {to_unit_open(r[0], r[1]), to_unit_open(r[2], r[3])};
}

} // namespace efsi::adhesion
