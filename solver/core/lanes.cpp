// exp and log of one real and of four (core/lanes.hpp). With EFSI_LIBMVEC (set by the
// build when it finds libmvec and the target has AVX2), glibc's 4-lane functions: one call
// for four values where std::exp or std::log takes four, accurate to a few ulp (not
// correctly rounded, so not bit for bit std::exp); a single real goes through lane 0 of the
// same function, so that a scalar code path and a 4-lane one agree exactly.
#include "core/lanes.hpp"

#include <cmath>

#if defined(EFSI_LIBMVEC) && defined(__AVX2__)
#include <immintrin.h>

static_assert(sizeof(efsi::real) == 8, "libmvec's 4-lane AVX2 functions take doubles");

// glibc's vector ABI names: _ZGV, d = AVX2, N = unmasked, 4 lanes, v = a vector argument.
extern "C" __m256d _ZGVdN4v_exp(__m256d);
extern "C" __m256d _ZGVdN4v_log(__m256d);

namespace efsi {

real4 lane_exp(real4 x) {
    return _ZGVdN4v_exp(x);
}
real4 lane_log(real4 x) {
    return _ZGVdN4v_log(x);
}
real lane_exp(real x) {
    return _ZGVdN4v_exp(_mm256_set1_pd(x))[0];
}
real lane_log(real x) {
    return _ZGVdN4v_log(_mm256_set1_pd(x))[0];
}

} // namespace efsi

#else

namespace efsi {

real lane_exp(real x) {
    return std::exp(x);
}
real lane_log(real x) {
    return std::log(x);
}
real4 lane_exp(real4 x) {
    return real4{std::exp(x[0]), std::exp(x[1]), std::exp(x[2]), std::exp(x[3])};
}
real4 lane_log(real4 x) {
    return real4{std::log(x[0]), std::log(x[1]), std::log(x[2]), std::log(x[3])};
}

} // namespace efsi

#endif
