// SplitMix64's finaliser (Steele, Lea & Flood 2014): a 64-bit mix in which every input bit
// changes about half the output bits. Used by the dataset checksums and the seeding's
// counter-based draws; both depend on its exact values (stored checksums, seeded scenes).
#pragma once

#include <cstdint>

namespace efsi {

inline std::uint64_t splitmix64(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

} // namespace efsi
