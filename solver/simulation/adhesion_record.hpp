// What a run records of platelet adhesion (docs/output.md, docs/method.md "Adhesion in the
// time step"): adhesion.csv, one row per diagnostics step (bonds held, formed and broken since
// the previous row, free receptors near a ligand box, largest tension, the bond springs'
// time-step limit, how far rigid receptors were lifted back onto a wall), and the `adhesion` entry
// of summary.json (totals over the run).
#pragma once

#include "adhesion/coupling.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <limits>

namespace efsi {

class AdhesionRecord {
  public:
    static const char* csv_header();
    /// After the step's add_bond_forces (step length dt): the largest tension so far, the
    /// impulses of the bonds on the bodies and of their reactions on the walls.
    void after_forces(const adhesion::Coupling& c, real dt);
    /// After the step's advance (`time` at the end of the step): bonds formed and broken.
    void after_advance(const adhesion::Coupling& c, real time);
    /// The named limit's value this step [s] (finite: bonds are held).
    void note_limit(real dt) { smallest_limit_ = std::min(smallest_limit_, dt); }
    real smallest_limit() const { return smallest_limit_; }
    /// Appends a row to `file` (call on one rank) and starts the next interval's counts on
    /// every rank. False if the append failed.
    bool append_row(const std::filesystem::path& file, const adhesion::Coupling& c, long step,
                    real time, bool write);
    nlohmann::json summary(const adhesion::Coupling& c) const;
    /// The counts, extremes and impulses into `r` (arrays record_counts, record_reals), so
    /// that a restarted run's rows and totals continue the checkpointed run's.
    void save(StateRecord& r) const;
    /// Takes back what save wrote (InputError naming the array when it does not fit).
    void restore(const StateRecord& r);

  private:
    std::size_t formed_ = 0, broken_ = 0;             ///< since the last row
    std::size_t total_formed_ = 0, total_broken_ = 0; ///< over the run (restarts included)
    std::size_t max_bonds_ = 0;
    real first_bond_time_ = -1; ///< end of the step that formed the first bond [s]
    real smallest_limit_ = std::numeric_limits<real>::infinity(); ///< [s]
    real max_tension_ = 0;                                        ///< [N]
    real lift_ = 0;       ///< receptors lifted back onto walls since the last row [m]
    real total_lift_ = 0; ///< the same over the run [m]
    Real3 impulse_bodies_{}, impulse_walls_{}, impulse_held_{}; ///< sum of F dt [N s]
};

} // namespace efsi
