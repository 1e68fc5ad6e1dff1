// One kinetic Monte Carlo step of receptor-ligand binding and rupture (docs/method.md,
// "Platelet adhesion (kinetic Monte Carlo)").
//
// In a step of length dt, with the states at the start of the step:
//  1. every receptor bound at the start breaks with probability 1 - exp(-k_off(F) dt), F the
//     bond's spring force (dissociation.hpp);
//  2. every receptor free at the start that has a ligand free at the start within the
//     reactive distance binds with probability 1 - exp(-k_on dt), to one of those ligands
//     picked uniformly; when several receptors pick the same ligand, the one with the smallest
//     priority draw gets it (ties: smaller id) and the others stay free this step.
// A receptor or ligand freed in step 1 cannot bind again before the next step: at most one
// event per receptor per step.
//
// Every draw is counter-based (counter_rng.hpp), keyed by (seed, receptor id, step, purpose),
// and the conflict rule depends only on the proposals, not on the order they were made: the
// outcome is the same for any processing order of the receptors, hence for any number of
// ranks as long as the proposals for one ligand are resolved together.
//
// The skip test: a free receptor farther than reactive_distance + margin from every ligand
// region gets no work (no draw, no lookup). A kinetics object and a LigandSet without ligands
// hold no memory; the scratch list of proposals grows only when a receptor proposes.
#pragma once

#include "adhesion/ligand.hpp"
#include "adhesion/parameters.hpp"
#include "adhesion/receptor.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace efsi::adhesion {

struct StepStats {
    std::size_t skipped = 0;   ///< free receptors the skip test left alone
    std::size_t examined = 0;  ///< free receptors that drew a binding number
    std::size_t formed = 0;    ///< bonds formed
    std::size_t broken = 0;    ///< bonds broken
    std::size_t contested = 0; ///< proposals lost to another receptor for the same ligand
};

/// A free receptor's bid for a ligand in one step. Plain data (no pointers), so a parallel
/// caller can gather the proposals of all ranks as bytes.
struct Proposal {
    std::uint64_t ligand = 0;
    double priority = 0;        ///< the receptor's priority draw: smallest wins
    std::uint64_t receptor = 0; ///< receptor id
    std::uint64_t slot = 0;     ///< index of the receptor in the proposing caller's span
};

class Kinetics {
  public:
    /// Validates the parameters (InputError naming the key).
    Kinetics(const AdhesionParameters& params, std::uint64_t seed);

    /// Advances receptors and ligands by one step `step` of length dt [s]: propose, rupture,
    /// resolve, apply (below). The receptors' ids must be unique; their positions are those
    /// at the start of the step.
    StepStats step(std::span<Receptor> receptors, LigandSet& ligands, std::uint64_t step, real dt);

    // The phases of a step, for a parallel caller that owns part of the receptors and a
    // copy of the ligands (tests/adhesion/test_adhesion_ranks.cpp does this on 1, 2 and 4
    // ranks and gets the serial result):
    //   propose(own receptors) -> gather all ranks' proposals;
    //   rupture(own receptors) -> gather the released ligands, release them everywhere;
    //   resolve(all proposals) -> the winners, the same on every rank;
    //   apply(own receptors, winners) on every rank.

    /// Appends the proposals of the free receptors (state at the start of the step).
    void propose(std::span<const Receptor> receptors, const LigandSet& ligands, std::uint64_t step,
                 real dt, std::vector<Proposal>& out, StepStats& stats);
    /// Breaks bonds; appends the ids of the released ligands to `released` if given.
    void rupture(std::span<Receptor> receptors, LigandSet& ligands, std::uint64_t step, real dt,
                 StepStats& stats, std::vector<std::uint64_t>* released = nullptr) const;
    /// Keeps, per ligand, the proposal with the smallest (priority, receptor id): a function
    /// of the set of proposals, not of their order.
    static void resolve(std::vector<Proposal>& proposals, StepStats& stats);
    /// Binds every winner's ligand to its receptor in `ligands`, and the receptors of
    /// `receptors` that made a winning proposal (matched by slot and id) to their ligand.
    static void apply(std::span<Receptor> receptors, LigandSet& ligands,
                      std::span<const Proposal> winners, StepStats& stats);

    const AdhesionParameters& parameters() const { return p_; }
    std::uint64_t seed() const { return seed_; }

  private:
    AdhesionParameters p_;
    std::uint64_t seed_;
    std::vector<Proposal> proposals_;
    std::vector<std::uint64_t> candidates_;
};

} // namespace efsi::adhesion
