#include "solid/solid_body.hpp"

namespace efsi {

SolidBody::SolidBody(const BodyConfig& body, const BodyContext& ctx) : BodyPhysics(body, ctx) {
    law_.shear_modulus = body.shear_modulus;
    law_.viscosity = body.solid_viscosity_or(ctx.run.fluid.viscosity);
    transport_ = std::make_unique<BodyTransport>(ctx.halos);
    // B is extended from the solid's mostly solid cells into the rest (docs/method.md).
    if (body.extension_threshold > 0)
        extension_ = std::make_unique<TensorExtension>(ctx.halos, body.extension_threshold, 4);
    const real dt = elastic_time_step_limit(ctx.run.grid, ctx.run.fluid.density,
                                            ctx.run.fluid.viscosity, {law_});
    if (dt > 0) limits_.push_back({"elastic", dt});
}

BodyWork SolidBody::prepare_force(Body& body) {
    if (law_.shear_modulus == 0) co_return;
    co_await halo_fill(body.tensor().comp, body.patch()); // B's components in one fill
}

void SolidBody::add_force(Body& body, VelocityField& force) {
    if (law_.shear_modulus == 0) return;
    add_elastic_force(force, body, law_, ctx_.run.grid, ctx_.dec.block());
}

BodyWork SolidBody::carry_tensor(Body& body, const BodyStep& s) {
    co_await transport_->advance(body, s.u, s.dt);
}

BodyWork SolidBody::extend_tensor(Body& body, const BodyStep&) {
    if (extension_) extension_->apply(body);
    co_return;
}

FixedWall::FixedWall(const BodyConfig& body, const BodyContext& ctx)
    : BodyPhysics(body, ctx), viscosity_(body.solid_viscosity_or(ctx.run.fluid.viscosity)) {}

bool FixedWall::add_pinning(const Body& body, Field& chi) const {
    // Pinned bodies never move, so their share of K = dt chi / tau is fixed.
    if (body.patch().empty()) return true;
    const Field& phi = body.phi();
    for_each_in(phi.owned(),
                [&](int i, int j, int l) { chi(i, j, l) += phi(i, j, l) / cfg_.pin_tau_over_dt; });
    return true;
}

} // namespace efsi
