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

/// Whether two patches' global boxes, widened by `w` cells, meet.
bool near(const Patch& a, const Patch& b, int w) {
    for (int d = 0; d < 3; ++d)
        if (a.global.hi[d] + w <= b.global.lo[d] || b.global.hi[d] + w <= a.global.lo[d])
            return false;
    return true;
}

} // namespace

std::vector<ContactPairForce> contact_forces(const std::vector<const Body*>& bodies,
                                             const Decomposition& dec, real stiffness) {
    const GlobalGrid& g = dec.grid();
    const int dim = dec.dim();
    const real dv = g.cell_volume(), h = g.dx(0);
    std::vector<ContactPairForce> pairs;
    for (std::size_t i = 0; i < bodies.size(); ++i)
        for (std::size_t j = i + 1; j < bodies.size(); ++j)
            if (near(bodies[i]->patch(), bodies[j]->patch(), 2))
                pairs.push_back({int(i), int(j), {0, 0, 0}});
    std::vector<real> local(3 * pairs.size(), 0.0);
    for (std::size_t q = 0; q < pairs.size(); ++q) {
        const Body& bi = *bodies[pairs[q].i];
        const Body& bj = *bodies[pairs[q].j];
        if (bi.patch().empty() || bj.patch().empty()) continue;
        // Cells of both patches one layer in from their edges (the dilation and the
        // gradient reach two cells, the patch fields' halo width).
        Box both = intersect(bi.patch().local, bj.patch().local);
        for_each_in(both, [&](int a, int b, int c) {
            const Int3 p{a, b, c};
            const real ai = dilated(bi.phi(), p, dim);
            if (ai <= 0) return;
            for (int d = 0; d < dim; ++d) {
                const real grad =
                    (dilated(bj.phi(), p + unit(d), dim) - dilated(bj.phi(), p - unit(d), dim)) /
                    (2 * h);
                local[3 * q + d] -= stiffness * ai * grad * dv;
            }
        });
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
