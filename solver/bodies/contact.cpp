#include "bodies/contact.hpp"

#include <algorithm>

namespace efsi {

namespace {

/// phi averaged over the 3^dim cells around p (the dilation by one cell).
real dilated(const Field& phi, const Int3& p, int dim) {
    real s = 0;
    int n = 0;
    const int kz = dim == 3 ? 1 : 0;
    for (int c = -kz; c <= kz; ++c)
        for (int b = -1; b <= 1; ++b)
            for (int a = -1; a <= 1; ++a, ++n)
                s += phi(p[0] + a, p[1] + b, p[2] + c);
    return s / n;
}

/// Whether two patches' global boxes, widened by `w` cells, meet when b's is shifted by `s`
/// cells along x.
bool near(const Patch& a, const Patch& b, int w, int s = 0) {
    const Box bg = shifted(b.global, {s, 0, 0});
    for (int d = 0; d < 3; ++d)
        if (a.global.hi[d] + w <= bg.lo[d] || bg.hi[d] + w <= a.global.lo[d]) return false;
    return true;
}

/// The shifts along x (0, and +-n across the periodic x seam when a patch crosses it) by
/// which b's indices meet a's cells: b's value at a's index p is b's at p - shift.
std::vector<int> image_shifts(const Patch& a, const Patch& b, int w) {
    const int n = std::max(a.seam_period, b.seam_period);
    std::vector<int> out;
    for (int s : {0, -n, n}) {
        if (s != 0 && n == 0) continue;
        if (near(a, b, w, s)) out.push_back(s);
    }
    return out;
}

} // namespace

std::vector<ContactPairForce> contact_forces(const std::vector<const Body*>& bodies,
                                             const Decomposition& dec, real stiffness) {
    const GlobalGrid& g = dec.grid();
    const int dim = dec.dim();
    const real dv = g.cell_volume(), h = g.dx(0);
    std::vector<ContactPairForce> pairs;
    std::vector<std::vector<int>> shifts;
    for (std::size_t i = 0; i < bodies.size(); ++i)
        for (std::size_t j = i + 1; j < bodies.size(); ++j) {
            std::vector<int> s = image_shifts(bodies[i]->patch(), bodies[j]->patch(), 2);
            if (s.empty()) continue;
            pairs.push_back({int(i), int(j), {0, 0, 0}});
            shifts.push_back(std::move(s));
        }
    std::vector<real> local(3 * pairs.size(), 0.0);
    for (std::size_t q = 0; q < pairs.size(); ++q) {
        const Body& bi = *bodies[pairs[q].i];
        const Body& bj = *bodies[pairs[q].j];
        if (bi.patch().empty() || bj.patch().empty()) continue;
        for (const int s : shifts[q]) {
            // Cells of both patches (bj's shifted by s along x) one layer in from their
            // edges (the dilation and the gradient reach two cells, the patch fields' halo
            // width).
            const Box both = intersect(bi.patch().local, shifted(bj.patch().local, {s, 0, 0}));
            const Int3 to_j{-s, 0, 0};
            for_each_in(both, [&](int a, int b, int c) {
                const Int3 p{a, b, c};
                const real ai = dilated(bi.phi(), p, dim);
                if (ai <= 0) return;
                const Int3 pj = p + to_j;
                for (int d = 0; d < dim; ++d) {
                    const real grad = (dilated(bj.phi(), pj + unit(d), dim) -
                                       dilated(bj.phi(), pj - unit(d), dim)) /
                                      (2 * h);
                    local[3 * q + d] -= stiffness * ai * grad * dv;
                }
            });
        }
    }
    if (!local.empty()) dec.sum_in_place(local);
    for (std::size_t q = 0; q < pairs.size(); ++q)
        for (int d = 0; d < 3; ++d)
            pairs[q].force_on_i[d] = local[3 * q + d];
    return pairs;
}

void add_contact_forces(const std::vector<const Body*>& bodies, const std::vector<bool>& held,
                        const Decomposition& dec, real stiffness, VelocityField& force) {
    const std::vector<ContactPairForce> pairs = contact_forces(bodies, dec, stiffness);
    if (pairs.empty()) return;
    const GlobalGrid& g = dec.grid();
    std::vector<Real3> total(bodies.size(), Real3{0, 0, 0});
    for (const ContactPairForce& p : pairs)
        for (int d = 0; d < 3; ++d) {
            total[p.i][d] += p.force_on_i[d];
            total[p.j][d] -= p.force_on_i[d];
        }
    // The volumes of the bodies that take a force.
    std::vector<real> vol(bodies.size(), 0.0);
    for (std::size_t k = 0; k < bodies.size(); ++k) {
        if (held[k] || bodies[k]->patch().empty()) continue;
        const Field& phi = bodies[k]->phi();
        for_each_in(phi.owned(), [&](int a, int b, int c) { vol[k] += phi(a, b, c); });
        vol[k] *= g.cell_volume();
    }
    dec.sum_in_place(vol);
    for (std::size_t k = 0; k < bodies.size(); ++k) {
        if (held[k] || !(vol[k] > 0) || bodies[k]->patch().empty()) continue;
        const Field& phi = bodies[k]->phi();
        for (int c = 0; c < force.dim; ++c) {
            const real per_volume = total[k][c] / vol[k];
            if (per_volume == 0) continue;
            for_each_in(phi.owned(), [&](int a, int b, int l) {
                const Int3 p{a, b, l};
                force[c](p) += 0.5 * (phi(p - unit(c)) + phi(p)) * per_volume;
            });
        }
    }
}

} // namespace efsi
