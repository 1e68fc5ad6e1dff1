// Transport of a body's cell fields by the flow, on the body's patch only.
//
//   scalars (kappa_R):      D s/Dt = 0
//   reference map offset:   D (X - x)_d/Dt = -v_d   (X the reference map, D X/Dt = 0)
//   tensors (B, Gs):        D T/Dt = L T + T L^T,   L_ij = d v_i / d x_j
//
// Space: the advective term u.grad s is written as div(u s) - s div(u), with face values
// of s from a MUSCL reconstruction limited by van Leer's limiter (second order where the
// field is smooth, no new extrema at the body edge), times the face velocity. L is
// evaluated at cell centres: diagonal terms from the two faces of the cell, off-diagonal
// terms as central differences averaged over the cell's two faces (exact for linear v).
// Time: Heun's method (RK2) with the velocity of the end of the flow step held fixed.
//
// Two forms of the same stencils: the pointwise kernels below (the reference, for tests
// and single cells) and the row sweeps that advance() runs (transport.cpp): unit-stride
// rows over raw pointers, L computed once per row for all components, each face's flux
// once (x within the row; y and z kept from the previous row and plane), the upwind choice
// and the limiter as selects (no branches), so the inner loops vectorise (transport.cpp is
// compiled with -fno-trapping-math for that, solver/CMakeLists.txt); Heun's two stages are fused
// with the rates (stage 1 writes k1 and T1, stage 2 updates T in place), so no pass re-reads a
// field it has just written. The sweeps multiply by 1/h where the pointwise kernels divide by h:
// equal to round-off (bit for bit when h is a power of two, as in the capsule cases).
#pragma once

#include "bodies/body.hpp"
#include "bodies/body_work.hpp"
#include "boundary/boundary.hpp"
#include "grid/field.hpp"

#include <array>
#include <vector>

namespace efsi {

/// A run of cells i in [lo, hi) of the row (j, k) (block-local indices).
struct RowSpan {
    int j, k, lo, hi;
};
/// The cells a sweep updates, as runs ordered by k, then j, then i (runs of one row do not
/// overlap).
using RowSpans = std::vector<RowSpan>;

/// For each of `reaches`, the runs of the cells of `box` within that many cells (in each
/// direction: a cube) of a cell of `phi` with lo <= phi <= 1 - lo. phi's halo must be filled
/// and as wide as the largest reach (its values there decide as their owners' do, so the runs
/// of neighbouring ranks agree); along a direction without halo (z in 2D) the reach is 0.
std::vector<RowSpans> band_spans(const Field& phi, const Box& box, real lo,
                                 const std::vector<int>& reaches);

/// Velocity gradient L_ij = dv_i/dx_j at the centre of cell p (zero rows/columns past dim).
Matrix3 velocity_gradient_at(const VelocityField& u, const GlobalGrid& g, const Int3& p);

/// -u.grad s at the centre of cell p (MUSCL / van Leer, flux form with divergence correction).
real advection_rate_at(const Field& s, const VelocityField& u, const GlobalGrid& g, const Int3& p);

/// Heun's first stage on `box` (block-local cells): k1 = R(T^n) and T1 = T^n + dt k1, R the
/// rates above; kappa (may be null) is carried as one more field, last in k1. T and kappa
/// need their halos filled; every tensor, kappa, k1 and T1 field shares one patch layout.
void transport_predict(const Box& box, const SymmetricTensorField& t, const Field* kappa,
                       const VelocityField& u, const GlobalGrid& g, real dt, std::vector<Field>& k1,
                       SymmetricTensorField& t1, Field* kappa1);

/// Heun's second stage on `box`: T^{n+1} = T^n + dt/2 (k1 + R(T1)), in place in t and kappa
/// (T1 and kappa1 with their halos filled).
void transport_correct(const Box& box, const SymmetricTensorField& t1, const Field* kappa1,
                       const VelocityField& u, const GlobalGrid& g, real dt,
                       const std::vector<Field>& k1, SymmetricTensorField& t, Field* kappa);

/// The general stages: an optional tensor `t` (null: none) and scalars `sc`, scalar k with the
/// source -v_{source[k]} when source[k] >= 0 (a reference map's offset X - x), none when -1.
/// k1 holds the tensor's components first, then the scalars'.
void transport_predict(const Box& box, const SymmetricTensorField* t,
                       const std::vector<const Field*>& sc, const std::vector<int>& source,
                       const VelocityField& u, const GlobalGrid& g, real dt, std::vector<Field>& k1,
                       SymmetricTensorField* t1, const std::vector<Field*>& sc1,
                       const RowSpans* spans = nullptr);
void transport_correct(const Box& box, const SymmetricTensorField* t1,
                       const std::vector<const Field*>& sc1, const std::vector<int>& source,
                       const VelocityField& u, const GlobalGrid& g, real dt,
                       const std::vector<Field>& k1, SymmetricTensorField* t,
                       const std::vector<Field*>& sc, const RowSpans* spans = nullptr);

class BodyTransport {
  public:
    explicit BodyTransport(const HaloFiller& halos) : halos_(halos) {}
    /// Advance the body's tensor (unless `tensor` is false), kappa_R and reference map by dt
    /// with the face velocity u (halos filled). `band_phi` > 0: the tensor only on the cells
    /// within 2 cells (a cube) of one with band_phi <= phi <= 1 - band_phi, its first stage
    /// within 4 (its values elsewhere are left as they were); the scalars on the whole patch.
    /// A BodyWork: it waits at each of its halo fills (run it with run_now or in rounds).
    BodyWork advance(Body& body, const VelocityField& u, real dt, bool tensor = true,
                     real band_phi = 0);

  private:
    const HaloFiller& halos_;
    std::vector<Field> k1_;
    SymmetricTensorField stage_;       ///< T^n + dt k1
    std::vector<Field> stage_scalars_; ///< the scalars' T^n + dt k1
    Field band_;                       ///< band_phi: phi with a halo of 4
};

} // namespace efsi
