#include "bodies/body_system.hpp"
#include "membrane/kinematics.hpp"

#include "bodies/body_shape.hpp"
#include "bodies/contact.hpp"

#include "core/error.hpp"
#include "interface/geometry.hpp"
#include "interface/shapes.hpp"
#include "io/voxel_mask.hpp"
#include "membrane/membrane_force.hpp"
#include "membrane/surface_velocity.hpp"
#include "solid/solid_mechanics.hpp"

#include <fmt/core.h>

#include <cmath>
#include <limits>

namespace efsi {

namespace {

/// A cell counts as occupied when its phi exceeds the VOF's epsilon: below it a cell has no
/// outflux (VofOptions::epsilon), so its value is a residue that stays where the body was.
constexpr real occupied_threshold = VofOptions{}.epsilon;
/// Residues farther than this (cells) from the occupied box are dropped after each step,
/// their volume put back on the band (BodySystem::track_patches). One cell: a step moves
/// phi at most one cell per direction, so nothing beyond it can be reached in the next
/// step, and it lies inside the patch for every margin (>= 2, moves at margin / 2).
constexpr int residue_reach = 1;

/// Whether global index p lies within `r` cells of [lo, hi) along a direction of n cells.
bool near_interval(int p, int lo, int hi, int n, bool periodic, int r) {
    auto in = [&](int q) { return q >= lo - r && q < hi + r; };
    return in(p) || (periodic && (in(p - n) || in(p + n)));
}

} // namespace

BodySystem::BodySystem(const Config& config, const Decomposition& dec, const HaloFiller& halos)
    : cfg_(config), dec_(dec), halos_(halos) {
    const BodyContext ctx{config, dec, halos};
    for (const BodyConfig& b : config.bodies) {
        physics_.push_back(make_body_physics(b, ctx));
        bodies_.push_back(std::make_unique<Body>(b.name, b.kind, b.bending, dec.dim(),
                                                 physics_.back()->carries_tensor(),
                                                 b.carries_reference_map()));
        if (b.carried_by_surface_velocity()) surface_velocity_bodies_.push_back(bodies_.size() - 1);
        if (b.carried_by_surface_velocity() && !surface_velocity_) {
            // One instance for every membrane: its halo covers the largest reach asked for.
            real reach = 0;
            for (const BodyConfig& other : config.bodies)
                if (other.carried_by_surface_velocity())
                    reach = std::max(reach, real(other.surface_velocity_reach));
            surface_velocity_ = std::make_unique<SurfaceVelocity>(halos, b.name, reach);
        }
        clipped_.push_back(0);
    }
    for (const BodyConfig& b : config.bodies)
        cross_seam_.push_back(may_cross_seam(config, b));
}

BodySystem::~BodySystem() = default;

bool may_cross_seam(const Config& config, const BodyConfig& b) {
    // A patch may cross the periodic x seam when the body's kernels touch only the velocity
    // (read) and the force (added) of the flow, which the seam copies serve: not with the
    // surface velocity's wide copy, a viscosity of its own (mu), the increment damping's
    // weight on the membranes, or receptors (adhesion). A pinned solid does not move.
    const real mu = config.fluid.viscosity;
    const bool moves = !(b.kind == BodyKind::Solid && b.pinned);
    const real viscosity = b.kind == BodyKind::Solid      ? b.solid_viscosity_or(mu)
                           : b.kind == BodyKind::Membrane ? b.viscosity_ratio * mu
                                                          : mu;
    const bool damped_membrane = config.time.increment_damping > 1 &&
                                 config.time.increment_damping_on == DampingRegion::Membranes &&
                                 b.kind == BodyKind::Membrane;
    return moves && !b.carried_by_surface_velocity() && viscosity == mu &&
           !config.adhesion.enabled && !damped_membrane;
}

void BodySystem::initialise() {
    // phi on a box that certainly holds each body, then every patch fitted to its body,
    // then the physics' own fields (Gs, B, kappa_R, the map) on the fitted patch only: they
    // are functions of the position, and the start box is several times the fitted one.
    for (std::size_t i = 0; i < bodies_.size(); ++i)
        initialise_body(i);
    track_patches(true);
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        const auto shape = make_body_shape(cfg_.bodies[i]); // null for a mask
        physics_[i]->initialise(*bodies_[i], shape.get());
    }
}

void BodySystem::initialise_body(std::size_t i) {
    const BodyConfig& bc = cfg_.bodies[i];
    Body& body = *bodies_[i];
    const GlobalGrid& g = dec_.grid();
    // Start on the box that certainly holds the body and the patch it will have (its bounding
    // box, the smoothed profile's tail, cut where phi < 1e-8, i.e. 9.2 eps out, and the
    // margin), or on the whole grid where it is unbounded (mask, slab, tube);
    // track_patches() then shrinks the patch to the body plus its margin before any step.
    // The values on the final patch are the same either way; the work follows the body.
    Box start{{0, 0, 0}, g.cells};
    const Real3 ext = body_half_extent(bc, g.dim);
    const real h = g.dx(0);
    for (int d = 0; d < g.dim; ++d) {
        if (ext[d] < 0) continue;
        const real tail = bc.interface == InterfaceKind::Smoothed ? 10 * bc.smoothing_width : 1;
        const real reach = ext[d] + (tail + bc.margin + 2) * h;
        start.lo[d] = int(std::floor((bc.centre[d] - reach - g.origin[d]) / h));
        start.hi[d] = int(std::ceil((bc.centre[d] + reach - g.origin[d]) / h));
    }
    body.allocate(make_patch(start, dec_, 2, cross_seam_[i]));
    Field& phi = body.phi();
    const auto shape = make_body_shape(bc); // null for a mask
    if (bc.shape == BodyShape::Mask) {
        const auto file = mask_path(bc, cfg_.case_dir);
        // Each rank reads the voxels its cells cover; a value outside [0, 1] anywhere is
        // reported by every rank (the first one in the image), before anything is written.
        VoxelMask mask;
        std::int64_t bad = -1;
        try {
            mask = read_voxel_mask_for_grid(file, bc.mask_dataset, g, cfg_.length_unit);
            bad = read_voxel_values(
                mask, mask_voxels_for(mask, g, dec_.block(), phi.owned(), bc.subsamples));
        } catch (const InputError& e) {
            throw InputError(fmt::format("body '{}': body.mask_file: {}", bc.name, e.what()));
        }
        constexpr real none = std::numeric_limits<real>::max();
        const real first_bad = dec_.min(bad < 0 ? none : real(bad));
        if (first_bad < none) {
            const auto v = std::int64_t(first_bad);
            const std::int64_t nx = mask.voxels[0], ny = mask.voxels[1];
            throw InputError(fmt::format("body '{}': body.mask_file {}: dataset '{}' holds a "
                                         "value that is not in [0, 1] (not finite, or past it) "
                                         "at voxel ({}, {}, {})",
                                         bc.name, file.string(), bc.mask_dataset, v % nx,
                                         (v / nx) % ny, v / (nx * ny)));
        }
        mask_volume_fraction(mask, g, dec_.block(), phi, bc.subsamples);
    } else {
        if (bc.interface == InterfaceKind::Smoothed) {
            // phi = (1 - tanh(L / eps)) / 2, L the shape's distance-like level function.
            // Where L is certainly past `cut` (the shape's bounding ball says so) phi is below
            // the 1e-8 the tail is cut at, so the level (an exact distance for a red cell,
            // ~100 flops) is not evaluated there: the same phi.
            const real eps = bc.smoothing_width * g.dx(0);
            const real cut = 1.001 * eps * std::atanh(1 - 2e-8);
            const real rb = shape->bounding_radius();
            const Real3 centre = shape->centre();
            for_each_in(phi.owned(), [&](int a, int b, int c) {
                // Across a periodic seam, the image of the cell nearest the body.
                const Real3 x = image_near(position(g, dec_.block(), Location::Cell, a, b, c),
                                           centre, g, dec_.periodic());
                if (std::hypot(x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]) - rb > cut) {
                    phi(a, b, c) = 0;
                    return;
                }
                const real v = 0.5 * (1 - std::tanh(shape->level(x) / eps));
                phi(a, b, c) = v < 1e-8 ? 0.0 : v; // the tail is cut ~9 eps out
            });
        } else {
            initial_volume_fraction(*shape, g, dec_.block(), phi, bc.subsamples, &dec_.periodic());
        }
    }
    halos_.fill(phi, body.patch());
}

void BodySystem::occupied_extent(const Body& b, real* out) const {
    const int big = std::numeric_limits<int>::max() / 2;
    real* neg_lo = out; // -lo, so that one max reduces both ends
    real* hi = out + 3;
    for (int d = 0; d < 3; ++d) {
        neg_lo[d] = -real(big);
        hi[d] = -real(big); // a patch across the seam has indices below 0
    }
    if (b.patch().empty()) return;
    const Int3 off = dec_.block().offset;
    for_each_in(b.phi().owned(), [&](int i, int j, int k) {
        if (b.phi()(i, j, k) <= occupied_threshold) return;
        const Int3 p = Int3{i, j, k} + off;
        for (int d = 0; d < 3; ++d) {
            neg_lo[d] = std::max(neg_lo[d], -real(p[d]));
            hi[d] = std::max(hi[d], real(p[d] + 1));
        }
    });
}

real BodySystem::drop_local(Body& body, const Box& occ) const {
    if (body.patch().empty()) return 0;
    const GlobalGrid& g = dec_.grid();
    const Int3 off = dec_.block().offset;
    Field& phi = body.phi();
    real dropped = 0;
    for_each_in(phi.owned(), [&](int i, int j, int k) {
        const Int3 p = Int3{i, j, k} + off;
        for (int d = 0; d < g.dim; ++d)
            if (!near_interval(p[d], occ.lo[d], occ.hi[d], g.cells[d], dec_.periodic()[d],
                               residue_reach)) {
                dropped += phi(i, j, k);
                phi(i, j, k) = 0;
                return;
            }
    });
    return dropped;
}

void BodySystem::drop_residues(const std::vector<std::size_t>& tracked,
                               const std::vector<Box>& occ) {
    // Two reductions for all the bodies: the dropped volumes, then (if any) the bands'.
    const std::size_t n = tracked.size();
    std::vector<real> dropped(n, 0), band(n, 0);
    for (std::size_t q = 0; q < n; ++q)
        if (!occ[q].empty()) dropped[q] = drop_local(*bodies_[tracked[q]], occ[q]);
    dec_.sum_in_place(dropped);
    bool any = false;
    for (std::size_t q = 0; q < n; ++q) {
        if (dropped[q] == 0) continue;
        any = true;
        const Body& body = *bodies_[tracked[q]];
        if (body.patch().empty()) continue;
        const Field& phi = body.phi();
        for_each_in(phi.owned(),
                    [&](int i, int j, int k) { band[q] += phi(i, j, k) * (1 - phi(i, j, k)); });
    }
    if (!any) return;
    dec_.sum_in_place(band);
    for (std::size_t q = 0; q < n; ++q) {
        if (dropped[q] == 0) continue;
        Body& body = *bodies_[tracked[q]];
        Field& phi = body.phi();
        if (band[q] > 0) {
            // Conservative to round-off; dropped ~1e-8 per cell against a band of O(1) per
            // cell, far below any other error.
            const real c = dropped[q] / band[q];
            if (!body.patch().empty())
                for_each_in(phi.owned(), [&](int i, int j, int k) {
                    phi(i, j, k) += c * phi(i, j, k) * (1 - phi(i, j, k));
                });
        } else {
            clipped_[tracked[q]] += dropped[q] * dec_.grid().cell_volume();
        }
        halos_.fill(phi, body.patch());
    }
}

void BodySystem::track_patches(bool force) {
    std::vector<std::size_t> tracked;
    for (std::size_t i = 0; i < bodies_.size(); ++i)
        if (physics_[i]->moves() || force) tracked.push_back(i);
    if (tracked.empty()) return;
    const std::size_t n = tracked.size();
    // Every tracked body's occupied box in one reduction.
    std::vector<real> ext(6 * n);
    for (std::size_t q = 0; q < n; ++q)
        occupied_extent(*bodies_[tracked[q]], ext.data() + 6 * q);
    dec_.max_in_place(ext);
    std::vector<Box> occ(n);
    for (std::size_t q = 0; q < n; ++q)
        for (int d = 0; d < 3; ++d) {
            occ[q].lo[d] = int(-ext[6 * q + d]);
            occ[q].hi[d] = int(ext[6 * q + 3 + d]);
        }
    unwrap_occupied(tracked, occ);
    if (!force) drop_residues(tracked, occ);
    for (std::size_t q = 0; q < n; ++q) {
        Body& body = *bodies_[tracked[q]];
        if (occ[q].empty()) {
            if (dec_.rank() == 0 && force)
                fmt::print("warning: body '{}' occupies no cell\n", body.name());
            continue;
        }
        // Move when the body comes within m/2 cells of its patch edge, or when the patch is
        // more than twice the box it would be fitted to now (it wrapped a periodic direction
        // that the body has since left), or when forced. Decided on the unwidened boxes, so
        // the moves do not depend on the rank layout; and since nothing is stored beyond the
        // residue reach (< m/2), a move changes what is stored, never a value the step sees.
        const int m = cfg_.bodies[tracked[q]].margin;
        Box needed = occ[q], wanted = occ[q];
        for (int d = 0; d < dec_.dim(); ++d) {
            needed.lo[d] -= m / 2;
            needed.hi[d] += m / 2;
            wanted.lo[d] -= m;
            wanted.hi[d] += m;
        }
        const Box& fitted = body.patch().fitted;
        const bool cross = cross_seam_[tracked[q]];
        const Patch target = make_patch(wanted, dec_, 2, cross);
        // A patch over the whole of x that may now cross the seam instead moves at once.
        const int nx = dec_.grid().cells[0];
        const bool leaves_whole_x = cross && fitted.lo[0] == 0 && fitted.hi[0] == nx &&
                                    target.fitted.hi[0] - target.fitted.lo[0] < nx;
        if (!force && !leaves_whole_x &&
            fitted.contains(make_patch(needed, dec_, 0, cross).fitted) &&
            fitted.count() <= 2 * target.fitted.count())
            continue;
        body.move_to(target);
        halos_.fill(body.phi(), body.patch());
    }
}

void BodySystem::advance(const VelocityField& u, real dt, long step, StageTimers& timers) {
    // Body after body with no global reduction in between (only the halo exchanges of each
    // patch, among the ranks it spans): a rank that holds one body does not wait while
    // another rank advances a different one. The VOF statistics are reduced afterwards.
    std::vector<VofStepStats> local(bodies_.size());
    // One copy of u with wide halos per step serves every membrane's surface velocity.
    if (surface_velocity_)
        timers.time("bodies_surface_velocity", [&] {
            std::vector<Box> patches;
            for (std::size_t i : surface_velocity_bodies_)
                patches.push_back(bodies_[i]->patch().global);
            surface_velocity_->load(u, patches);
        });
    // Patches across the periodic x seam read the velocity from a copy whose x halo reaches
    // past them (the same values: the flow is periodic there).
    const VelocityField& uv = seam_velocity(u);
    const BodyStep s{uv, dt, step, timers, surface_velocity_.get()};
    std::vector<std::size_t> moving;
    for (std::size_t i = 0; i < bodies_.size(); ++i)
        if (physics_[i]->moves()) moving.push_back(i);
    // The tensors first, with the velocity gradient of this step; then phi; then the
    // profiles and the tensors' extensions. The tensors and the extensions run all bodies in
    // rounds of halo fills (bodies/body_work.hpp); phi sweep by sweep over all bodies, with one
    // halo fill for all of them after each sweep (a body shared with another rank would
    // otherwise make each rank wait for the other at each of its sweeps: measured,
    // capillary_coarse on 2 ranks, a third of the VOF's time). Each body's arithmetic is as
    // body by body.
    auto in_rounds = [&](const char* stage, auto&& work_of) {
        timers.time(stage, [&] {
            std::vector<BodyWork> works;
            for (std::size_t i : moving)
                works.push_back(work_of(i));
            run_in_rounds(works, halos_);
        });
    };
    in_rounds("bodies_tensor",
              [&](std::size_t i) { return physics_[i]->advance_tensor(*bodies_[i], s); });
    timers.time("bodies_vof", [&] {
        std::vector<Field*> phis;
        std::vector<const Patch*> patches;
        for (std::size_t i : moving) {
            local[i] = physics_[i]->vof().start(bodies_[i]->phi(), &bodies_[i]->patch());
            phis.push_back(&bodies_[i]->phi());
            patches.push_back(&bodies_[i]->patch());
        }
        for (int sweep = 0; sweep < dec_.dim(); ++sweep) {
            for (std::size_t i : moving)
                physics_[i]->vof().sweep_step(bodies_[i]->phi(), uv, dt, step, sweep,
                                              &bodies_[i]->patch(), local[i]);
            halos_.fill(phis, patches);
        }
    });
    in_rounds("bodies_extension", [&](std::size_t i) {
        return physics_[i]->finish_advance(*bodies_[i], s, local[i].clipped_volume);
    });
    timers.time("bodies_vof_reduce", [&] {
        for (std::size_t i = 0; i < bodies_.size(); ++i)
            if (physics_[i]->moves())
                clipped_[i] = VofAdvection::reduce(dec_, local[i]).clipped_volume;
    });
    timers.time("bodies_patches", [&] { track_patches(false); });
}

void BodySystem::update_viscosity(Field& mu) const {
    std::vector<const Body*> list;
    std::vector<SolidLaw> laws;
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        list.push_back(bodies_[i].get());
        laws.push_back(SolidLaw{0, physics_[i]->viscosity()});
    }
    update_mixture_viscosity(mu, cfg_.fluid.viscosity, list, laws);
}

bool BodySystem::viscosity_varies() const {
    for (const auto& p : physics_)
        if (p->viscosity() != cfg_.fluid.viscosity) return true;
    return false;
}

bool BodySystem::adds_force() const {
    if (cfg_.contact.stiffness > 0 && bodies_.size() > 1) return true;
    for (const auto& p : physics_)
        if (p->adds_force()) return true;
    return false;
}

void BodySystem::add_forces(VelocityField& force) {
    for (int c = 0; c < force.dim; ++c)
        force[c].fill(0);
    // Each body's work on its own fields in rounds of halo fills (a rank does not wait at a
    // body's fill while the other still works on a body it holds more of), then the forces
    // added body after body: the sums of a body-by-body loop (patches across the periodic x
    // seam add to a copy whose x halo is folded back afterwards).
    std::vector<BodyWork> works;
    for (std::size_t i = 0; i < bodies_.size(); ++i)
        works.push_back(physics_[i]->prepare_force(*bodies_[i]));
    run_in_rounds(works, halos_);
    VelocityField& target = seam_force(force);
    for (std::size_t i = 0; i < bodies_.size(); ++i)
        physics_[i]->add_force(*bodies_[i], target);
    if (cfg_.contact.stiffness > 0 && bodies_.size() > 1) {
        std::vector<const Body*> list;
        std::vector<bool> held;
        for (std::size_t i = 0; i < bodies_.size(); ++i) {
            list.push_back(bodies_[i].get());
            held.push_back(!physics_[i]->moves());
        }
        add_contact_forces(list, held, dec_, cfg_.contact.stiffness, target);
    }
    fold_seam_force(force);
}

bool BodySystem::add_pinning(Field& chi) const {
    bool any = false;
    for (std::size_t i = 0; i < bodies_.size(); ++i)
        any = physics_[i]->add_pinning(*bodies_[i], chi) || any;
    return any;
}

std::vector<TimeStepLimit> BodySystem::time_step_limits() const {
    std::vector<TimeStepLimit> out;
    for (const auto& p : physics_)
        for (const TimeStepLimit& l : p->time_step_limits()) {
            auto same = std::find_if(out.begin(), out.end(),
                                     [&](const TimeStepLimit& o) { return o.name == l.name; });
            if (same == out.end())
                out.push_back(l);
            else
                same->dt = std::min(same->dt, l.dt);
        }
    return out;
}

real BodySystem::vof_time_step_limit(const GlobalGrid& g, real max_speed) {
    real h = g.dx(0);
    for (int d = 1; d < g.dim; ++d)
        h = std::min(h, g.dx(d));
    return max_speed > 0 ? 0.45 * h / max_speed : 0.0;
}

} // namespace efsi
