#include "bodies/transport.hpp"

#include "operators/flow_operators.hpp"

#include <cmath>

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

void BodyTransport::rates(const Body& body, const SymmetricTensorField& t, const Field* kappa,
                          const VelocityField& u, std::vector<Field>& out) {
    const GlobalGrid& g = halos_.decomposition().grid();
    const int dim = t.dim;
    const int n = SymmetricTensorField::count(dim);
    for_each_in(body.patch().local, [&](int i, int j, int k) {
        const Int3 p{i, j, k};
        const Matrix3 L = velocity_gradient_at(u, g, p);
        for (int a = 0; a < 3; ++a)
            for (int b = a; b < 3; ++b) {
                const int s = SymmetricTensorField::slot(a, b, dim);
                if (s < 0) continue;
                // (L T + T L^T)_ab
                real src = 0;
                for (int c = 0; c < 3; ++c)
                    src += L[a][c] * t.value(c, b, p) + t.value(a, c, p) * L[b][c];
                out[s](p) = advection_rate_at(t.comp[s], u, g, p) + src;
            }
        if (kappa) out[n](p) = advection_rate_at(*kappa, u, g, p);
    });
}

void BodyTransport::advance(Body& body, const VelocityField& u, real dt) {
    if (body.patch().empty()) return;
    SymmetricTensorField& t = body.tensor();
    Field* kappa = body.reference_curvature();
    const int n = int(t.comp.size());
    const int total = n + (kappa ? 1 : 0);
    auto field = [&](int s) -> Field& { return s < n ? t.comp[s] : *kappa; };
    auto stage = [&](int s) -> Field& { return s < n ? stage_.comp[s] : stage_kappa_; };
    // Scratch fields follow the body's patch.
    if (int(k1_.size()) != total || k1_[0].begin() != t.comp[0].begin() ||
        k1_[0].cells() != t.comp[0].cells()) {
        k1_.assign(total, t.comp[0]);
        k2_.assign(total, t.comp[0]);
        stage_ = t;
        if (kappa) stage_kappa_ = *kappa;
    }
    // Stage 1: k1 = R(T^n); T1 = T^n + dt k1.
    for (int s = 0; s < total; ++s)
        halos_.fill(field(s), body.patch());
    rates(body, t, kappa, u, k1_);
    for (int s = 0; s < total; ++s) {
        for_each_in(body.patch().local, [&](int i, int j, int k) {
            stage(s)(i, j, k) = field(s)(i, j, k) + dt * k1_[s](i, j, k);
        });
        halos_.fill(stage(s), body.patch());
    }
    // Stage 2: k2 = R(T1); T^{n+1} = T^n + dt/2 (k1 + k2).
    rates(body, stage_, kappa ? &stage_kappa_ : nullptr, u, k2_);
    for (int s = 0; s < total; ++s)
        for_each_in(body.patch().local, [&](int i, int j, int k) {
            field(s)(i, j, k) += 0.5 * dt * (k1_[s](i, j, k) + k2_[s](i, j, k));
        });
}

} // namespace efsi
