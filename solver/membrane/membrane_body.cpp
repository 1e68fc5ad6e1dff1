#include "membrane/membrane_body.hpp"

#include "bodies/body_shape.hpp"
#include "interface/geometry.hpp"
#include "interface/shapes.hpp"
#include "membrane/surface_velocity.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace efsi {

real membrane_time_step_limit(const GlobalGrid& g, real density, real viscosity, real es_max) {
    if (es_max <= 0) return 0;
    real h = g.dx(0);
    for (int d = 1; d < g.dim; ++d)
        h = std::min(h, g.dx(d));
    const real viscous = kMembraneViscousFactor * viscosity * h / es_max;
    const real inertial = std::sqrt(density * h * h * h / (2 * 3.141592653589793 * es_max));
    return std::max(viscous, inertial);
}

real resolvable_reference_curvature(real kappa, real h) {
    if (std::isnan(kappa)) return 0;
    const real bound = 4 / h;
    return std::clamp(kappa, -bound, bound);
}

MembraneBody::MembraneBody(const BodyConfig& b, const BodyContext& ctx) : BodyPhysics(b, ctx) {
    const Config& run = ctx.run;
    law_ = make_membrane_law(b.law, b.elastic_modulus, b.area_dilation);
    MembraneForceSettings ms;
    ms.smoothing_width = b.smoothing_width;
    ms.bending_modulus = b.bending_modulus;
    ms.min_distance_gradient = b.min_distance_gradient;
    force_ = std::make_unique<MembraneForce>(run.grid, ctx.halos, ms);
    transport_ = std::make_unique<BodyTransport>(ctx.halos);
    // Gs is extended from the core of the band to the whole band: layers enough to reach
    // the band's edge (phi = band cutoff 1e-5, |psi| = 5.75 eps) from the core's
    // (|psi| = eps atanh(1 - 2 t)), plus one for the force's stencil; or, with
    // strain_extension = normal, along the normals from the core (normal_extension.hpp).
    if (b.strain_extension == StrainExtension::Normal) {
        normal_extension_ = std::make_unique<NormalExtension>(
            ctx.halos, b.name, b.smoothing_width, b.strain_core, -1,
            b.carries_reference_map() && b.map_interpolation == MapInterpolation::Cubic,
            b.carries_reference_map() && b.map_area_filter, b.newton_foot_points);
    } else if (b.extension_threshold > 0) {
        const real cutoff = MembraneForceSettings{}.band_cutoff;
        const int layers =
            int(std::ceil((std::atanh(1 - 2 * cutoff) - std::atanh(1 - 2 * b.extension_threshold)) *
                          b.smoothing_width)) +
            2;
        extension_ = std::make_unique<TensorExtension>(ctx.halos, b.extension_threshold, layers,
                                                       /*two_sided=*/true);
    }
    if (b.carries_reference_map() && b.map_projection &&
        b.strain_extension == StrainExtension::Normal)
        reference_shape_ = make_body_shape(b); // null for a mask
    if (b.profile_iterations > 0)
        reinit_ = std::make_unique<ConservativeReinit>(ctx.halos, b.smoothing_width,
                                                       b.profile_iterations);
    const real mu = b.membrane_damping_viscosity(run.fluid.viscosity) + increment_viscosity(run);
    const real membrane =
        membrane_time_step_limit(run.grid, run.fluid.density, mu, law_->stiffest_modulus());
    if (membrane > 0) limits_.push_back({"membrane", membrane});
    const real bending =
        bending_time_step_limit(run.grid, run.fluid.density, mu, b.bending_modulus);
    if (bending > 0) limits_.push_back({"bending", bending});
}

MembraneBody::~MembraneBody() = default;

void MembraneBody::initialise(Body& body, const Shape* shape) {
    if (cfg_.carries_reference_map()) {
        // X = x (the allocated offset 0) made constant along the normals, the state the
        // surface velocity keeps; Gs from it (P to O(h^2)), kept for a mask. For a shape
        // the exact P_R below replaces it until the first step rebuilds Gs from X.
        ctx_.halos.fill(body.phi(), body.patch());
        normal_extension_->apply_reference_map(body, /*whole_band=*/true, reference_shape_.get());
    }
    if (!shape) return; // a mask: Gs stays the identity (or, with a map, Gs from X)
    initialise_tensor(body, *shape);
    initialise_reference_curvature(body, *shape);
}

void MembraneBody::initialise_tensor(Body& body, const Shape& shape_ref) {
    const Shape* shape = &shape_ref;
    const GlobalGrid& g = ctx_.dec.grid();
    const Field& phi = body.phi();
    // Gs = P_R = I - n_R n_R, n_R the normal of the shape's level sets through each
    // point (exact on the surface, its natural extension off it), by central
    // differences of the level function with a step far below the cell size.
    const real step = 1e-6 * g.dx(0);
    for_each_in(phi.owned(), [&](int a, int b, int c) {
        // Across a periodic seam, the image of the cell nearest the shape.
        const Real3 x = image_near(position(g, ctx_.dec.block(), Location::Cell, a, b, c),
                                   shape->centre(), g, ctx_.dec.periodic());
        Real3 n{0, 0, 0};
        real len = 0;
        for (int d = 0; d < g.dim; ++d) {
            Real3 xp = x, xm = x;
            xp[d] += step;
            xm[d] -= step;
            n[d] = shape->level(xp) - shape->level(xm);
            len += n[d] * n[d];
        }
        len = std::sqrt(len);
        for (int r = 0; r < 3; ++r)
            for (int q = r; q < 3; ++q) {
                const int slot = SymmetricTensorField::slot(r, q, g.dim);
                if (slot < 0) continue;
                const real nn = len > 0 ? n[r] * n[q] / (len * len) : 0.0;
                body.tensor().comp[slot](a, b, c) = (r == q ? 1.0 : 0.0) - nn;
            }
    });
    for (Field& comp : body.tensor().comp)
        ctx_.halos.fill(comp, body.patch());
}

void MembraneBody::initialise_reference_curvature(Body& body, const Shape& shape_ref) {
    const Shape* shape = &shape_ref;
    const GlobalGrid& g = ctx_.dec.grid();
    if (Field* kr = body.reference_curvature()) {
        // kappa_R = the curvature of the shape's level set through each point
        // (level_set_curvature: the mean curvature in 3D, the section's in 2D; 1/r
        // around a sphere), exact on the surface. Gradient and Hessian by central
        // differences of the level function with a step of h/100: truncation
        // (h/100)^2 relative, round-off ~1e-16 |L| / (h/100)^2, both below 1e-7.
        // In 3D a shape with a closed form (the sphere, the red cell's distance) gives it
        // directly: one nearest-point search per cell instead of 19 level evaluations.
        const real h = g.dx(0); // cubic cells (the config reader enforces it)
        const real s = 1e-2 * h;
        for_each_in(body.phi().owned(), [&](int a, int b, int c) {
            const Real3 x = image_near(position(g, ctx_.dec.block(), Location::Cell, a, b, c),
                                       shape->centre(), g, ctx_.dec.periodic());
            if (g.dim == 3) {
                if (const real k = shape->level_set_mean_curvature(x); !std::isnan(k)) {
                    (*kr)(a, b, c) = resolvable_reference_curvature(k, h);
                    return;
                }
            }
            auto L = [&](int d1, int s1, int d2, int s2) {
                Real3 y = x;
                y[d1] += s1 * s;
                y[d2] += s2 * s;
                return shape->level(y);
            };
            const real l0 = shape->level(x);
            Real3 grad{0, 0, 0};
            Matrix3 H{};
            for (int d = 0; d < g.dim; ++d) {
                const real lp = L(d, 1, d, 0), lm = L(d, -1, d, 0);
                grad[d] = (lp - lm) / (2 * s);
                H[d][d] = (lp - 2 * l0 + lm) / (s * s);
                for (int e = d + 1; e < g.dim; ++e)
                    H[d][e] = H[e][d] =
                        (L(d, 1, e, 1) - L(d, 1, e, -1) - L(d, -1, e, 1) + L(d, -1, e, -1)) /
                        (4 * s * s);
            }
            (*kr)(a, b, c) = resolvable_reference_curvature(level_set_curvature(H, grad, g.dim), h);
        });
        ctx_.halos.fill(*kr, body.patch());
    }
}

BodyWork MembraneBody::prepare_force(Body& body) {
    return force_->prepare(body, *law_);
}

void MembraneBody::add_force(Body& body, VelocityField& force) {
    force_->scatter(body, force);
}

BodyWork MembraneBody::carry_tensor(Body& body, const BodyStep& s) {
    const VelocityField* carrier = &s.u;
    if (cfg_.carried_by_surface_velocity())
        s.timers.time("bodies_surface_velocity", [&] {
            carrier = &s.surface_velocity->compute(body, cfg_.smoothing_width,
                                                   cfg_.surface_velocity_reach);
        });
    // With a reference map only the map (and kappa_R) is carried; Gs is rebuilt from it.
    const bool tensor = !cfg_.carries_reference_map();
    // A carried Gs extended along the normals: the extension keeps the transported Gs only
    // in its core and reads it at foot points on the surface, and sets every other cell of
    // the patch, so Gs is transported near the band only (|psi| <= the reach, phi >= band).
    real band = 0;
    if (tensor && normal_extension_ && cfg_.band_transport)
        band = 0.5 * (1 - std::tanh(normal_extension_->reach_cells() / cfg_.smoothing_width));
    if (carrier != &s.u) {
        // The surface velocity is one buffer that every membrane's computes into: this body's
        // transport ends before the next body's surface velocity is computed.
        run_now(transport_->advance(body, *carrier, s.dt, tensor, band), ctx_.halos);
        co_return;
    }
    co_await transport_->advance(body, *carrier, s.dt, tensor, band);
}

real MembraneBody::restore_profile(Body& body, const BodyStep& s) {
    if (!reinit_) return 0;
    real clipped = 0;
    s.timers.time("bodies_reinit", [&] { clipped = reinit_->apply(body).clipped_volume; });
    return clipped;
}

BodyWork MembraneBody::extend_tensor(Body& body, const BodyStep&) {
    if (extension_) extension_->apply(body);
    if (!normal_extension_) co_return;
    if (cfg_.carries_reference_map())
        normal_extension_->apply_reference_map(body, false, reference_shape_.get());
    else
        co_await normal_extension_->apply(body);
}

/// A possible cause worth naming when a run with membranes blows up: with the layered
/// extension of Gs (strain_extension = "layers"), Gs carried by the surface velocity over a
/// wide reach is unstable for stiff membranes (docs/method.md, "The reach of the surface
/// velocity, and stiff membranes"); with the reference map (the default), a body a few cells
/// thick (docs/method.md, "The reference map"). Empty when no body qualifies.
std::string membrane_instability_hint(const Config& cfg) {
    std::string names, maps, carried;
    auto append = [](std::string& list, const std::string& name) {
        list += (list.empty() ? "'" : ", '") + name + "'";
    };
    for (const BodyConfig& b : cfg.bodies) {
        if (b.carried_by_surface_velocity() && b.strain_extension == StrainExtension::Layers &&
            b.surface_velocity_reach > SurfaceVelocity::stiff_membrane_reach)
            append(names, b.name);
        else if (b.carried_by_surface_velocity() && !b.carries_reference_map())
            append(carried, b.name);
        if (b.carries_reference_map()) append(maps, b.name);
    }
    if (names.empty() && maps.empty() && !carried.empty())
        return fmt::format(". Membranes that carry Gs with the surface velocity ({}) can grow "
                           "their strain by themselves where the body is thinner than its band "
                           "(phi never reaches 1/2 there: a red cell on a coarse grid, pressed "
                           "against a wall); refine the grid or set body.strain_velocity = "
                           "\"local\" (docs/method.md, \"The red cells of capillary_coarse\")",
                           carried);
    if (names.empty() && !maps.empty())
        return fmt::format(". Membranes carried by a reference map ({}) lose it where the body "
                           "is only a few cells thick (the two faces' bands overlap: the tips "
                           "of a strongly deformed capsule at d/16); refine the grid there or "
                           "set body.strain_model = \"tensor\" (docs/method.md, \"The "
                           "reference map\")",
                           maps);
    if (names.empty()) return "";
    const real r = SurfaceVelocity::stiff_membrane_reach;
    return fmt::format(". Membranes with strain_extension = \"layers\" that carry Gs with the "
                       "surface velocity over more than {} cells ({}) are unstable when stiff, "
                       "whatever dt; if yours is stiff, set body.surface_velocity_reach = {} "
                       "or use the default strain_extension = \"normal\" (docs/method.md)",
                       r, names, r);
}

} // namespace efsi
