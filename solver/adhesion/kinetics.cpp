#include "adhesion/kinetics.hpp"

#include "adhesion/bond.hpp"
#include "adhesion/counter_rng.hpp"
#include "adhesion/dissociation.hpp"
#include "core/error.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <tuple>

namespace efsi::adhesion {

Kinetics::Kinetics(const AdhesionParameters& params, std::uint64_t seed) : p_(params), seed_(seed) {
    p_.validate();
}

namespace {

void check_dt(real dt) {
    if (!(dt > 0) || !std::isfinite(dt))
        throw RunError(fmt::format("adhesion: time step dt = {:g} s must be positive", dt));
}

} // namespace

StepStats Kinetics::step(std::span<Receptor> receptors, LigandSet& ligands, std::uint64_t step,
                         real dt) {
    StepStats stats;
    proposals_.clear();
    // 1. Proposals first, so that they see the ligands free at the start of the step.
    propose(receptors, ligands, step, dt, proposals_, stats);
    // 2. Ruptures of the bonds present at the start.
    rupture(receptors, ligands, step, dt, stats);
    // 3. The proposed ligands were free at the start, so step 2 did not touch them.
    resolve(proposals_, stats);
    apply(receptors, ligands, proposals_, stats);
    return stats;
}

void Kinetics::propose(std::span<const Receptor> receptors, const LigandSet& ligands,
                       std::uint64_t step, real dt, std::vector<Proposal>& out, StepStats& stats) {
    check_dt(dt);
    const real p_on = event_probability(p_.k_on, dt);
    const real reach = p_.reactive_distance, skip_reach = p_.reactive_distance + p_.margin;
    // With k_on = 0 nothing can bind: no work at all.
    for (std::size_t slot = 0; p_on > 0 && slot < receptors.size(); ++slot) {
        const Receptor& r = receptors[slot];
        if (r.bound()) continue;
        if (ligands.empty() || !ligands.may_reach(r.x, skip_reach)) {
            ++stats.skipped;
            continue;
        }
        ++stats.examined;
        const UniformPair u = uniform_pair(seed_, r.id, step, Purpose::bind);
        if (!(u.u0 < p_on)) continue;
        candidates_.clear();
        ligands.for_each_within(r.x, reach, [&](std::uint64_t id, real) {
            if (ligands.free(id)) candidates_.push_back(id);
        });
        if (candidates_.empty()) continue;
        std::sort(candidates_.begin(), candidates_.end());
        const auto pick =
            std::min(candidates_.size() - 1,
                     static_cast<std::size_t>(u.u1 * static_cast<double>(candidates_.size())));
        out.push_back(
            {candidates_[pick], uniform_pair(seed_, r.id, step, Purpose::priority).u0, r.id, slot});
    }
}

void Kinetics::rupture(std::span<Receptor> receptors, LigandSet& ligands, std::uint64_t step,
                       real dt, StepStats& stats, std::vector<std::uint64_t>* released) const {
    check_dt(dt);
    for (Receptor& r : receptors) {
        if (!r.bound()) continue;
        if (r.ligand >= ligands.size() || ligands.bound_receptor(r.ligand) != r.id)
            throw RunError(fmt::format(
                "adhesion: receptor {} claims ligand {}, which {}", r.id, r.ligand,
                r.ligand >= ligands.size()
                    ? "does not exist"
                    : fmt::format("is bound to receptor {}", ligands.bound_receptor(r.ligand))));
        const BondForce f =
            bond_force(r.x, ligands.position(r.ligand), p_.bond_stiffness, p_.bond_rest_length);
        const real p_off = event_probability(off_rate(p_, f.tension), dt);
        if (uniform_pair(seed_, r.id, step, Purpose::rupture).u0 < p_off) {
            if (released) released->push_back(r.ligand);
            ligands.release(r.ligand);
            r.ligand = no_ligand;
            ++stats.broken;
        }
    }
}

void Kinetics::resolve(std::vector<Proposal>& proposals, StepStats& stats) {
    std::sort(proposals.begin(), proposals.end(), [](const Proposal& a, const Proposal& b) {
        return std::tie(a.ligand, a.priority, a.receptor) <
               std::tie(b.ligand, b.priority, b.receptor);
    });
    std::size_t kept = 0;
    for (std::size_t k = 0; k < proposals.size(); ++k) {
        if (k > 0 && proposals[k - 1].ligand == proposals[k].ligand) {
            ++stats.contested;
            continue;
        }
        proposals[kept++] = proposals[k];
    }
    proposals.resize(kept);
}

void Kinetics::apply(std::span<Receptor> receptors, LigandSet& ligands,
                     std::span<const Proposal> winners, StepStats& stats) {
    for (const Proposal& w : winners) {
        if (!ligands.free(w.ligand))
            throw RunError(fmt::format("adhesion: receptor {} won ligand {}, which is bound to "
                                       "receptor {}",
                                       w.receptor, w.ligand, ligands.bound_receptor(w.ligand)));
        ligands.bind(w.ligand, w.receptor);
        if (w.slot < receptors.size() && receptors[w.slot].id == w.receptor) {
            receptors[w.slot].ligand = w.ligand;
            ++stats.formed;
        }
    }
}

} // namespace efsi::adhesion
