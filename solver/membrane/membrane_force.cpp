#include "membrane/membrane_force.hpp"

#include "core/error.hpp"
#include "membrane/neo_hookean.hpp"
#include "membrane/skalak.hpp"

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

// Pass 1 of MembraneForce::add, the same arithmetic as membrane_stress_at on every cell of
// `grown` in for_each_in order, batched: the stencil values (psi = eps atanh(2 phi - 1) for
// the distance stencil, else phi) and the cutoff test are evaluated once per cell into work
// arrays on `grown` plus one layer, the 3^dim band test is a separable AND of the cutoff
// flags, the gradient reads the work array at fixed linear offsets (same terms, same order,
// so the result is bit-for-bit that of gradient_at), and the law is a template parameter so
// a final law's energy derivatives are called directly.
struct BandScratch {
    std::vector<real>& value;
    std::vector<unsigned char>&ok, &tmp;
};

template <class Law>
void band_stress(const Field& phi, const SymmetricTensorField& Gs, const Law& law,
                 const GlobalGrid& g, const MembraneForceSettings& s, const Box& grown,
                 BandScratch& w, SymmetricTensorField& stress, std::vector<Int3>& band) {
    const int dim = g.dim;
    const bool distance = s.stencil == GradientStencil::Distance;
    const real eps = s.smoothing_width * g.dx(0);
    Box W = grown; // grown plus the stencil's layer
    for (int d = 0; d < dim; ++d) {
        W.lo[d] -= 1;
        W.hi[d] += 1;
    }
    const int ex = W.hi[0] - W.lo[0], ey = W.hi[1] - W.lo[1], ez = W.hi[2] - W.lo[2];
    if (ex <= 0 || ey <= 0 || ez <= 0) return;
    const std::ptrdiff_t sx = 1, sy = ex, sz = std::ptrdiff_t(ex) * ey;
    const std::size_t n = std::size_t(ex) * ey * ez;
    w.value.resize(n);
    w.ok.resize(n);
    w.tmp.resize(n);
    real* val = w.value.data();
    unsigned char* ok = w.ok.data();
    unsigned char* tmp = w.tmp.data();
    const real lo_cut = s.band_cutoff, hi_cut = 1 - s.band_cutoff;
    for (int k = 0; k < ez; ++k)
        for (int j = 0; j < ey; ++j) {
            const real* pr = phi.data().data() + phi.index(W.lo[0], W.lo[1] + j, W.lo[2] + k);
            const std::size_t row = std::size_t(j) * sy + std::size_t(k) * sz;
            for (int i = 0; i < ex; ++i) {
                const real v = pr[i];
                const bool o = v > lo_cut && v < hi_cut;
                ok[row + i] = o;
                if (!distance) {
                    val[row + i] = v;
                } else if (o) { // only cells of a band stencil are read
                    const real c = std::clamp(v, 1e-9, 1 - 1e-9);
                    val[row + i] = eps * std::atanh(2 * c - 1);
                } else {
                    val[row + i] = 0;
                }
            }
        }
    // Separable AND over the 3^dim block: along x into tmp, along y into ok, along z
    // into tmp (3D); entries on the faces of W are left unset and never read.
    auto and3 = [&](const unsigned char* in, unsigned char* out, std::ptrdiff_t st, int d) {
        for (int k = (d == 2); k < ez - (d == 2); ++k)
            for (int j = (d == 1); j < ey - (d == 1); ++j) {
                const std::size_t row = std::size_t(j) * sy + std::size_t(k) * sz;
                for (int i = (d == 0); i < ex - (d == 0); ++i) {
                    const std::size_t l = row + i;
                    out[l] = in[l - st] & in[l] & in[l + st];
                }
            }
    };
    and3(ok, tmp, sx, 0);
    and3(tmp, ok, sy, 1);
    const unsigned char* in_block = ok;
    if (dim == 3) {
        and3(ok, tmp, sz, 2);
        in_block = tmp;
    }
    // The gradient stencil (gradient_at): per direction d the transverse offsets in the
    // same order, their weights and the linear offsets of q + e_d and q - e_d.
    const real a = s.stencil == GradientStencil::Central  ? 0.0
                   : s.stencil == GradientStencil::Youngs ? 0.25
                                                          : 1.0 / 6.0;
    const real wt[3] = {a, 1 - 2 * a, a};
    const std::ptrdiff_t stride[3] = {sx, sy, sz};
    int terms[3] = {0, 0, 0};
    real weight[3][9];
    std::ptrdiff_t off_p[3][9], off_m[3][9];
    real denom[3] = {1, 1, 1};
    for (int d = 0; d < dim; ++d) {
        const int t1 = (d + 1) % 3, t2 = (d + 2) % 3;
        const int r1 = t1 < dim ? 1 : 0, r2 = t2 < dim ? 1 : 0;
        for (int o1 = -r1; o1 <= r1; ++o1)
            for (int o2 = -r2; o2 <= r2; ++o2) {
                const int m = terms[d]++;
                weight[d][m] = (r1 ? wt[o1 + 1] : 1.0) * (r2 ? wt[o2 + 1] : 1.0);
                const std::ptrdiff_t base = o1 * stride[t1] + o2 * stride[t2];
                off_p[d][m] = base + stride[d];
                off_m[d][m] = base - stride[d];
            }
        denom[d] = 2 * g.dx(d);
    }
    // Gs components (or the constant of an unstored one) per (a, b).
    const Field* gf[3][3];
    real gconst[3][3];
    for (int a0 = 0; a0 < 3; ++a0)
        for (int b0 = 0; b0 < 3; ++b0) {
            const int sl = SymmetricTensorField::slot(a0, b0, Gs.dim);
            gf[a0][b0] = sl >= 0 ? &Gs.comp[sl] : nullptr;
            gconst[a0][b0] = (a0 == 2 && b0 == 2) ? Gs.zz_2d : 0.0;
        }
    Field* sf[3][3] = {};
    for (int a0 = 0; a0 < dim; ++a0)
        for (int b0 = a0; b0 < dim; ++b0)
            sf[a0][b0] = &stress.comp[SymmetricTensorField::slot(a0, b0, dim)];
    const real c2 = s.min_normal_consistency * s.min_normal_consistency;
    const real ar2 = s.min_area_ratio * s.min_area_ratio;

    for (int k = grown.lo[2]; k < grown.hi[2]; ++k)
        for (int j = grown.lo[1]; j < grown.hi[1]; ++j) {
            const std::size_t row = std::size_t(j - W.lo[1]) * sy + std::size_t(k - W.lo[2]) * sz;
            for (int i = grown.lo[0]; i < grown.hi[0]; ++i) {
                const std::size_t l = row + std::size_t(i - W.lo[0]);
                if (!in_block[l]) continue;
                const real* v = val + l;
                Real3 gr{0, 0, 0};
                for (int d = 0; d < dim; ++d) {
                    real acc = 0;
                    for (int m = 0; m < terms[d]; ++m)
                        acc += weight[d][m] * (v[off_p[d][m]] - v[off_m[d][m]]);
                    gr[d] = acc / denom[d];
                }
                const real mag = std::sqrt(gr[0] * gr[0] + gr[1] * gr[1] + gr[2] * gr[2]);
                real delta = mag;
                if (distance) {
                    const real c = std::clamp(phi(i, j, k), 1e-9, 1 - 1e-9);
                    delta = 2 * c * (1 - c) / eps * mag;
                }
                if (!(mag > 0)) continue;
                if (distance && mag < s.min_distance_gradient) continue;
                const Real3 nn{gr[0] / mag, gr[1] / mag, gr[2] / mag};
                Matrix3 G{};
                for (int a0 = 0; a0 < 3; ++a0)
                    for (int b0 = 0; b0 < 3; ++b0)
                        G[a0][b0] = gf[a0][b0] ? (*gf[a0][b0])(i, j, k) : gconst[a0][b0];
                const MembraneKinematics kin = membrane_kinematics(nn, G);
                const real JG2 = second_invariant(G);
                if (JG2 < ar2 || kin.IIs + 1 < c2 * JG2) continue;
                const Matrix3 tau =
                    MembraneLaw::tension_from(law.energy_derivatives(kin.Is, kin.IIs), kin);
                for (int a0 = 0; a0 < dim; ++a0)
                    for (int b0 = a0; b0 < dim; ++b0)
                        (*sf[a0][b0])(i, j, k) = delta * tau[a0][b0];
                band.push_back({i, j, k});
            }
        }
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
    run_now(prepare(body, law), halos_);
    scatter(body, force);
}

BodyWork MembraneForce::prepare(Body& body, const MembraneLaw& law) {
    const Patch& patch = body.patch();
    const int dim = g_.dim;
    if (patch.empty()) co_return;
    const bool bending = settings_.bending_modulus > 0;
    if (bending && !body.reference_curvature())
        throw InputError("membrane '" + body.name() +
                         "': a bending modulus needs the body to carry kappa_R");
    // phi, Gs and kappa_R in one fill (a named vector: GCC 12 rejects a braced temporary
    // of one inside a coroutine).
    std::vector<Field*> inputs{&body.phi()};
    for (Field& c : body.tensor().comp)
        inputs.push_back(&c);
    if (bending) inputs.push_back(body.reference_curvature());
    co_await halo_fill(std::move(inputs), patch);

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
    {
        BandScratch scratch{work_value_, work_ok_, work_tmp_};
        if (const auto* nh = dynamic_cast<const NeoHookeanLaw*>(&law))
            band_stress(body.phi(), body.tensor(), *nh, g_, settings_, grown, scratch, stress_,
                        band_);
        else if (const auto* sk = dynamic_cast<const SkalakLaw*>(&law))
            band_stress(body.phi(), body.tensor(), *sk, g_, settings_, grown, scratch, stress_,
                        band_);
        else
            band_stress(body.phi(), body.tensor(), law, g_, settings_, grown, scratch, stress_,
                        band_);
    }

    if (bending) co_await prepare_bending(body);
}

void MembraneForce::scatter(const Body& body, VelocityField& force) const {
    const Patch& patch = body.patch();
    const int dim = g_.dim;
    if (patch.empty()) return;
    // Pass 2: scatter the staggered divergence of S from each band cell q to the faces
    // whose stencil contains q (the transpose of the gather formula in the header), on the
    // faces of the patch's owned cells.
    const Box& faces = patch.local;
    auto add_to = [&](int d, const Int3& p, real v) {
        if (inside(faces, p)) force[d](p) += v;
    };
    // Band cells at least one cell inside the owned box touch only owned faces: there the
    // same additions in the same order go through linear offsets, without the box test.
    Box inner = faces;
    for (int d = 0; d < dim; ++d) {
        inner.lo[d] += 1;
        inner.hi[d] -= 1;
    }
    const Field* sc[3][3] = {};
    for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b)
            sc[a][b] = &stress_.comp[SymmetricTensorField::slot(a, b, dim)];
    std::ptrdiff_t fstride[3][3] = {}; // fstride[d][k]: offset of e_k in force[d]
    for (int d = 0; d < dim; ++d) {
        const Int3& e = force[d].extent();
        fstride[d][0] = 1;
        fstride[d][1] = e[0];
        fstride[d][2] = std::ptrdiff_t(e[0]) * e[1];
    }
    for (const Int3& q : band_) {
        if (inside(inner, q)) {
            const std::size_t sq = sc[0][0]->index(q[0], q[1], q[2]);
            for (int d = 0; d < dim; ++d) {
                real* f = force[d].data().data() + force[d].index(q[0], q[1], q[2]);
                const std::ptrdiff_t sd = fstride[d][d];
                const real Sdd = sc[d][d]->data()[sq] / g_.dx(d);
                f[0] += Sdd;
                f[sd] += -Sdd;
                for (int k = 0; k < dim; ++k) {
                    if (k == d) continue;
                    const std::ptrdiff_t sk = fstride[d][k];
                    const real v = sc[d][k]->data()[sq] / (4 * g_.dx(k));
                    f[-sk] += v;
                    f[-sk + sd] += v;
                    f[sk] += -v;
                    f[sk + sd] += -v;
                }
            }
            continue;
        }
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
    }

    if (settings_.bending_modulus > 0) scatter_bending(body, force);
}

BodyWork MembraneForce::prepare_bending(Body& body) {
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
    // Most cells of a patch are empty or full: their clamped value's psi is computed once
    // (the same expression, so the same value).
    const real psi_empty = eps * std::atanh(2 * 1e-9 - 1);
    const real psi_full = eps * std::atanh(2 * (1 - 1e-9) - 1);
    for_each_in(all, [&](int i, int j, int k) {
        const real c = std::clamp(phi(i, j, k), 1e-9, 1 - 1e-9);
        psi_(i, j, k) = c == 1e-9       ? psi_empty
                        : c == 1 - 1e-9 ? psi_full
                                        : eps * std::atanh(2 * c - 1);
    });

    // Pass A, on the band cells (owned and one halo layer; their 3^dim stencil is in the
    // band): the unit normal and the bending moment m = Eb (kappa - kappa_R P_b), with
    // kappa = -P H P / |grad psi| the curvature tensor of the level surface through the
    // cell (H by central second differences of psi) and P_b the projection on the
    // directions that bend (P in 3D; its in-plane block in 2D).
    band_grad_.resize(band_.size());
    for (std::size_t q = 0; q < band_.size(); ++q) {
        const Int3& c = band_[q];
        band_mask_(c) = 1;
        const Real3 gr = gradient_at(psi_, g_, c, GradientStencil::Isotropic);
        real mag = 0;
        for (int a = 0; a < dim; ++a)
            mag += gr[a] * gr[a];
        mag = std::sqrt(mag);
        band_grad_[q] = mag;
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
    for (std::size_t qi = 0; qi < band_.size(); ++qi) {
        const Int3& c = band_[qi];
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
        // |grad psi| for the coarea weight (pass A's isotropic gradient).
        const real mag = band_grad_[qi];
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
    co_await halo_fill(std::span(q_.data(), std::size_t(dim)), patch);
}

void MembraneForce::scatter_bending(const Body& body, VelocityField& force) const {
    const Patch& patch = body.patch();
    const int dim = g_.dim;
    const real h = g_.dx(0);
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
