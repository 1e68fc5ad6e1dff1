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

/// A small 3x3 matrix or tensor (rotation, velocity gradient, B, Gs, stress), row-major:
/// M[i][j]. The one small-tensor type of the code (see docs/method.md, "Small tensors").
using Matrix3 = std::array<Real3, 3>;

// Int3 arithmetic: cell offsets p + q, p - q, -p, s * p (stencils, patch corners).
constexpr Int3 operator+(const Int3& a, const Int3& b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
constexpr Int3 operator-(const Int3& a, const Int3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
constexpr Int3 operator-(const Int3& a) {
    return {-a[0], -a[1], -a[2]};
}
constexpr Int3 operator*(int s, const Int3& a) {
    return {s * a[0], s * a[1], s * a[2]};
}
constexpr Int3& operator+=(Int3& a, const Int3& b) {
    return a = a + b;
}
constexpr Int3& operator-=(Int3& a, const Int3& b) {
    return a = a - b;
}

/// Unit offset in direction d, for stencils written once for all directions.
constexpr Int3 unit(int d) {
    Int3 e{0, 0, 0};
    e[d] = 1;
    return e;
}

} // namespace efsi
