#include "simulation/adhesion_record.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <fstream>

namespace efsi {

const char* AdhesionRecord::csv_header() {
    return "step,time,bonds,formed,broken,free_near,bodies_near,max_tension,time_step_limit,"
           "force_bodies_x,force_bodies_y,force_bodies_z,reaction_walls_x,reaction_walls_y,"
           "reaction_walls_z,reaction_held_x,reaction_held_y,reaction_held_z,wall_lift,"
           "wall_support_x,wall_support_y,wall_support_z";
}

void AdhesionRecord::after_forces(const adhesion::Coupling& c, real dt) {
    const adhesion::CouplingStats& s = c.stats();
    max_tension_ = std::max(max_tension_, s.max_tension);
    for (int a = 0; a < 3; ++a) {
        impulse_bodies_[a] += s.force_on_bodies[a] * dt;
        impulse_walls_[a] += s.reaction_on_walls[a] * dt;
        impulse_held_[a] += s.reaction_on_held[a] * dt;
    }
}

void AdhesionRecord::after_advance(const adhesion::Coupling& c, real time) {
    const adhesion::StepStats& k = c.stats().kinetics;
    formed_ += k.formed;
    broken_ += k.broken;
    lift_ += c.stats().wall_lift;
    total_lift_ += c.stats().wall_lift;
    total_formed_ += k.formed;
    total_broken_ += k.broken;
    const std::size_t bonds = c.bond_count();
    max_bonds_ = std::max(max_bonds_, bonds);
    if (bonds > 0 && first_bond_time_ < 0) first_bond_time_ = time;
}

bool AdhesionRecord::append_row(const std::filesystem::path& file, const adhesion::Coupling& c,
                                long step, real time, bool write) {
    bool ok = true;
    if (write) {
        std::size_t near = 0;
        for (const adhesion::BodyReceptors& b : c.bodies())
            near += b.near ? 1 : 0;
        const real limit = c.stable_time_step();
        std::ofstream out(file, std::ios::app);
        const adhesion::CouplingStats& s = c.stats();
        out << fmt::format("{},{:.10e},{},{},{},{},{},{:.6e},{:.6e}", step, time, c.bond_count(),
                           formed_, broken_, s.kinetics.examined, near, s.max_tension,
                           std::isfinite(limit) ? limit : 0.0);
        for (const Real3* v : {&s.force_on_bodies, &s.reaction_on_walls, &s.reaction_on_held})
            out << fmt::format(",{:.10e},{:.10e},{:.10e}", (*v)[0], (*v)[1], (*v)[2]);
        out << fmt::format(",{:.6e}", lift_);
        out << fmt::format(",{:.10e},{:.10e},{:.10e}\n", s.wall_support[0], s.wall_support[1],
                           s.wall_support[2]);
        out.close();
        ok = static_cast<bool>(out);
    }
    formed_ = broken_ = 0;
    lift_ = 0;
    return ok;
}

nlohmann::json AdhesionRecord::summary(const adhesion::Coupling& c) const {
    nlohmann::json per_body = nlohmann::json::object();
    for (const adhesion::BodyReceptors& b : c.bodies())
        per_body[b.name] = {{"receptors", b.end - b.begin}, {"bonds", b.bonds}};
    const adhesion::CouplingStats& s = c.stats();
    return {
        {"receptors", c.receptors().size()},
        {"ligands", c.ligands().size()},
        {"bonds", c.bond_count()},
        {"max_bonds", max_bonds_},
        {"bonds_formed", total_formed_},
        {"bonds_broken", total_broken_},
        {"first_bond_time",
         first_bond_time_ < 0 ? nlohmann::json(nullptr) : nlohmann::json(first_bond_time_)},
        {"max_tension", max_tension_},
        {"wall_lift", total_lift_},
        {"force_on_bodies", {s.force_on_bodies[0], s.force_on_bodies[1], s.force_on_bodies[2]}},
        {"reaction_on_walls",
         {s.reaction_on_walls[0], s.reaction_on_walls[1], s.reaction_on_walls[2]}},
        {"reaction_on_held", {s.reaction_on_held[0], s.reaction_on_held[1], s.reaction_on_held[2]}},
        {"impulse_on_bodies", {impulse_bodies_[0], impulse_bodies_[1], impulse_bodies_[2]}},
        {"impulse_on_walls", {impulse_walls_[0], impulse_walls_[1], impulse_walls_[2]}},
        {"impulse_on_held", {impulse_held_[0], impulse_held_[1], impulse_held_[2]}},
        {"bodies", per_body}};
}

void AdhesionRecord::save(StateRecord& r) const {
    r.integers["record_counts"] = {formed_, broken_, total_formed_, total_broken_, max_bonds_};
    std::vector<double>& v = r.reals["record_reals"];
    v = {first_bond_time_, smallest_limit_, max_tension_, lift_, total_lift_};
    for (const Real3* i : {&impulse_bodies_, &impulse_walls_, &impulse_held_})
        v.insert(v.end(), i->begin(), i->end());
}

void AdhesionRecord::restore(const StateRecord& r) {
    const std::vector<std::uint64_t>& n = r.integer_array("record_counts", 5);
    const std::vector<double>& v = r.real_array("record_reals", 14);
    formed_ = n[0];
    broken_ = n[1];
    total_formed_ = n[2];
    total_broken_ = n[3];
    max_bonds_ = n[4];
    first_bond_time_ = v[0];
    smallest_limit_ = v[1];
    max_tension_ = v[2];
    lift_ = v[3];
    total_lift_ = v[4];
    for (int a = 0; a < 3; ++a) {
        impulse_bodies_[a] = v[5 + a];
        impulse_walls_[a] = v[8 + a];
        impulse_held_[a] = v[11 + a];
    }
}

} // namespace efsi
