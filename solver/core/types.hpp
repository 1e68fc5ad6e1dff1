// Precision and small fixed-size vectors, in one place.
#pragma once

#include <array>
#include <cstdint>

namespace efsi {

/// Floating-point type of every field. Change here (and only here) for single precision.
using real = double;

/// Number of spatial directions the code is written for; 2D runs use the first two.
inline constexpr int max_dim = 3;

using Int3 = std::array<int, 3>;
using Real3 = std::array<real, 3>;
using Bool3 = std::array<bool, 3>;

/// Unit offset in direction d, for stencils written once for all directions.
constexpr Int3 unit(int d) {
    Int3 e{0, 0, 0};
    e[d] = 1;
    return e;
}

} // namespace efsi
