#include "adhesion/coupling.hpp"

#include "core/error.hpp"

#include <fmt/core.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace efsi::adhesion {

namespace {

std::string point_text(const Real3& x) {
    return fmt::format("({:.6g}, {:.6g}, {:.6g}) m", x[0], x[1], x[2]);
}

/// Shift applied along periodic axis a to bring coordinate c into [lo, lo + L).
real periodic_shift(real c, real lo, real length) {
    return -length * std::floor((c - lo) / length);
}

} // namespace

real SpringLimits::stable_dt(real k, real m, real z) {
    if (!(k > 0)) return std::numeric_limits<real>::infinity();
    return std::max(std::sqrt(2 * m / k), 2 * z / k);
}

Coupling::Coupling(const AdhesionConfig& config, const std::vector<BodyConfig>& bodies,
                   const Decomposition& dec, real density, real viscosity) {
    if (!config.enabled) return; // a scene without adhesion: nothing held, nothing done
    active_ = true;
    dec_ = &dec;
    p_ = config.parameters;
    max_step_displacement_ = config.max_step_displacement;
    motion_ = config.receptor_motion;
    kin_.emplace(p_, config.seed);
    const GlobalGrid& g = dec.grid();
    if (g.dim != 3) throw InputError("adhesion: needs a 3D grid");
    limits_.h = std::min({g.dx(0), g.dx(1), g.dx(2)});
    limits_.kernel_mass = density * g.cell_volume();
    limits_.kernel_drag = 6 * std::numbers::pi * viscosity * limits_.h;
    ligands_ = LigandSet::from_regions(config.ligand_regions, p_.reactive_distance);
    anchor({{{true, true}, {true, true}, {true, true}}}, nullptr, false);

    std::uint64_t next_id = 0;
    for (const ReceptorGroupConfig& group : config.receptors) {
        const BodyConfig& bc = bodies.at(group.body_index);
        const SurfaceEllipsoid surface = receptor_surface(bc);
        std::vector<Receptor> placed = place_receptors(surface, group.count, next_id, config.seed);
        next_id += group.count;
        BodyReceptors b;
        b.body = group.body_index;
        b.name = bc.name;
        b.begin = receptors_.size();
        // The body's receptors stay one cloud (never split by the periodic wrap): its centre
        // is brought into the domain, and the cloud is shifted as a whole.
        for (int a = 0; a < 3; ++a) {
            if (!dec.periodic()[a]) continue;
            const real s = periodic_shift(surface.centre[a], g.origin[a], g.length[a]);
            for (Receptor& r : placed)
                r.x[a] += s;
        }
        receptors_.insert(receptors_.end(), placed.begin(), placed.end());
        b.end = receptors_.size();
        const Real3& ax = surface.semi_axes;
        const real volume = 4.0 / 3.0 * std::numbers::pi * ax[0] * ax[1] * ax[2];
        b.mass = density * volume;
        b.drag = 6 * std::numbers::pi * viscosity * std::cbrt(ax[0] * ax[1] * ax[2]);
        update_bounds(b);
        bodies_.push_back(std::move(b));
    }
    x_.reserve(receptors_.size());
    v_.reserve(receptors_.size());
    work_.reserve(receptors_.size());
}

void Coupling::anchor(const std::array<std::array<bool, 2>, 3>& no_slip,
                      const VelocityField* pinning) {
    anchor(no_slip, pinning, true);
}

void Coupling::anchor(const std::array<std::array<bool, 2>, 3>& no_slip,
                      const VelocityField* pinning, bool strict) {
    if (!active_) return;
    const GlobalGrid& g = dec_->grid();
    pinning_ = pinning;
    for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side)
            no_slip_[a][side] = no_slip[a][side] && !dec_->periodic()[a];
    anchor_.assign(ligands_.size(), LigandAnchor::none);
    std::vector<std::uint64_t> off_wall;
    for (std::uint64_t id = 0; id < ligands_.size(); ++id) {
        const Real3& y = ligands_.position(id);
        for (int a = 0; a < 3; ++a) {
            if (dec_->periodic()[a]) continue;
            const real tol = 0.5 * g.dx(a);
            if ((no_slip[a][0] && y[a] - g.origin[a] <= tol) ||
                (no_slip[a][1] && g.origin[a] + g.length[a] - y[a] <= tol))
                anchor_[id] = LigandAnchor::domain_wall;
        }
        if (anchor_[id] == LigandAnchor::none) off_wall.push_back(id);
    }
    if (off_wall.empty()) return;
    std::vector<real> share(off_wall.size(), 0.0);
    if (pinning) {
        std::vector<Real3> x(off_wall.size());
        for (std::size_t k = 0; k < off_wall.size(); ++k)
            x[k] = ligands_.position(off_wall[k]);
        held_spreader_.held_share(*pinning, *dec_, x, share);
    }
    for (std::size_t k = 0; k < off_wall.size(); ++k) {
        if (share[k] >= min_held_share) {
            anchor_[off_wall[k]] = LigandAnchor::held_body;
            continue;
        }
        if (!strict) continue;
        const std::uint64_t id = off_wall[k];
        throw InputError(fmt::format(
            "adhesion.ligand_regions[{}]: ligand {} at {} is neither within half a cell of a "
            "no-slip wall of the domain nor on a pinned solid (held share of its kernel {:.3g} "
            "< {:g}): a vWF ligand is anchored to the vessel wall, which must take the bond's "
            "reaction (docs/method.md, \"The wall takes the reaction\")",
            ligands_.region_of(id), id, point_text(ligands_.position(id)), share[k],
            min_held_share));
    }
}

Real3 Coupling::canonical(Real3 x) const {
    const GlobalGrid& g = dec_->grid();
    for (int a = 0; a < 3; ++a)
        if (dec_->periodic()[a]) {
            x[a] += periodic_shift(x[a], g.origin[a], g.length[a]);
            if (x[a] >= g.origin[a] + g.length[a]) x[a] = g.origin[a]; // round-off
        }
    return x;
}

Real3 Coupling::image_near(Real3 x, const Real3& anchor) const {
    const GlobalGrid& g = dec_->grid();
    for (int a = 0; a < 3; ++a)
        if (dec_->periodic()[a]) x[a] -= g.length[a] * std::round((x[a] - anchor[a]) / g.length[a]);
    return x;
}

bool Coupling::may_reach(const Real3& lo, const Real3& hi, real d) const {
    const GlobalGrid& g = dec_->grid();
    for (const auto& [blo, bhi] : ligands_.boxes()) {
        real s = 0;
        for (int a = 0; a < 3; ++a) {
            real gap = std::max({blo[a] - hi[a], lo[a] - bhi[a], real(0)});
            if (dec_->periodic()[a])
                for (real shift : {-g.length[a], g.length[a]})
                    gap = std::min(gap, std::max({blo[a] - (hi[a] + shift),
                                                  (lo[a] + shift) - bhi[a], real(0)}));
            s += gap * gap;
        }
        if (std::sqrt(s) <= d) return true;
    }
    return false;
}

void Coupling::copy_to_work(BodyReceptors& b) {
    b.work = work_.size();
    for (std::size_t k = b.begin; k < b.end; ++k) {
        Receptor r = receptors_[k];
        r.x = r.bound() ? image_near(r.x, ligands_.position(r.ligand)) : canonical(r.x);
        work_.push_back(r);
    }
}

void Coupling::update_bounds(BodyReceptors& b) {
    const real inf = std::numeric_limits<real>::infinity();
    b.lo = {inf, inf, inf};
    b.hi = {-inf, -inf, -inf};
    for (std::size_t k = b.begin; k < b.end; ++k)
        for (int a = 0; a < 3; ++a) {
            b.lo[a] = std::min(b.lo[a], receptors_[k].x[a]);
            b.hi[a] = std::max(b.hi[a], receptors_[k].x[a]);
        }
}

std::size_t Coupling::bond_count() const {
    std::size_t n = 0;
    for (const BodyReceptors& b : bodies_)
        n += b.bonds;
    return n;
}

real Coupling::stable_time_step() const {
    real dt = std::numeric_limits<real>::infinity();
    if (!active_) return dt;
    const real sigma = p_.bond_stiffness;
    for (const BodyReceptors& b : bodies_) {
        if (b.bonds == 0) continue;
        dt = std::min(dt,
                      SpringLimits::stable_dt(static_cast<real>(b.bonds) * sigma, b.mass, b.drag));
        dt = std::min(dt, SpringLimits::stable_dt(sigma, limits_.kernel_mass, limits_.kernel_drag));
    }
    return dt;
}

void Coupling::report_unstable_body(const BodyReceptors& b, real dt, real number) const {
    // The most loaded bond, to say where.
    const Receptor* worst = nullptr;
    Real3 worst_x{};
    real worst_t = -1;
    for (std::size_t k = b.begin; k < b.end; ++k) {
        const Receptor& r = receptors_[k];
        if (!r.bound()) continue;
        const Real3 xr = image_near(r.x, ligands_.position(r.ligand));
        const BondForce f =
            bond_force(xr, ligands_.position(r.ligand), p_.bond_stiffness, p_.bond_rest_length);
        if (std::abs(f.tension) > worst_t) {
            worst_t = std::abs(f.tension);
            worst = &r;
            worst_x = xr;
        }
    }
    const real k = static_cast<real>(b.bonds) * p_.bond_stiffness;
    throw RunError(fmt::format(
        "adhesion: body '{}' holds {} bonds of stiffness {:g} N/m; with dt = {:.4g} s the "
        "explicit springs are unstable (n sigma dt min(dt/m, 1/(6 pi mu a)) = {:.3g} > 2, "
        "m = {:.3g} kg, 6 pi mu a = {:.3g} N s/m): dt must stay below {:.4g} s "
        "(stable_time_step). Most loaded bond: receptor {} at {} with ligand {} at {}, "
        "tension {:.4g} N",
        b.name, b.bonds, p_.bond_stiffness, dt, number, b.mass, b.drag,
        SpringLimits::stable_dt(k, b.mass, b.drag), worst ? worst->id : 0,
        worst ? point_text(worst_x) : "-", worst ? worst->ligand : 0,
        worst ? point_text(ligands_.position(worst->ligand)) : "-", worst_t));
}

void Coupling::add_bond_forces(VelocityField& force, real dt) {
    stats_.bonds_spread = stats_.face_writes = 0;
    stats_.max_tension = 0;
    stats_.force_on_bodies = stats_.reaction_on_walls = stats_.reaction_on_held = {0, 0, 0};
    stats_.wall_support = {0, 0, 0};
    held_x_.clear();
    held_f_.clear();
    if (!active_) return;
    if (!(dt > 0) || !std::isfinite(dt))
        throw RunError(fmt::format("adhesion: time step dt = {:g} s must be positive", dt));
    const real sigma = p_.bond_stiffness;
    const real mk = SpringLimits::mobility(dt, limits_.kernel_mass, limits_.kernel_drag);
    // The per-bond force limit: the receptor's kernel, pushed by F alone for one step,
    // moves at most max_step_displacement cells.
    AdhesionParameters p = p_;
    p.max_bond_force = max_step_displacement_ * limits_.h / (mk * dt);
    const bool rigid = motion_ == ReceptorMotion::rigid;
    if (rigid) rigid_loads_.assign(bodies_.size(), RigidLoad{});
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        const BodyReceptors& b = bodies_[i];
        if (b.bonds == 0) continue;
        const real body_number =
            static_cast<real>(b.bonds) * sigma * dt * SpringLimits::mobility(dt, b.mass, b.drag);
        if (body_number > 2) report_unstable_body(b, dt, body_number);
        if (sigma * dt * mk > 2)
            throw RunError(fmt::format(
                "adhesion: body '{}': a single bond of stiffness {:g} N/m is unstable with "
                "dt = {:.4g} s on the grid (sigma dt min(dt/(rho h^3), 1/(6 pi mu h)) = {:.3g} > "
                "2): dt must stay below {:.4g} s (stable_time_step)",
                b.name, sigma, dt, sigma * dt * mk,
                SpringLimits::stable_dt(sigma, limits_.kernel_mass, limits_.kernel_drag)));
        loads_.clear();
        work_.clear();
        for (std::size_t k = b.begin; k < b.end; ++k)
            if (receptors_[k].bound()) {
                Receptor r = receptors_[k];
                r.x = image_near(r.x, ligands_.position(r.ligand));
                work_.push_back(r);
            }
        try {
            bond_loads(work_, ligands_, p, loads_);
        } catch (const RunError& e) {
            throw RunError(fmt::format(
                "{} (body '{}'; the limit is max_step_displacement h / (dt min(dt/(rho h^3), "
                "1/(6 pi mu h))) with max_step_displacement = {:g} cells, h = {:.4g} m, dt = "
                "{:.4g} s: the bond's force alone would move its receptor farther than that in "
                "one step)",
                e.what(), b.name, max_step_displacement_, limits_.h, dt));
        }
        RigidLoad& load = rigid ? rigid_loads_[i] : scratch_load_;
        for (int a = 0; a < 3; ++a)
            load.point[a] = 0.5 * (b.lo[a] + b.hi[a]);
        for (const BondLoad& l : loads_) {
            if (rigid) {
                // Summed into the body's force and torque (spread by the caller over the
                // body, bodies/rigid_fit.hpp).
                add_to_load(load, l.receptor_x, l.force.on_receptor);
            } else {
                stats_.face_writes += spread_force(force, *dec_, l.receptor_x, l.force.on_receptor);
            }
            for (int a = 0; a < 3; ++a)
                stats_.force_on_bodies[a] += l.force.on_receptor[a];
            // The reaction: taken by the wall the ligand is anchored to.
            switch (anchor_[l.ligand]) {
            case LigandAnchor::domain_wall:
                for (int a = 0; a < 3; ++a)
                    stats_.reaction_on_walls[a] += l.force.on_ligand[a];
                break;
            case LigandAnchor::held_body:
                held_x_.push_back(l.ligand_x);
                held_f_.push_back(l.force.on_ligand);
                for (int a = 0; a < 3; ++a)
                    stats_.reaction_on_held[a] += l.force.on_ligand[a];
                break;
            case LigandAnchor::none:
                throw RunError(fmt::format(
                    "adhesion: receptor {} (body '{}') is bound to ligand {} at {}, which is "
                    "anchored to no wall (Coupling::anchor was not given a wall or a pinned "
                    "solid there): its bond's reaction has nowhere to go",
                    l.receptor, b.name, l.ligand, point_text(l.ligand_x)));
            }
            stats_.max_tension = std::max(stats_.max_tension, std::abs(l.force.tension));
            ++stats_.bonds_spread;
        }
        if (rigid) support_on_walls(b, load);
    }
    // Every rank holds the same bonds, so every rank makes this collective call or none.
    if (!held_x_.empty())
        stats_.face_writes +=
            held_spreader_.spread(force, *pinning_, *dec_, held_x_, held_f_, min_held_share);
}

void Coupling::kinetics(real dt, std::uint64_t step) {
    const real reach = p_.reactive_distance + p_.margin;
    proposals_.clear();
    work_.clear();
    // The skip test, then a working copy of the near bodies' receptors as the kinetics
    // sees them (periodic images, see the header).
    for (BodyReceptors& b : bodies_) {
        b.near =
            b.bonds > 0 || (!ligands_.empty() && b.end > b.begin && may_reach(b.lo, b.hi, reach));
        if (!b.near) {
            ++stats_.bodies_skipped;
            continue;
        }
        ++stats_.bodies_near;
        copy_to_work(b);
    }
    if (work_.empty()) return;
    // Proposals of every body first (they see the ligands free at the start of the step),
    // then the ruptures, then one resolution over all proposals: the kinetics of one step
    // as in Kinetics::step, over the bodies that passed the skip test.
    for (const BodyReceptors& b : bodies_) {
        if (!b.near) continue;
        const std::size_t first = proposals_.size();
        kin_->propose(std::span<const Receptor>(work_).subspan(b.work, b.end - b.begin), ligands_,
                      step, dt, proposals_, stats_.kinetics);
        for (std::size_t q = first; q < proposals_.size(); ++q)
            proposals_[q].slot += b.work;
    }
    for (const BodyReceptors& b : bodies_) {
        if (!b.near || b.bonds == 0) continue; // nothing to break
        kin_->rupture(std::span<Receptor>(work_).subspan(b.work, b.end - b.begin), ligands_, step,
                      dt, stats_.kinetics);
    }
    Kinetics::resolve(proposals_, stats_.kinetics);
    Kinetics::apply(work_, ligands_, proposals_, stats_.kinetics);
    // Back to the stored receptors: their bonds (positions are not changed by the kinetics).
    for (BodyReceptors& b : bodies_) {
        if (!b.near) continue;
        b.bonds = 0;
        for (std::size_t k = b.begin; k < b.end; ++k) {
            receptors_[k].ligand = work_[b.work + (k - b.begin)].ligand;
            b.bonds += receptors_[k].bound() ? 1 : 0;
        }
    }
}

std::string Coupling::body_name_of(std::size_t k) const {
    for (const BodyReceptors& b : bodies_)
        if (k >= b.begin && k < b.end) return b.name;
    return "?";
}

void Coupling::check_inside(std::span<const Real3> at) const {
    const GlobalGrid& g = dec_->grid();
    for (std::size_t k = 0; k < at.size(); ++k)
        for (int a = 0; a < 3; ++a)
            if (!dec_->periodic()[a] &&
                !(at[k][a] >= g.origin[a] && at[k][a] <= g.origin[a] + g.length[a]))
                throw RunError(fmt::format("adhesion: receptor {} (body '{}') is at {}, outside "
                                           "the domain through the wall in {} (the step moved it "
                                           "too far: dt too large for the flow near the wall?)",
                                           receptors_[k].id, body_name_of(k), point_text(at[k]),
                                           "xyz"[a]));
}

void Coupling::carry(const VelocityField& u, real dt) {
    if (!active_ || receptors_.empty()) return;
    x_.resize(receptors_.size());
    v_.resize(receptors_.size());
    auto interpolate = [&](std::span<const Real3> at) {
        try {
            interpolator_.interpolate(u, *dec_, at, v_);
        } catch (const RunError&) {
            check_inside(at); // names the receptor when it left through a wall
            throw;
        }
    };
    // Midpoint rule on the frozen field: x* = x + dt/2 u(x), x' = x + dt u(x*).
    for (std::size_t k = 0; k < receptors_.size(); ++k)
        x_[k] = receptors_[k].x;
    interpolate(x_);
    for (std::size_t k = 0; k < receptors_.size(); ++k)
        for (int a = 0; a < 3; ++a)
            x_[k][a] = receptors_[k].x[a] + 0.5 * dt * v_[k][a];
    interpolate(x_);
    for (std::size_t k = 0; k < receptors_.size(); ++k)
        for (int a = 0; a < 3; ++a)
            x_[k][a] = receptors_[k].x[a] + dt * v_[k][a];
    place_moved();
}

void Coupling::place_moved() {
    const GlobalGrid& g = dec_->grid();
    check_inside(x_);
    for (std::size_t k = 0; k < receptors_.size(); ++k)
        receptors_[k].x = x_[k];
    // Periodic wrap, a body's cloud as a whole, and only while it holds no bond (a bond's
    // vector is taken between the stored positions).
    for (BodyReceptors& b : bodies_) {
        update_bounds(b);
        if (b.bonds > 0) continue;
        for (int a = 0; a < 3; ++a) {
            if (!dec_->periodic()[a]) continue;
            const real s = periodic_shift(0.5 * (b.lo[a] + b.hi[a]), g.origin[a], g.length[a]);
            if (s == 0) continue;
            for (std::size_t k = b.begin; k < b.end; ++k)
                receptors_[k].x[a] += s;
            b.lo[a] += s;
            b.hi[a] += s;
        }
    }
}

void Coupling::save(StateRecord& r) const {
    if (!active_) return;
    std::vector<std::uint64_t>& id = r.integers["receptor_id"];
    std::vector<std::uint64_t>& ligand = r.integers["receptor_ligand"];
    std::vector<double>& x = r.reals["receptor_x"];
    id.clear();
    ligand.clear();
    x.clear();
    for (const Receptor& q : receptors_) {
        id.push_back(q.id);
        ligand.push_back(q.ligand);
        x.insert(x.end(), q.x.begin(), q.x.end());
    }
}

void Coupling::restore(const StateRecord& r) {
    if (!active_) return;
    const std::size_t n = receptors_.size();
    const std::vector<std::uint64_t>& id = r.integer_array("receptor_id", n);
    const std::vector<double>& x = r.real_array("receptor_x", 3 * n);
    const std::vector<std::uint64_t>& ligand = r.integer_array("receptor_ligand", n);
    for (std::size_t k = 0; k < n; ++k) {
        if (id[k] != receptors_[k].id)
            throw InputError(fmt::format("array 'receptor_id': entry {} is receptor {} where the "
                                         "case places receptor {}",
                                         k, id[k], receptors_[k].id));
        if (ligand[k] != no_ligand && ligand[k] >= ligands_.size())
            throw InputError(fmt::format("array 'receptor_ligand': receptor {} is bound to ligand "
                                         "{}, which does not exist ({} ligands)",
                                         id[k], ligand[k], ligands_.size()));
        for (int a = 0; a < 3; ++a)
            if (!std::isfinite(x[3 * k + a]))
                throw InputError(fmt::format("array 'receptor_x': receptor {} is at a non-finite "
                                             "position",
                                             id[k]));
    }
    for (std::uint64_t l = 0; l < ligands_.size(); ++l)
        ligands_.release(l);
    for (std::size_t k = 0; k < n; ++k) {
        Receptor& q = receptors_[k];
        q.x = {x[3 * k], x[3 * k + 1], x[3 * k + 2]};
        q.ligand = ligand[k];
        if (!q.bound()) continue;
        if (!ligands_.free(q.ligand))
            throw InputError(fmt::format("array 'receptor_ligand': ligand {} is bound to "
                                         "receptors {} and {}",
                                         q.ligand, ligands_.bound_receptor(q.ligand), q.id));
        ligands_.bind(q.ligand, q.id);
    }
    for (BodyReceptors& b : bodies_) {
        b.bonds = 0;
        for (std::size_t k = b.begin; k < b.end; ++k)
            b.bonds += receptors_[k].bound() ? 1 : 0;
        update_bounds(b);
    }
}

void Coupling::advance(const VelocityField& u, real dt, std::uint64_t step,
                       std::span<const RigidMotion> motions) {
    stats_.bodies_near = stats_.bodies_skipped = 0;
    stats_.kinetics = {};
    stats_.wall_lift = 0;
    if (!active_) return;
    if (!(dt > 0) || !std::isfinite(dt))
        throw RunError(fmt::format("adhesion: time step dt = {:g} s must be positive", dt));
    kinetics(dt, step);
    if (motion_ == ReceptorMotion::rigid)
        carry_rigidly(motions, dt);
    else
        carry(u, dt);
}

} // namespace efsi::adhesion
