#include "bodies/body_physics.hpp"

#include "membrane/membrane_body.hpp"
#include "solid/solid_body.hpp"

namespace efsi {

BodyPhysics::BodyPhysics(const BodyConfig& body, const BodyContext& ctx) : cfg_(body), ctx_(ctx) {
    VofOptions vo;
    vo.scheme = parse_vof_scheme(ctx.run.vof.scheme);
    vo.beta_thinc = ctx.run.vof.beta_thinc;
    vo.beta_mthinc = ctx.run.vof.beta_mthinc;
    // A smoothed body keeps its tanh profile (1 - tanh(L/eps))/2: MTHINC reconstructs
    // exactly (1 + tanh(beta s/h))/2 in each cell, so beta = h/eps = 1/smoothing_width
    // carries that profile without sharpening or smearing it (the smoothed VOF).
    if (body.interface == InterfaceKind::Smoothed) {
        vo.scheme = VofScheme::Mthinc;
        vo.beta_mthinc = 1.0 / body.smoothing_width;
    }
    vof_ = std::make_unique<VofAdvection>(ctx.halos, vo);
}

BodyPhysics::~BodyPhysics() = default;

void BodyPhysics::initialise(Body&, const Shape*) {}

BodyWork BodyPhysics::prepare_force(Body&) {
    co_return;
}

void BodyPhysics::add_force(Body&, VelocityField&) {}

bool BodyPhysics::add_pinning(const Body&, Field&) const {
    return false;
}

BodyWork BodyPhysics::carry_tensor(Body&, const BodyStep&) {
    co_return;
}

real BodyPhysics::restore_profile(Body&, const BodyStep&) {
    return 0;
}

BodyWork BodyPhysics::extend_tensor(Body&, const BodyStep&) {
    co_return;
}

BodyWork BodyPhysics::advance_tensor(Body& body, const BodyStep& s) {
    if (!body.tensor().comp.empty()) co_await carry_tensor(body, s);
}

BodyWork BodyPhysics::finish_advance(Body& body, const BodyStep& s, real& clipped) {
    clipped += restore_profile(body, s);
    co_await extend_tensor(body, s);
}

std::unique_ptr<BodyPhysics> make_body_physics(const BodyConfig& body, const BodyContext& ctx) {
    switch (body.kind) {
    case BodyKind::Passive:
        return std::make_unique<PassiveBody>(body, ctx);
    case BodyKind::Solid:
        if (body.pinned) return std::make_unique<FixedWall>(body, ctx);
        return std::make_unique<SolidBody>(body, ctx);
    case BodyKind::Membrane:
        return std::make_unique<MembraneBody>(body, ctx);
    }
    return nullptr;
}

} // namespace efsi
