#include "membrane/membrane_force.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace efsi {

namespace {

bool inside(const Box& b, const Int3& p) {
    for (int d = 0; d < 3; ++d)
        if (p[d] < b.lo[d] || p[d] >= b.hi[d]) return false;
    return true;
}

} // namespace

Matrix3 membrane_stress_at(const Field& phi, const SymmetricTensorField& Gs, const MembraneLaw& law,
                           const GlobalGrid& g, const MembraneForceSettings& s, const Int3& p,
                           bool& in_band) {
    const real eps = s.smoothing_width * g.dx(0);
    in_band = false;
    const int r2 = g.dim == 3 ? 1 : 0;
    for (int c = -r2; c <= r2; ++c)
        for (int b = -1; b <= 1; ++b)
            for (int a = -1; a <= 1; ++a) {
                const real v = phi(p[0] + a, p[1] + b, p[2] + c);
                if (!(v > s.band_cutoff && v < 1 - s.band_cutoff)) return Matrix3{};
            }
    const Real3 gr = gradient_at(phi, g, p, s.stencil, eps);
    const real mag = std::sqrt(gr[0] * gr[0] + gr[1] * gr[1] + gr[2] * gr[2]);
    // The smoothed delta |grad phi|. With the distance stencil gr = grad psi and, since
    // phi = (1 + tanh(psi/eps))/2, grad phi = phi'(psi) grad psi with
    // phi'(psi) = (1 - tanh^2)/(2 eps) = 2 phi (1 - phi) / eps: the profile is evaluated
    // exactly and only the (linear) psi is differenced.
    real delta = mag;
    if (s.stencil == GradientStencil::Distance) {
        const real c = std::clamp(phi(p), 1e-9, 1 - 1e-9);
        delta = 2 * c * (1 - c) / eps * mag;
    }
    in_band = mag > 0;
    if (s.stencil == GradientStencil::Distance && mag < s.min_distance_gradient) in_band = false;
    Matrix3 S{};
    if (!in_band) return S;
    const Real3 n{gr[0] / mag, gr[1] / mag, gr[2] / mag};
    Matrix3 G{};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            G[a][b] = Gs.value(a, b, p);
    const MembraneKinematics kin = membrane_kinematics(n, G);
    // The normal of phi must be a normal of the surface Gs carries: then P Gs P keeps the
    // area ratio of Gs itself (Gs = F P_R F^T has rank 2, its second invariant is J^2 for
    // any n with Gs n = 0). See min_normal_consistency.
    const real JG2 = second_invariant(G);
    const real c2 = s.min_normal_consistency * s.min_normal_consistency;
    if (JG2 < s.min_area_ratio * s.min_area_ratio || kin.IIs + 1 < c2 * JG2) {
        in_band = false;
        return S;
    }
    const Matrix3 tau = law.tension(kin);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            S[a][b] = delta * tau[a][b];
    return S;
}

MembraneForce::MembraneForce(const GlobalGrid& g, const HaloFiller& halos,
                             MembraneForceSettings settings)
    : g_(g), halos_(halos), settings_(settings) {}

real bending_time_step_limit(const GlobalGrid& g, real density, real viscosity, real eb_max) {
    if (eb_max <= 0) return 0;
    real h = g.dx(0);
    for (int d = 1; d < g.dim; ++d)
        h = std::min(h, g.dx(d));
    const real pi = std::numbers::pi;
    const real viscous = viscosity * h * h * h / eb_max;
    const real inertial = std::sqrt(density * std::pow(h, 5) / (2 * pi * eb_max));
    return std::max(viscous, inertial);
}

void MembraneForce::allocate(const Patch& patch) {
    const int dim = g_.dim;
    stress_ = SymmetricTensorField{};
    stress_.dim = dim;
    stress_.zz_2d = 0; // S_zz of a 2D run is never used (no z derivative, no z force)
    for (int c = 0; c < SymmetricTensorField::count(dim); ++c)
        stress_.comp.push_back(Field::on_patch(SymmetricTensorField::component_name("S", c, dim),
                                               Location::Cell, patch.local.lo, patch.local.size(),
                                               dim, 1));
    stress_box_ = patch.local;
    band_.clear();
    if (settings_.bending_modulus > 0) {
        auto make = [&](const std::string& name, int halo) {
            Field f = Field::on_patch(name, Location::Cell, patch.local.lo, patch.local.size(), dim,
                                      halo);
            f.fill(0);
            return f;
        };
        psi_ = make("psi", 2);
        band_mask_ = make("band", 1);
        m_ = SymmetricTensorField{};
        m_.dim = dim;
        m_.zz_2d = 0; // m_zz of a 2D run never loads the flow (no z derivative)
        for (int c = 0; c < SymmetricTensorField::count(dim); ++c)
            m_.comp.push_back(make(SymmetricTensorField::component_name("m", c, dim), 1));
        for (int d = 0; d < dim; ++d) {
            n_[d] = make(std::string("n_") + "xyz"[d], 1);
            q_[d] = make(std::string("q_") + "xyz"[d], 1);
        }
    }
}

void MembraneForce::add(Body& body, const MembraneLaw& law, VelocityField& force) {
    const Patch& patch = body.patch();
    const int dim = g_.dim;
    if (patch.empty()) return;
    halos_.fill(body.phi(), patch);
    for (Field& c : body.tensor().comp)
        halos_.fill(c, patch);
    const bool bending = settings_.bending_modulus > 0;
    if (bending) {
        if (!body.reference_curvature())
            throw InputError("membrane '" + body.name() +
                             "': a bending modulus needs the body to carry kappa_R");
        halos_.fill(*body.reference_curvature(), patch);
    }

    if (stress_.comp.empty() || !(stress_box_ == patch.local)) allocate(patch);
    for (const Int3& q : band_) { // clear the previous band only
        for (Field& c : stress_.comp)
            c(q) = 0;
        if (bending) band_mask_(q) = 0;
    }
    band_.clear();

    // Pass 1: S = |grad phi| tau_s on the owned cells and one halo layer, band only.
    Box grown = patch.local;
    for (int d = 0; d < dim; ++d) {
        grown.lo[d] -= 1;
        grown.hi[d] += 1;
    }
    for_each_in(grown, [&](int i, int j, int k) {
        const Int3 q{i, j, k};
        bool in_band = false;
        const Matrix3 S =
            membrane_stress_at(body.phi(), body.tensor(), law, g_, settings_, q, in_band);
        if (!in_band) return;
        for (int a = 0; a < dim; ++a)
            for (int b = a; b < dim; ++b)
                stress_.comp[SymmetricTensorField::slot(a, b, dim)](q) = S[a][b];
        band_.push_back(q);
    });

    // Pass 2: scatter the staggered divergence of S from each band cell q to the faces
    // whose stencil contains q (the transpose of the gather formula in the header), on the
    // faces of the patch's owned cells.
    const Box& faces = patch.local;
    auto add_to = [&](int d, const Int3& p, real v) {
        if (inside(faces, p)) force[d](p) += v;
    };
    for (const Int3& q : band_)
        for (int d = 0; d < dim; ++d) {
            const Int3 ed = unit(d);
            const real Sdd = stress_.value(d, d, q) / g_.dx(d);
            add_to(d, q, Sdd);
            add_to(d, {q[0] + ed[0], q[1] + ed[1], q[2] + ed[2]}, -Sdd);
            for (int k = 0; k < dim; ++k) {
                if (k == d) continue;
                const Int3 ek = unit(k);
                const real v = stress_.value(d, k, q) / (4 * g_.dx(k));
                Int3 p = q; // q = p + e_k and q = p + e_k - e_d
                for (int a = 0; a < 3; ++a)
                    p[a] -= ek[a];
                add_to(d, p, v);
                add_to(d, {p[0] + ed[0], p[1] + ed[1], p[2] + ed[2]}, v);
                p = q; // q = p - e_k and q = p - e_k - e_d
                for (int a = 0; a < 3; ++a)
                    p[a] += ek[a];
                add_to(d, p, -v);
                add_to(d, {p[0] + ed[0], p[1] + ed[1], p[2] + ed[2]}, -v);
            }
        }

    if (bending) add_bending(body, force);
}

void MembraneForce::add_bending(Body& body, VelocityField& force) {
    const Patch& patch = body.patch();
    const int dim = g_.dim;
    const real h = g_.dx(0); // cubic cells (the config reader enforces it)
    const real eps = settings_.smoothing_width * h;
    const real Eb = settings_.bending_modulus;
    const Field& phi = body.phi();
    const Field& kappa_r = *body.reference_curvature();

    // psi = eps atanh(2 phi - 1) on the owned cells and both halo layers (as gradient_at).
    Box all = patch.local;
    for (int d = 0; d < dim; ++d) {
        all.lo[d] -= 2;
        all.hi[d] += 2;
    }
    for_each_in(all, [&](int i, int j, int k) {
        const real c = std::clamp(phi(i, j, k), 1e-9, 1 - 1e-9);
        psi_(i, j, k) = eps * std::atanh(2 * c - 1);
    });

    // Pass A, on the band cells (owned and one halo layer; their 3^dim stencil is in the
    // band): the unit normal and the bending moment m = Eb (kappa - kappa_R P_b), with
    // kappa = -P H P / |grad psi| the curvature tensor of the level surface through the
    // cell (H by central second differences of psi) and P_b the projection on the
    // directions that bend (P in 3D; its in-plane block in 2D).
    for (const Int3& c : band_) {
        band_mask_(c) = 1;
        const Real3 gr = gradient_at(psi_, g_, c, GradientStencil::Isotropic);
        real mag = 0;
        for (int a = 0; a < dim; ++a)
            mag += gr[a] * gr[a];
        mag = std::sqrt(mag);
        Real3 n{0, 0, 0};
        for (int a = 0; a < dim; ++a)
            n[a] = gr[a] / mag;
        Matrix3 H{};
        const real p0 = psi_(c);
        for (int a = 0; a < dim; ++a) {
            const Int3 ea = unit(a);
            const Int3 cp{c[0] + ea[0], c[1] + ea[1], c[2] + ea[2]};
            const Int3 cm{c[0] - ea[0], c[1] - ea[1], c[2] - ea[2]};
            H[a][a] = (psi_(cp) - 2 * p0 + psi_(cm)) / (h * h);
            for (int b = a + 1; b < dim; ++b) {
                const Int3 eb = unit(b);
                auto at = [&](int sa, int sb) {
                    return psi_(c[0] + sa * ea[0] + sb * eb[0], c[1] + sa * ea[1] + sb * eb[1],
                                c[2] + sa * ea[2] + sb * eb[2]);
                };
                H[a][b] = H[b][a] = (at(1, 1) - at(1, -1) - at(-1, 1) + at(-1, -1)) / (4 * h * h);
            }
        }
        Matrix3 P{};
        for (int a = 0; a < dim; ++a)
            for (int b = 0; b < dim; ++b)
                P[a][b] = (a == b ? 1.0 : 0.0) - n[a] * n[b];
        Matrix3 PH{};
        for (int a = 0; a < dim; ++a)
            for (int b = 0; b < dim; ++b)
                for (int e = 0; e < dim; ++e)
                    PH[a][b] += P[a][e] * H[e][b];
        const real kr = kappa_r(c);
        for (int a = 0; a < dim; ++a) {
            n_[a](c) = n[a];
            for (int b = a; b < dim; ++b) {
                real phpb = 0;
                for (int e = 0; e < dim; ++e)
                    phpb += PH[a][e] * P[e][b];
                m_.comp[SymmetricTensorField::slot(a, b, dim)](c) =
                    Eb * (-phpb / mag - kr * P[a][b]);
            }
        }
    }

    // Pass B, on the owned band cells inside the kernel: q = P [(P.grad).m] by central
    // differences of m (so the whole stencil of m must be in the band), weighted by the
    // kernel: Q = delta_b q.
    for (int d = 0; d < dim; ++d)
        q_[d].fill(0);
    bending_cells_ = bending_dropped_ = 0;
    const real w = settings_.bending_width * h;
    const bool cosine = settings_.bending_kernel == MembraneForceSettings::BendingKernel::Cosine;
    const real pi = std::numbers::pi;
    for (const Int3& c : band_) {
        if (!inside(patch.local, c)) continue;
        const real s = psi_(c);
        if (cosine && std::abs(s) >= w) continue;
        bool whole = true;
        for (int l = 0; l < dim && whole; ++l) {
            const Int3 el = unit(l);
            whole = band_mask_(c[0] + el[0], c[1] + el[1], c[2] + el[2]) > 0 &&
                    band_mask_(c[0] - el[0], c[1] - el[1], c[2] - el[2]) > 0;
        }
        if (!whole) {
            ++bending_dropped_;
            continue;
        }
        Real3 n{0, 0, 0};
        for (int a = 0; a < dim; ++a)
            n[a] = n_[a](c);
        Matrix3 P{};
        for (int a = 0; a < dim; ++a)
            for (int b = 0; b < dim; ++b)
                P[a][b] = (a == b ? 1.0 : 0.0) - n[a] * n[b];
        // (div_s m)_j = P_kl d_l m_kj.
        Real3 div{0, 0, 0};
        for (int l = 0; l < dim; ++l) {
            const Int3 el = unit(l);
            const Int3 cp{c[0] + el[0], c[1] + el[1], c[2] + el[2]};
            const Int3 cm{c[0] - el[0], c[1] - el[1], c[2] - el[2]};
            for (int k = 0; k < dim; ++k) {
                if (P[k][l] == 0) continue;
                for (int j = 0; j < dim; ++j)
                    div[j] += P[k][l] * (m_.value(k, j, cp) - m_.value(k, j, cm)) / (2 * h);
            }
        }
        // |grad psi| for the coarea weight (the isotropic gradient, as in pass A).
        const Real3 gr = gradient_at(psi_, g_, c, GradientStencil::Isotropic);
        real mag = 0;
        for (int a = 0; a < dim; ++a)
            mag += gr[a] * gr[a];
        mag = std::sqrt(mag);
        real delta = 0;
        if (cosine) {
            delta = (1 + std::cos(pi * s / w)) / (2 * w) * mag;
        } else {
            const real p = std::clamp(phi(c), 1e-9, 1 - 1e-9);
            delta = 2 * p * (1 - p) / eps * mag;
        }
        for (int a = 0; a < dim; ++a) {
            real qa = 0;
            for (int b = 0; b < dim; ++b)
                qa += P[a][b] * div[b];
            q_[a](c) = delta * qa;
        }
        ++bending_cells_;
    }
    for (int d = 0; d < dim; ++d)
        halos_.fill(q_[d], patch);

    // Pass C: the force -div(delta_b q n): S_b,dk = -n_d Q_k, scattered like the tension's
    // S (the d-force takes the k-difference of S_dk).
    auto add_to = [&](int d, const Int3& p, real v) {
        if (inside(patch.local, p)) force[d](p) += v;
    };
    for (const Int3& c : band_) {
        bool any = false;
        for (int k = 0; k < dim; ++k)
            any = any || q_[k](c) != 0;
        if (!any) continue;
        for (int d = 0; d < dim; ++d) {
            const real nd = n_[d](c);
            const Int3 ed = unit(d);
            const real Sdd = -nd * q_[d](c) / h;
            add_to(d, c, Sdd);
            add_to(d, {c[0] + ed[0], c[1] + ed[1], c[2] + ed[2]}, -Sdd);
            for (int k = 0; k < dim; ++k) {
                if (k == d) continue;
                const Int3 ek = unit(k);
                const real v = -nd * q_[k](c) / (4 * h);
                Int3 p{c[0] - ek[0], c[1] - ek[1], c[2] - ek[2]};
                add_to(d, p, v);
                add_to(d, {p[0] + ed[0], p[1] + ed[1], p[2] + ed[2]}, v);
                p = {c[0] + ek[0], c[1] + ek[1], c[2] + ek[2]};
                add_to(d, p, -v);
                add_to(d, {p[0] + ed[0], p[1] + ed[1], p[2] + ed[2]}, -v);
            }
        }
    }
}

} // namespace efsi
