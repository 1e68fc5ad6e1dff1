// Half-open index boxes [lo, hi): a body's region of the grid.
#pragma once

#include "core/types.hpp"

#include <algorithm>

namespace efsi {

struct Box {
    Int3 lo{0, 0, 0};
    Int3 hi{0, 0, 0};

    Int3 size() const {
        return {std::max(0, hi[0] - lo[0]), std::max(0, hi[1] - lo[1]), std::max(0, hi[2] - lo[2])};
    }
    bool empty() const { return hi[0] <= lo[0] || hi[1] <= lo[1] || hi[2] <= lo[2]; }
    std::int64_t count() const {
        const Int3 s = size();
        return std::int64_t(s[0]) * s[1] * s[2];
    }
    bool contains(const Box& b) const {
        for (int d = 0; d < 3; ++d)
            if (b.lo[d] < lo[d] || b.hi[d] > hi[d]) return false;
        return true;
    }
    bool operator==(const Box&) const = default;
};

inline Box intersect(const Box& a, const Box& b) {
    Box r;
    for (int d = 0; d < 3; ++d) {
        r.lo[d] = std::max(a.lo[d], b.lo[d]);
        r.hi[d] = std::min(a.hi[d], b.hi[d]);
    }
    return r;
}

inline Box shifted(Box b, const Int3& by) {
    for (int d = 0; d < 3; ++d) {
        b.lo[d] += by[d];
        b.hi[d] += by[d];
    }
    return b;
}

/// Loop over the points of a box: f(i,j,k).
template <class F>
inline void for_each_in(const Box& b, F&& f) {
    for (int k = b.lo[2]; k < b.hi[2]; ++k)
        for (int j = b.lo[1]; j < b.hi[1]; ++j)
            for (int i = b.lo[0]; i < b.hi[0]; ++i)
                f(i, j, k);
}

} // namespace efsi
