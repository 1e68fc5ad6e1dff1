#include "simulation/adhesion_record.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <fstream>

namespace efsi {

const char* AdhesionRecord::csv_header() {
    return "step,time,bonds,formed,broken,free_near,bodies_near,max_tension,time_step_limit";
}

void AdhesionRecord::after_forces(const adhesion::Coupling& c) {
    max_tension_ = std::max(max_tension_, c.stats().max_tension);
}

void AdhesionRecord::after_advance(const adhesion::Coupling& c, real time) {
    const adhesion::StepStats& k = c.stats().kinetics;
    formed_ += k.formed;
    broken_ += k.broken;
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
        out << fmt::format("{},{:.10e},{},{},{},{},{},{:.6e},{:.6e}\n", step, time, c.bond_count(),
                           formed_, broken_, c.stats().kinetics.examined, near,
                           c.stats().max_tension, std::isfinite(limit) ? limit : 0.0);
        out.close();
        ok = static_cast<bool>(out);
    }
    formed_ = broken_ = 0;
    return ok;
}

nlohmann::json AdhesionRecord::summary(const adhesion::Coupling& c) const {
    nlohmann::json per_body = nlohmann::json::object();
    for (const adhesion::BodyReceptors& b : c.bodies())
        per_body[b.name] = {{"receptors", b.end - b.begin}, {"bonds", b.bonds}};
    return {{"receptors", c.receptors().size()},
            {"ligands", c.ligands().size()},
            {"bonds", c.bond_count()},
            {"max_bonds", max_bonds_},
            {"bonds_formed", total_formed_},
            {"bonds_broken", total_broken_},
            {"first_bond_time",
             first_bond_time_ < 0 ? nlohmann::json(nullptr) : nlohmann::json(first_bond_time_)},
            {"max_tension", max_tension_},
            {"bodies", per_body}};
}

} // namespace efsi
