#include "bodies/transport.hpp"

#include "operators/flow_operators.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

namespace efsi {

namespace {

/// van Leer's limited slope from the backward and forward differences.
inline real van_leer(real a, real b) {
    return a * b > 0 ? 2 * a * b / (a + b) : 0.0;
}

/// MUSCL value of s on the low d-face of cell p, upwinded by the face velocity w.
inline real face_value(const Field& s, int d, const Int3& p, real w) {
    if (w >= 0) { // from cell p - e_d
        const Int3 q = shifted(p, d, -1);
        const real sq = s(q);
        return sq + 0.5 * van_leer(sq - s(shifted(q, d, -1)), s(p) - sq);
    }
    const real sp = s(p);
    return sp - 0.5 * van_leer(sp - s(shifted(p, d, -1)), s(shifted(p, d, 1)) - sp);
}

} // namespace

Matrix3 velocity_gradient_at(const VelocityField& u, const GlobalGrid& g, const Int3& p) {
    Matrix3 L{};
    for (int i = 0; i < u.dim; ++i)
        for (int j = 0; j < u.dim; ++j) {
            if (i == j) {
                L[i][i] = (u[i](shifted(p, i, 1)) - u[i](p)) / g.dx(i);
            } else {
                const Int3 f1 = p, f2 = shifted(p, i, 1); // the cell's two i-faces
                const real c1 = u[i](shifted(f1, j, 1)) - u[i](shifted(f1, j, -1));
                const real c2 = u[i](shifted(f2, j, 1)) - u[i](shifted(f2, j, -1));
                L[i][j] = 0.25 * (c1 + c2) / g.dx(j);
            }
        }
    return L;
}

real advection_rate_at(const Field& s, const VelocityField& u, const GlobalGrid& g, const Int3& p) {
    real rate = 0;
    const real sp = s(p);
    for (int d = 0; d < u.dim; ++d) {
        const Int3 ph = shifted(p, d, 1);
        const real wl = u[d](p), wh = u[d](ph);
        const real flux_div = (wh * face_value(s, d, ph, wh) - wl * face_value(s, d, p, wl));
        rate -= (flux_div - sp * (wh - wl)) / g.dx(d);
    }
    return rate;
}

namespace {

/// van_leer() without a branch: the inputs of the division are selected (0 / 1 where the
/// limiter is off), never its result, so every operation runs in every lane and the loops
/// that call it vectorise (an operation under a condition that may trap is not speculated).
inline real van_leer_select(real a, real b) {
    const bool limited = a * b > 0;
    const real num = limited ? 2 * a * b : real(0);
    const real den = limited ? a + b : real(1);
    return num / den;
}

/// face_value() on a raw row: the low face (stride st) of the point s[0], upwinded by w; the
/// upwind cell's value and differences are selected first, so one limiter serves both sides
/// (c - x is c + (-x) exactly, so the sign is a factor).
inline real face_value_row(const real* s, std::ptrdiff_t st, real w) {
    const real sm2 = s[-2 * st], sm1 = s[-st], s0 = s[0], sp1 = s[st];
    const real d1 = sm1 - sm2, d2 = s0 - sm1, d3 = sp1 - s0;
    const bool up = w >= 0;
    const real c = up ? sm1 : s0;
    const real a = up ? d1 : d2;
    const real b = up ? d2 : d3;
    return c + (up ? real(0.5) : real(-0.5)) * van_leer_select(a, b);
}

/// Asks the cache for the n values from p on (a hint: no value changes). The sweeps read
/// about forty rows at a time (every field at four planes, the velocity, the outputs), more
/// streams than the hardware prefetchers follow, so the rows first read from memory at the
/// next row are named one row ahead. A prefetch never faults, so asking past the patch's
/// last rows is harmless.
template <bool Write = false>
inline void prefetch_row(const real* p, int n) {
    constexpr int line = 64 / sizeof(real);
    for (int i = 0; i < n + line; i += line)
        __builtin_prefetch(p + i, Write ? 1 : 0);
}

/// The y or z term of advection_rate_at on a row: rate -= (flux_div - s div_d u) / h_d, the
/// low faces' fluxes taken from `flo`, which receives the high faces' for the next row.
inline void transverse_term(const real* __restrict f, const real* __restrict wd, std::ptrdiff_t sud,
                            std::ptrdiff_t spd, real id, int n0, real* __restrict flo,
                            real* __restrict rate) {
    for (int i = 0; i < n0; ++i) {
        const real wl = wd[i], wh = wd[i + sud];
        const real fhi = wh * face_value_row(f + i + spd, spd, wh);
        const real flux_div = fhi - flo[i];
        rate[i] -= (flux_div - f[i] * (wh - wl)) * id;
        flo[i] = fhi;
    }
}

/// Rates of the tensor's stored components (if any) and of the scalars on `box`, row by row:
/// for each row (j, k), or each run of a row that `spans` names (null: every row whole), and
/// field s (the tensor's components in slot order, then the scalars) calls finish(s, offset,
/// rate, n0, next), `offset` the index of the run's first point in the patch fields,
/// rate[0..n0) its rates and offset + next the next row's (to prefetch). A scalar k with
/// source[k] = a >= 0 has the source -v_a (cell-centre mean of its two a-faces): the offset
/// X - x of a reference map X, whose material derivative is -v. Exactly the pointwise kernels'
/// expressions (with 1/h), whichever cells are asked for.
template <int Dim, class Finish>
void rate_rows(const Box& box, const RowSpans* spans, const SymmetricTensorField* t,
               const std::vector<const Field*>& sc, const std::vector<int>& source,
               const VelocityField& u, const GlobalGrid& g, Finish&& finish) {
    if (box.empty()) return;
    if (!t && sc.empty()) return;
    const Field& lay = t ? t->comp[0] : *sc[0];
    for (int d = 1; d < Dim; ++d)
        if (u[d].extent() != u[0].extent() || u[d].begin() != u[0].begin())
            throw std::logic_error("transport: velocity components differ in layout");
    if (t)
        for (const Field& c : t->comp)
            if (c.extent() != lay.extent() || c.begin() != lay.begin())
                throw std::logic_error("transport: tensor components differ in layout");
    for (const Field* c : sc)
        if (c->extent() != lay.extent() || c->begin() != lay.begin())
            throw std::logic_error("transport: a scalar differs from the tensor in layout");
    const int n = t ? (Dim == 2 ? 3 : 6) : 0;
    const int nfields = n + int(sc.size());
    std::ptrdiff_t su[3] = {1, std::ptrdiff_t(u[0].extent()[0]),
                            std::ptrdiff_t(u[0].extent()[0]) * u[0].extent()[1]};
    std::ptrdiff_t sp[3] = {1, std::ptrdiff_t(lay.extent()[0]),
                            std::ptrdiff_t(lay.extent()[0]) * lay.extent()[1]};
    real inv[3];
    for (int d = 0; d < 3; ++d)
        inv[d] = d < Dim ? 1.0 / g.dx(d) : 0.0;
    // The stored (a, b) of each slot, and the slot of each (a, b).
    int pa[6], pb[6], slot[3][3];
    for (int a = 0; a < Dim; ++a)
        for (int b = 0; b < Dim; ++b) {
            slot[a][b] = SymmetricTensorField::slot(a, b, Dim);
            pa[slot[a][b]] = std::min(a, b);
            pb[slot[a][b]] = std::max(a, b);
        }
    const int nb = box.hi[0] - box.lo[0];
    // Run buffers: L (Dim x Dim rows), the x-face fluxes (n0 + 1) and the rates.
    std::vector<real> buf(std::size_t(nb) * (Dim * Dim + 1) + std::size_t(nb) + 1);
    real* Lrow[3][3] = {};
    for (int a = 0; a < Dim; ++a)
        for (int c = 0; c < Dim; ++c)
            Lrow[a][c] = buf.data() + std::size_t(a * Dim + c) * nb;
    real* __restrict rate = buf.data() + std::size_t(Dim * Dim) * nb;
    real* __restrict fx = rate + nb;
    // The flux through the low y-face of a cell is the high one of the cell below it, and the
    // low z-face's that of the cell behind it: kept per field (fy: one row, fz: one plane) with
    // the row (plane) that stored it, and computed afresh where that is not the row (plane)
    // just before (the box's first row and plane; a run that starts or ends elsewhere than the
    // one below it), so every face is computed once where the runs line up, and always by the
    // same expression.
    const int n1 = box.hi[1] - box.lo[1];
    std::vector<real> fy_buf(std::size_t(nfields) * nb);
    std::vector<real> fz_buf(Dim > 2 ? std::size_t(nfields) * nb * n1 : 0);
    std::vector<int> fy_row(std::size_t(nb), std::numeric_limits<int>::min());
    std::vector<int> fz_plane(Dim > 2 ? std::size_t(nb) * n1 : 0, std::numeric_limits<int>::min());
    const real* ubase[3] = {};
    for (int d = 0; d < Dim; ++d)
        ubase[d] = u[d].data().data();
    auto run = [&](int j, int k, int lo, int hi) {
        const int n0 = hi - lo;
        const int ib = lo - box.lo[0]; // the run's first point in the box's row buffers
        const std::ptrdiff_t ru = std::ptrdiff_t(u[0].index(lo, j, k));
        const std::ptrdiff_t rp = std::ptrdiff_t(lay.index(lo, j, k));
        // The next row's leading values: each field's at the plane (2D: row) two
        // ahead, where the transverse stencil first reaches, and the velocity's one ahead.
        const std::ptrdiff_t lead = Dim > 2 ? sp[1] + 2 * sp[2] : 3 * sp[1];
        const std::ptrdiff_t lead_u = Dim > 2 ? su[1] + su[2] : 2 * su[1];
        for (int s = 0; s < nfields; ++s)
            prefetch_row((s < n ? t->comp[s] : *sc[s - n]).data().data() + rp + lead - 2, n0 + 4);
        for (int d = 0; d < Dim; ++d)
            prefetch_row(ubase[d] + ru + lead_u - 1, n0 + 2);
        // Which of the run's low y- and z-face fluxes the row (plane) before stored: all
        // (the usual case), none, or some (then face by face).
        const int row = (k - box.lo[2]) * n1 + (j - box.lo[1]);
        enum class Kept { All, None, Some };
        auto kept = [&](const int* stamp, int want) {
            int hits = 0;
            for (int i = 0; i < n0; ++i)
                hits += stamp[i] == want;
            return hits == n0 ? Kept::All : hits == 0 ? Kept::None : Kept::Some;
        };
        int* ystamp = fy_row.data() + ib;
        int* zstamp = Dim > 2 ? fz_plane.data() + std::size_t(j - box.lo[1]) * nb + ib : nullptr;
        const Kept ykept = j > box.lo[1] ? kept(ystamp, row - 1) : Kept::None;
        const Kept zkept = Dim > 2 && k > box.lo[2] ? kept(zstamp, k - 1) : Kept::None;
        // L on the run (velocity_gradient_at), for the tensor's source only.
        for (int a = 0; n > 0 && a < Dim; ++a) {
            const real* __restrict ua = ubase[a] + ru;
            const std::ptrdiff_t sa = su[a];
            for (int c = 0; c < Dim; ++c) {
                real* __restrict l = Lrow[a][c];
                if (a == c) {
                    const real ia = inv[a];
                    for (int i = 0; i < n0; ++i)
                        l[i] = (ua[i + sa] - ua[i]) * ia;
                } else {
                    const std::ptrdiff_t so = su[c];
                    const real ic = inv[c];
                    for (int i = 0; i < n0; ++i) {
                        const real c1 = ua[i + so] - ua[i - so];
                        const real c2 = ua[i + sa + so] - ua[i + sa - so];
                        l[i] = 0.25 * (c1 + c2) * ic;
                    }
                }
            }
        }
        const real* __restrict w0 = ubase[0] + ru;
        for (int s = 0; s < nfields; ++s) {
            const real* __restrict f = (s < n ? t->comp[s] : *sc[s - n]).data().data() + rp;
            // x-face fluxes w s_face, faces i - 1/2 for i = 0..n0.
            for (int i = 0; i <= n0; ++i)
                fx[i] = w0[i] * face_value_row(f + i, 1, w0[i]);
            // advection_rate_at: the x term, then y (and z).
            for (int i = 0; i < n0; ++i) {
                real r = 0;
                r -= ((fx[i + 1] - fx[i]) - f[i] * (w0[i + 1] - w0[i])) * inv[0];
                rate[i] = r;
            }
            for (int d = 1; d < Dim; ++d) {
                const real* __restrict wd = ubase[d] + ru;
                const std::ptrdiff_t sud = su[d], spd = sp[d];
                const real id = inv[d];
                real* __restrict flo =
                    d == 1 ? fy_buf.data() + std::size_t(s) * nb + ib
                           : fz_buf.data() + (std::size_t(s) * n1 + (j - box.lo[1])) * nb + ib;
                const Kept have = d == 1 ? ykept : zkept;
                const int* stamp = d == 1 ? ystamp : zstamp;
                const int want = d == 1 ? row - 1 : k - 1;
                if (have == Kept::None) {
                    for (int i = 0; i < n0; ++i)
                        flo[i] = wd[i] * face_value_row(f + i, spd, wd[i]);
                } else if (have == Kept::Some) {
                    for (int i = 0; i < n0; ++i)
                        if (stamp[i] != want) flo[i] = wd[i] * face_value_row(f + i, spd, wd[i]);
                }
                transverse_term(f, wd, sud, spd, id, n0, flo, rate);
            }
            if (s < n) {
                // + (L T + T L^T)_ab
                const int a = pa[s], b = pb[s];
                const real* __restrict T[3][3] = {};
                for (int x = 0; x < Dim; ++x)
                    for (int y = 0; y < Dim; ++y)
                        T[x][y] = t->comp[slot[x][y]].data().data() + rp;
                const real* __restrict La[3] = {Lrow[a][0], Lrow[a][1], Lrow[a][Dim - 1]};
                const real* __restrict Lb[3] = {Lrow[b][0], Lrow[b][1], Lrow[b][Dim - 1]};
                // The rate row, the rows of L and of T are distinct buffers (too many
                // pointers for GCC to check at run time, so it is told).
#pragma GCC ivdep
                for (int i = 0; i < n0; ++i) {
                    real src = 0;
#pragma GCC unroll 3
                    for (int c = 0; c < Dim; ++c)
                        src += La[c][i] * T[c][b][i] + T[a][c][i] * Lb[c][i];
                    // 2D: the pointwise kernel adds the (zero) c = z term too.
                    if constexpr (Dim == 2) src += real(0);
                    rate[i] = rate[i] + src;
                }
            } else if (const int a = source[s - n]; a >= 0) {
                // - v_a at the cell centre
                const real* __restrict ua = ubase[a] + ru;
                const std::ptrdiff_t sa = su[a];
                for (int i = 0; i < n0; ++i)
                    rate[i] -= 0.5 * (ua[i] + ua[i + sa]);
            }
            finish(s, rp, static_cast<const real*>(rate), n0, sp[1]);
        }
        for (int i = 0; i < n0; ++i)
            ystamp[i] = row;
        if (Dim > 2)
            for (int i = 0; i < n0; ++i)
                zstamp[i] = k;
    };
    if (spans) {
        for (const RowSpan& r : *spans) {
            const int lo = std::max(r.lo, box.lo[0]), hi = std::min(r.hi, box.hi[0]);
            if (lo < hi && r.j >= box.lo[1] && r.j < box.hi[1] && r.k >= box.lo[2] &&
                r.k < box.hi[2])
                run(r.j, r.k, lo, hi);
        }
        return;
    }
    for (int k = box.lo[2]; k < box.hi[2]; ++k)
        for (int j = box.lo[1]; j < box.hi[1]; ++j)
            run(j, k, box.lo[0], box.hi[0]);
}

template <class Finish>
void rate_rows(const Box& box, const RowSpans* spans, const SymmetricTensorField* t,
               const std::vector<const Field*>& sc, const std::vector<int>& source,
               const VelocityField& u, const GlobalGrid& g, Finish&& finish) {
    if (g.dim == 3)
        rate_rows<3>(box, spans, t, sc, source, u, g, finish);
    else
        rate_rows<2>(box, spans, t, sc, source, u, g, finish);
}

std::vector<const Field*> one_or_none(const Field* kappa) {
    return kappa ? std::vector<const Field*>{kappa} : std::vector<const Field*>{};
}

} // namespace

std::vector<RowSpans> band_spans(const Field& phi, const Box& box, real lo,
                                 const std::vector<int>& reaches) {
    std::vector<RowSpans> out(reaches.size());
    if (box.empty()) return out;
    const int reach = reaches.empty() ? 0 : *std::max_element(reaches.begin(), reaches.end());
    // The box widened by the reach (within phi's halo: none along a direction without one,
    // z in 2D), the band marked on it, then widened by the reach direction by direction with
    // a running count (a cell is kept when its window holds a band cell).
    Int3 r{0, 0, 0}, e0{}, n{};
    for (int d = 0; d < 3; ++d) {
        r[d] = std::min(reach, phi.halo()[d]);
        e0[d] = box.lo[d] - r[d];
        n[d] = box.hi[d] - box.lo[d] + 2 * r[d];
    }
    const std::size_t sy = std::size_t(n[0]), sz = sy * std::size_t(n[1]);
    std::vector<unsigned char> m(sz * std::size_t(n[2])), w(m.size());
    const real hi = 1 - lo;
    for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j) {
            const real* f = phi.data().data() + phi.index(e0[0], e0[1] + j, e0[2] + k);
            unsigned char* row = m.data() + std::size_t(k) * sz + std::size_t(j) * sy;
            for (int i = 0; i < n[0]; ++i)
                row[i] = f[i] >= lo && f[i] <= hi;
        }
    // One direction: out[x] = 1 where in[x - rd .. x + rd] (along d, within the box) holds a 1.
    auto widen = [&](const std::vector<unsigned char>& in, std::vector<unsigned char>& to, int d) {
        if (r[d] == 0) {
            to = in;
            return;
        }
        const std::size_t st[3] = {1, sy, sz};
        if (d > 0) {
            // Along y (z): the window's count of every cell of a row (plane) at once, rows
            // (planes) added and removed whole, so the inner loops run along x, unit stride.
            // A count never exceeds the window's 2 r + 1 cells, so a byte holds it.
            const std::size_t len = st[d]; // cells of one row (plane)
            const int outer = d == 1 ? n[2] : 1;
            std::vector<unsigned char> count(len);
            for (int q2 = 0; q2 < outer; ++q2) {
                const unsigned char* src = in.data() + std::size_t(q2) * sz;
                unsigned char* dst = to.data() + std::size_t(q2) * sz;
                std::fill(count.begin(), count.end(), 0);
                auto add = [&](int q, int sign) {
                    const unsigned char* s = src + std::size_t(q) * st[d];
                    unsigned char* c = count.data();
                    if (sign > 0)
                        for (std::size_t i = 0; i < len; ++i)
                            c[i] += s[i];
                    else
                        for (std::size_t i = 0; i < len; ++i)
                            c[i] -= s[i];
                };
                for (int q = 0; q < std::min(r[d], n[d]); ++q)
                    add(q, 1);
                for (int q = 0; q < n[d]; ++q) {
                    if (q + r[d] < n[d]) add(q + r[d], 1);
                    if (q - r[d] - 1 >= 0) add(q - r[d] - 1, -1);
                    unsigned char* o = dst + std::size_t(q) * st[d];
                    const unsigned char* c = count.data();
                    for (std::size_t i = 0; i < len; ++i)
                        o[i] = c[i] > 0;
                }
            }
            return;
        }
        const int a = 1, b = 2; // the other two directions
        for (int q2 = 0; q2 < n[b]; ++q2)
            for (int q1 = 0; q1 < n[a]; ++q1) {
                const unsigned char* src =
                    in.data() + std::size_t(q1) * st[a] + std::size_t(q2) * st[b];
                unsigned char* dst = to.data() + std::size_t(q1) * st[a] + std::size_t(q2) * st[b];
                int count = 0;
                for (int q = 0; q < std::min(r[d], n[d]); ++q)
                    count += src[std::size_t(q) * st[d]];
                for (int q = 0; q < n[d]; ++q) {
                    if (q + r[d] < n[d]) count += src[std::size_t(q + r[d]) * st[d]];
                    if (q - r[d] - 1 >= 0) count -= src[std::size_t(q - r[d] - 1) * st[d]];
                    dst[std::size_t(q) * st[d]] = count > 0;
                }
            }
    };
    // The reaches in increasing order, each widening the last (a cube widened by a and then by
    // b is the cube widened by a + b; within the box widened by the largest reach, the box's
    // cells see every band cell that the largest reach reaches).
    std::vector<std::size_t> order(reaches.size());
    for (std::size_t q = 0; q < order.size(); ++q)
        order[q] = q;
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return reaches[a] < reaches[b]; });
    Int3 done{0, 0, 0};
    for (std::size_t q : order) {
        for (int d = 0; d < 3; ++d) {
            const int want = std::min(reaches[q], phi.halo()[d]);
            r[d] = want - done[d];
            done[d] = want;
        }
        widen(m, w, 0);
        widen(w, m, 1);
        widen(m, w, 2);
        m = w;
        // The runs of the box's rows.
        const int nx = box.hi[0] - box.lo[0];
        const int r0 = std::min(reach, phi.halo()[0]);
        for (int k = box.lo[2]; k < box.hi[2]; ++k)
            for (int j = box.lo[1]; j < box.hi[1]; ++j) {
                const unsigned char* row = m.data() + std::size_t(k - e0[2]) * sz +
                                           std::size_t(j - e0[1]) * sy + std::size_t(r0);
                for (int i = 0; i < nx;) {
                    if (!row[i]) {
                        ++i;
                        continue;
                    }
                    int e = i;
                    while (e < nx && row[e])
                        ++e;
                    out[q].push_back({j, k, box.lo[0] + i, box.lo[0] + e});
                    i = e;
                }
            }
    }
    return out;
}

void transport_predict(const Box& box, const SymmetricTensorField& t, const Field* kappa,
                       const VelocityField& u, const GlobalGrid& g, real dt, std::vector<Field>& k1,
                       SymmetricTensorField& t1, Field* kappa1) {
    std::vector<Field*> s1;
    if (kappa1) s1.push_back(kappa1);
    transport_predict(box, &t, one_or_none(kappa), {-1}, u, g, dt, k1, &t1, s1);
}

void transport_correct(const Box& box, const SymmetricTensorField& t1, const Field* kappa1,
                       const VelocityField& u, const GlobalGrid& g, real dt,
                       const std::vector<Field>& k1, SymmetricTensorField& t, Field* kappa) {
    std::vector<Field*> sn;
    if (kappa) sn.push_back(kappa);
    transport_correct(box, &t1, one_or_none(kappa1), {-1}, u, g, dt, k1, &t, sn);
}

void transport_predict(const Box& box, const SymmetricTensorField* t,
                       const std::vector<const Field*>& sc, const std::vector<int>& source,
                       const VelocityField& u, const GlobalGrid& g, real dt, std::vector<Field>& k1,
                       SymmetricTensorField* t1, const std::vector<Field*>& sc1,
                       const RowSpans* spans) {
    const int n = t ? int(t->comp.size()) : 0;
    const auto stage1 = [&](int s, std::ptrdiff_t off, const real* rate, int n0,
                            std::ptrdiff_t next) {
        const real* __restrict f = (s < n ? t->comp[s] : *sc[s - n]).data().data() + off;
        real* __restrict k = k1[s].data().data() + off;
        real* __restrict st = (s < n ? t1->comp[s] : *sc1[s - n]).data().data() + off;
        prefetch_row<true>(k + next, n0);
        prefetch_row<true>(st + next, n0);
        for (int i = 0; i < n0; ++i) {
            k[i] = rate[i];
            st[i] = f[i] + dt * rate[i];
        }
    };
    rate_rows(box, spans, t, sc, source, u, g, stage1);
}

void transport_correct(const Box& box, const SymmetricTensorField* t1,
                       const std::vector<const Field*>& sc1, const std::vector<int>& source,
                       const VelocityField& u, const GlobalGrid& g, real dt,
                       const std::vector<Field>& k1, SymmetricTensorField* t,
                       const std::vector<Field*>& sc, const RowSpans* spans) {
    const int n = t ? int(t->comp.size()) : 0;
    const auto stage2 = [&](int s, std::ptrdiff_t off, const real* rate, int n0,
                            std::ptrdiff_t next) {
        const real* __restrict k = k1[s].data().data() + off;
        real* __restrict f = (s < n ? t->comp[s] : *sc[s - n]).data().data() + off;
        prefetch_row(k + next, n0);
        prefetch_row<true>(f + next, n0);
        for (int i = 0; i < n0; ++i)
            f[i] += 0.5 * dt * (k[i] + rate[i]);
    };
    rate_rows(box, spans, t1, sc1, source, u, g, stage2);
}

BodyWork BodyTransport::advance(Body& body, const VelocityField& u, real dt, bool tensor,
                                real band_phi) {
    if (body.patch().empty()) co_return;
    SymmetricTensorField* t = tensor && !body.tensor().comp.empty() ? &body.tensor() : nullptr;
    // The scalars: kappa_R (D s/Dt = 0), then the reference map's offset (D s/Dt = -v_d).
    std::vector<Field*> sc;
    std::vector<int> source;
    if (Field* kappa = body.reference_curvature()) {
        sc.push_back(kappa);
        source.push_back(-1);
    }
    for (std::size_t d = 0; d < body.reference_map().size(); ++d) {
        sc.push_back(&body.reference_map()[d]);
        source.push_back(int(d));
    }
    const int n = t ? int(t->comp.size()) : 0;
    const int total = n + int(sc.size());
    if (total == 0) co_return;
    const Field& lay = t ? t->comp[0] : *sc[0];
    const GlobalGrid& g = halos_.decomposition().grid();
    // Scratch fields follow the body's patch.
    if (int(k1_.size()) != total || k1_[0].begin() != lay.begin() ||
        k1_[0].cells() != lay.cells() || int(stage_.comp.size()) != n) {
        k1_.assign(total, lay);
        stage_ = t ? *t : SymmetricTensorField{};
        stage_scalars_.clear();
        for (Field* f : sc)
            stage_scalars_.push_back(*f);
    }
    std::vector<const Field*> sc_c(sc.begin(), sc.end());
    std::vector<Field*> st1;
    for (Field& f : stage_scalars_)
        st1.push_back(&f);
    std::vector<const Field*> st1_c(st1.begin(), st1.end());
    SymmetricTensorField* stage = t ? &stage_ : nullptr;
    const Box& box = body.patch().local;
    const Patch& patch = body.patch();
    // Heun's two stages: k1 = R(T^n), T1 = T^n + dt k1; T^{n+1} = T^n + dt/2 (k1 + R(T1)).
    auto fields_of = [](SymmetricTensorField* tt, const std::vector<Field*>& s) {
        std::vector<Field*> out;
        if (tt)
            for (Field& c : tt->comp)
                out.push_back(&c);
        out.insert(out.end(), s.begin(), s.end());
        return out;
    };
    // A coroutine lambda: it lives in this frame, which waits for it to end.
    auto heun = [&](SymmetricTensorField* tt, const std::vector<Field*>& s,
                    const std::vector<const Field*>& s_c, SymmetricTensorField* st,
                    const std::vector<Field*>& s1, const std::vector<const Field*>& s1_c,
                    const std::vector<int>& src, const RowSpans* first,
                    const RowSpans* second) -> BodyWork {
        co_await halo_fill(fields_of(tt, s), patch);
        transport_predict(box, tt, s_c, src, u, g, dt, k1_, st, s1, first);
        co_await halo_fill(fields_of(st, s1), patch);
        transport_correct(box, st, s1_c, src, u, g, dt, k1_, tt, s, second);
    };
    if (!t || band_phi <= 0) {
        co_await heun(t, sc, sc_c, stage, st1, st1_c, source, nullptr, nullptr);
        co_return;
    }
    // The tensor on the band only: the second stage on the cells within 2 of it (a cube), the
    // first on those within 4, whose T1 the second stage's stencil (2 cells along each
    // direction) reads. Decided on a copy of phi with a halo of 4, so that every rank marks its
    // own cells as the rank beside it would. Then the scalars, on the whole patch.
    const Field& phi = body.phi();
    if (band_.data().empty() || band_.begin() != phi.begin() || band_.cells() != phi.cells())
        band_ = Field::on_patch("band", Location::Cell, phi.begin(), phi.cells(), g.dim, 4);
    for_each_in(phi.owned(), [&](int i, int j, int k) { band_(i, j, k) = phi(i, j, k); });
    co_await halo_fill(band_, patch);
    const std::vector<RowSpans> runs = band_spans(band_, box, band_phi, {2, 4});
    const RowSpans &second = runs[0], &first = runs[1];
    co_await heun(t, {}, {}, stage, {}, {}, {}, &first, &second);
    if (!sc.empty())
        co_await heun(nullptr, sc, sc_c, nullptr, st1, st1_c, source, nullptr, nullptr);
}

} // namespace efsi
