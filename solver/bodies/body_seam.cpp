// BodySystem and the periodic x seam (docs/method.md, "The periodic seam"): a moving body's
// patch may cross it as one unwrapped box of indices (bodies/patch.hpp), whose kernels then
// read the velocity and add the force past [0, n) along x. They do so in copies of the flow's
// fields with an x halo that reaches past every such patch: the velocity's filled across the
// seam (the flow is periodic), the force's folded back onto the faces it images. x is whole
// on every rank when a patch crosses (make_patch), so neither copy needs a message.
#include "bodies/body_system.hpp"

#include <algorithm>

namespace efsi {

namespace {

/// The interval of `occupied` (a periodic row of n columns, nonzero where occupied) that
/// leaves out its longest run of empty columns, as [lo, hi) with lo in [0, n) and hi up to
/// lo + n; hi = lo + n when no column is empty.
std::pair<int, int> shortest_cover(const real* occupied, int n) {
    int best_start = 0, best_len = 0;
    for (int start = 0; start < n; ++start) {
        if (occupied[start] != 0 || occupied[(start + n - 1) % n] == 0) continue;
        int len = 0;
        while (len < n && occupied[(start + len) % n] == 0)
            ++len;
        if (len > best_len) {
            best_len = len;
            best_start = start;
        }
    }
    if (best_len == 0) {
        // All occupied, or all empty (then the loop above found no run's start).
        const bool none = std::all_of(occupied, occupied + n, [](real v) { return v == 0; });
        return none ? std::pair{0, 0} : std::pair{0, n};
    }
    const int lo = (best_start + best_len) % n;
    return {lo, lo + n - best_len};
}

/// Rows (j, k) of a field over its whole stored y and z extents, halos included, each from
/// the x index `from` on: f(row pointer at `from`).
template <class F>
void for_stored_rows(Field& field, int from, F&& f) {
    const Int3 b = field.begin(), n = field.cells(), h = field.halo();
    for (int k = b[2] - h[2]; k < b[2] + n[2] + h[2]; ++k)
        for (int j = b[1] - h[1]; j < b[1] + n[1] + h[1]; ++j)
            f(field.data().data() + field.index(from, j, k), j, k);
}

/// (Re)allocate `copy` as `like` with an x halo of at least `hx` cells (its y and z halos
/// as like's), unless it already is one.
void fit_seam_copy(VelocityField& copy, const VelocityField& like, int hx) {
    if (copy.dim == like.dim && !copy[0].data().empty() && copy[0].halo()[0] >= hx) return;
    copy.dim = like.dim;
    for (int c = 0; c < like.dim; ++c) {
        const Field& f = like[c];
        copy[c] = Field(f.name() + "_seam", f.location(), f.begin(), f.cells(), like.dim,
                        Int3{hx, f.halo()[1], f.halo()[2]});
    }
}

} // namespace

void BodySystem::unwrap_occupied(const std::vector<std::size_t>& tracked,
                                 std::vector<Box>& occ) const {
    const GlobalGrid& g = dec_.grid();
    const int n = g.cells[0];
    std::vector<std::size_t> whole; // positions in `tracked`
    for (std::size_t q = 0; q < tracked.size(); ++q) {
        const Patch& patch = bodies_[tracked[q]]->patch();
        if (cross_seam_[tracked[q]] && dec_.periodic()[0] && dec_.ranks_per_dim()[0] == 1 &&
            !occ[q].empty() && patch.global.lo[0] == 0 && patch.global.hi[0] == n)
            whole.push_back(q);
    }
    if (whole.empty()) return;
    // Each such body's occupied columns (phi above the VOF's epsilon anywhere in them), in
    // one reduction for all of them.
    std::vector<real> columns(whole.size() * std::size_t(n), 0.0);
    for (std::size_t w = 0; w < whole.size(); ++w) {
        const Body& b = *bodies_[tracked[whole[w]]];
        if (b.patch().empty()) continue;
        real* col = columns.data() + w * std::size_t(n);
        const Field& phi = b.phi();
        for_each_in(phi.owned(), [&](int i, int j, int k) {
            if (phi(i, j, k) > VofOptions{}.epsilon) col[i] = 1;
        });
    }
    dec_.max_in_place(columns);
    for (std::size_t w = 0; w < whole.size(); ++w) {
        const auto [lo, hi] = shortest_cover(columns.data() + w * std::size_t(n), n);
        if (hi - lo < n) {
            occ[whole[w]].lo[0] = lo;
            occ[whole[w]].hi[0] = hi;
        }
    }
}

bool BodySystem::any_crosses_seam() const {
    return std::any_of(bodies_.begin(), bodies_.end(),
                       [](const auto& b) { return b->patch().crosses_seam(); });
}

int BodySystem::seam_halo() const {
    const int n = dec_.grid().cells[0];
    int past = 0;
    for (const auto& b : bodies_)
        if (b->patch().crosses_seam())
            past = std::max({past, -b->patch().global.lo[0], b->patch().global.hi[0] - n});
    return seam_halo_cells(past, n);
}

int seam_halo_cells(int past, int n) {
    return std::min((past + 4 + 7) / 8 * 8, n);
}

std::size_t BodySystem::seam_copy_bytes() const {
    std::size_t n = 0;
    for (const VelocityField* copy : {&seam_u_, &seam_force_})
        for (int c = 0; c < copy->dim; ++c)
            n += (*copy)[c].data().size() * sizeof(real);
    return n;
}

const VelocityField& BodySystem::seam_velocity(const VelocityField& u) {
    if (!any_crosses_seam()) return u;
    const int dim = dec_.dim();
    fit_seam_copy(seam_u_, u, seam_halo());
    for (int c = 0; c < dim; ++c) {
        const Field& from = u[c];
        const int nx = from.cells()[0];
        // The owned x range of every stored row (u's y and z halos are filled), then the x
        // halo across the seam: a periodic exchange with this rank itself.
        for_stored_rows(seam_u_[c], 0, [&](real* row, int j, int k) {
            const real* src = from.data().data() + from.index(0, j, k);
            std::copy(src, src + nx, row);
        });
        dec_.exchange(seam_u_[c], 0);
    }
    return seam_u_;
}

VelocityField& BodySystem::seam_force(VelocityField& force) {
    force_in_copy_ = any_crosses_seam();
    if (!force_in_copy_) return force;
    const int dim = force.dim;
    fit_seam_copy(seam_force_, force, seam_halo());
    for (int c = 0; c < dim; ++c)
        seam_force_[c].fill(0);
    return seam_force_;
}

void BodySystem::fold_seam_force(VelocityField& force) {
    if (!force_in_copy_) return;
    force_in_copy_ = false;
    for (int c = 0; c < force.dim; ++c) {
        Field& copy = seam_force_[c];
        const int nx = copy.cells()[0], hx = copy.halo()[0];
        for_stored_rows(copy, 0, [&](real* row, int j, int k) {
            // x in [-hx, 0) images x + n, x in [n, n + hx) images x - n (hx <= n).
            for (int i = -hx; i < 0; ++i)
                row[i + nx] += row[i];
            for (int i = nx; i < nx + hx; ++i)
                row[i - nx] += row[i];
            std::copy(row, row + nx, force[c].data().data() + force[c].index(0, j, k));
        });
    }
}

} // namespace efsi
