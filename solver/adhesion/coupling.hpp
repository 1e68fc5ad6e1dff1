// Platelet adhesion coupled to the flow (docs/method.md, "Platelet adhesion", "Coupling to
// the flow"): GPIb-alpha receptors on the surfaces of the bodies named in
// [[adhesion.receptors]], moved with their body's fitted rigid motion (or with the flow); vWF
// ligands on the wall boxes of
// [[adhesion.ligand_regions]]; the kinetic Monte Carlo of kinetics.hpp between them; each
// bond's spring force spread onto the face force field at the receptor; its reaction, -F,
// taken by the wall the ligand is anchored to (docs/method.md, "The wall takes the
// reaction"): a ligand on a no-slip wall of the domain gives it to the boundary (nothing
// goes into the fluid), a ligand on a pinned solid spreads it onto that solid's held faces
// (grid_transfer.hpp, HeldSpreader), where the pinning absorbs it. The force on the bodies
// and the reaction on the walls are summed every step (stats(): equal and opposite).
//
// Where it goes in a time step of length dt (the time-step loop calls, in this order):
//   1. dt = min(other limits, time.cfl * stable_time_step())   when choosing dt
//   2. add_bond_forces(force, dt)    after the force field is zeroed and the elastic and
//                                    membrane forces are added, before the flow step
//   3. the flow step (SMAC) with that force
//   4. advance(u_mid, dt, step, m)   with u_mid = (v^n + v^n+1)/2 (halos filled) and m the
//                                    rigid motions fitted to u_mid over the bodies at the
//                                    start of the step; `step` = the step's index at its start
// Everything in a step uses the receptors' positions and bonds at the start of the step:
// the forces of (2) are those of the bonds the kinetics of (4) then breaks or keeps.
//
// Ranks: every rank holds every receptor, every ligand and every bond, and does the same
// kinetics on them (the draws are counter-based, so this is the same run on any rank
// count); interpolation is one element-wise sum of 8 values per receptor and component
// (24 N doubles, twice per step for the midpoint rule) and spreading writes owned faces
// only. Cost per step: O(N) per rank for N receptors plus two reductions of 24 N doubles
// (N ~ 100-1000 per platelet: ~0.2 MB for 1000 receptors, well under a flow step). The
// physics makes no MPI call: the reductions go through the Decomposition.
//
// receptor_motion = rigid (docs/method.md, "Receptors that move with their platelet"):
// advance moves each body's receptors with the rigid motion the caller fitted to the flow
// over the body (bodies/rigid_fit.hpp), lifting a cloud the motion takes through a no-slip
// wall back onto it; add_bond_forces spreads nothing at the receptors but sums each body's
// bond force and torque into rigid_loads() (with the wall's support of a body in contact),
// for the caller to spread over the body (the fit's adjoint).
//
// Skip what is not needed: a body with no bond whose receptors' bounding box is farther than
// reactive_distance + margin from every ligand box gets no kinetics, no ligand lookup, no
// draw and no force work (its receptors still move with the body: they must be where
// the body is when it comes near). Without [adhesion] the object holds nothing and every
// call returns at once.
//
// Periodic directions: a body's receptors are stored as one cloud (never split by the
// wrap; the cloud is shifted by a box length when its centre leaves the box and it holds no
// bond); interpolation and spreading wrap indices. The kinetics and the bond forces see a
// bound receptor at its periodic image nearest its ligand (minimum image) and a free one
// wrapped into the box; the skip test measures box distances over the periodic images. What
// is not done: a free receptor within the reactive distance of a periodic boundary does not
// see the ligands just across it (a strip one reactive distance wide, 70 nm by default).
//
// Restart (save / restore): the state is every receptor's id, position and ligand; the
// ligands' occupancy, the bond counts and the bounding boxes follow from them, and the
// draws are keyed by (seed, receptor id, step), so with the step restored by the checkpoint
// a restarted run continues bit for bit. Every rank holds the same state: nothing to gather.
#pragma once

#include "adhesion/bond.hpp"
#include "adhesion/grid_transfer.hpp"
#include "adhesion/kinetics.hpp"
#include "config/adhesion_config.hpp"
#include "config/body_config.hpp"
#include "core/rigid_motion.hpp"
#include "core/state_record.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace efsi::adhesion {

/// The receptors of one body: receptors()[begin, end).
struct BodyReceptors {
    std::size_t body = 0; ///< index in Config::bodies
    std::string name;
    std::size_t begin = 0, end = 0;
    real mass = 0;         ///< rho V of the initial shape [kg]
    real drag = 0;         ///< 6 pi mu a, a the radius of the sphere of equal volume [N s/m]
    std::size_t bonds = 0; ///< bonds now
    bool near = false;     ///< passed the skip test in the last advance
    std::size_t work = 0;  ///< first index of its receptors in the kinetics' working copy
    Real3 lo{}, hi{};      ///< bounding box of its receptors now [m]
};

struct CouplingStats {
    // add_bond_forces
    std::size_t bonds_spread = 0; ///< bonds whose forces went to the grid
    std::size_t face_writes = 0;  ///< face values written on this rank (work counter)
    real max_tension = 0;         ///< largest |sigma (l - lambda)| [N]
    Real3 force_on_bodies{};      ///< sum of the bonds' forces on the receptors [N]
    Real3 reaction_on_walls{};    ///< sum of -F taken by no-slip walls of the domain [N]
    Real3 reaction_on_held{};     ///< sum of -F spread onto pinned (held) solids [N]
    /// receptor_motion = rigid: the no-slip walls' push on bodies in contact with them (the
    /// normal part of the bonds' pull towards the wall they touch; support_on_walls) [N]. It
    /// is in force_on_bodies too, and minus it in reaction_on_walls.
    Real3 wall_support{};
    // advance
    std::size_t bodies_near = 0;    ///< bodies that got kinetics
    std::size_t bodies_skipped = 0; ///< bodies the skip test left alone
    StepStats kinetics;             ///< over the bodies that got kinetics
    /// Sum over the bodies of how far their receptors were lifted back onto a wall the
    /// rigid motion would have taken them through (carry_rigidly) [m].
    real wall_lift = 0;
};

/// The explicit-spring numbers of the coupling (docs/method.md, "Time-step limits").
struct SpringLimits {
    real kernel_mass = 0; ///< rho h^3 [kg]
    real kernel_drag = 0; ///< 6 pi mu h [N s/m]
    real h = 0;           ///< cell size [m]
    /// Mobility over one step of a body of mass m and drag z: min(dt / m, 1 / z) [m/(N s)].
    static real mobility(real dt, real m, real z) { return std::min(dt / m, 1 / z); }
    /// Largest dt with n sigma dt mobility(dt) <= 2: max(sqrt(2 m / k), 2 z / k), k = n sigma.
    static real stable_dt(real k, real m, real z);
};

/// What a ligand is anchored to (Coupling::anchor).
enum class LigandAnchor : std::uint8_t {
    domain_wall, ///< within half a cell of a no-slip wall of the domain: the boundary takes -F
    held_body,   ///< on a pinned solid: -F spread onto its held faces
    none         ///< not (yet) known to be on a wall: a bond to it stops the run
};

class Coupling {
  public:
    /// Places the receptors and ligands (nothing at all when !config.enabled). `bodies` are
    /// the case's [[body]] entries (for the receptors' initial surfaces), `density` and
    /// `viscosity` the fluid's (for the time-step limits). Keeps a reference to `dec`, which
    /// must outlive it.
    Coupling(const AdhesionConfig& config, const std::vector<BodyConfig>& bodies,
             const Decomposition& dec, real density, real viscosity);

    bool active() const { return active_; }

    /// Decides what each ligand is anchored to: a no-slip wall of the domain (bc type wall)
    /// within half a cell, else a pinned solid whose held faces (`pinning`, K = dt chi / tau
    /// on the faces, or null without pinned solids) carry at least min_held_share of its
    /// kernel. Throws InputError naming adhesion.ligand_regions[i] when one of its ligands
    /// is on neither. Collective. The constructor assumes every non-periodic boundary is a
    /// no-slip wall and leaves the other ligands `none`, until this is called.
    void anchor(const std::array<std::array<bool, 2>, 3>& no_slip, const VelocityField* pinning);
    LigandAnchor anchor_of(std::uint64_t ligand) const { return anchor_[ligand]; }
    static constexpr real min_held_share = 0.25;

    /// The largest dt the current bonds allow (infinity without bonds): the explicit spring
    /// limit of every body with bonds and of a single bond on its kernel. The time step
    /// control multiplies it by time.cfl like its other limits.
    real stable_time_step() const;

    /// Adds every bond's force (positions at the start of the step) to `force` [N/m^3]:
    /// +F at the receptor (receptor_motion = flow; rigid: summed into rigid_loads()); -F to the
    /// ligand's wall (nothing in `force` for a domain wall, the held faces of a pinned solid; see
    /// anchor). Throws RunError for a bond to a ligand anchored to nothing. Throws RunError naming
    /// the body (and its most loaded bond) when its bonds make the explicit springs unstable at
    /// this dt, or naming the bond (receptor, ligand, positions, force) when a bond's force would
    /// move its receptor more than max_step_displacement cells in one step.
    void add_bond_forces(VelocityField& force, real dt);

    /// With receptor_motion = rigid, add_bond_forces spreads no force at the receptors: the
    /// bonds' force and torque on each body are here instead, rigid_loads()[i] for bodies()[i]
    /// (zero without bonds), for the caller to spread over the body (bodies/rigid_fit.hpp).
    /// The reactions on the walls are as with flow-carried receptors. Empty otherwise.
    std::span<const RigidLoad> rigid_loads() const { return rigid_loads_; }

    /// One step's kinetics (bonds break and form, from the states at the start of the step,
    /// draws keyed by `step`), then the receptors moved (periodic directions wrapped): with
    /// receptor_motion = rigid, those of bodies()[i] with motions[i] (the rigid motion fitted
    /// to the flow over that body at the start of the step, bodies/rigid_fit.hpp); with
    /// receptor_motion = flow, each with `u` (the velocity the bodies moved with; halos
    /// filled) by the midpoint rule, and `motions` is not read. Throws RunError naming the
    /// receptor when one leaves the domain through a wall. Collective: every rank calls it.
    void advance(const VelocityField& u, real dt, std::uint64_t step,
                 std::span<const RigidMotion> motions = {});

    /// Whether advance needs the bodies' rigid motions (receptor_motion = rigid).
    bool moves_rigidly() const { return active_ && motion_ == ReceptorMotion::rigid; }

    std::span<const Receptor> receptors() const { return receptors_; }
    std::span<const BodyReceptors> bodies() const { return bodies_; }
    const LigandSet& ligands() const { return ligands_; }
    const CouplingStats& stats() const { return stats_; }
    std::size_t bond_count() const;
    const SpringLimits& limits() const { return limits_; }

    /// Carries the receptors with `u` only (no kinetics): the flow part of advance.
    void carry(const VelocityField& u, real dt);
    /// Moves the receptors of bodies()[i] with motions[i] only (no kinetics): the rigid part
    /// of advance. The motion's centre may be in any periodic image of the body. A cloud the
    /// motion takes through a no-slip wall of the domain is lifted back along the wall's
    /// normal until its farthest receptor is exactly on the wall (stats().wall_lift): the
    /// body is then in contact (see add_bond_forces and support_on_walls).
    void carry_rigidly(std::span<const RigidMotion> motions, real dt);

    /// Writes the state a restart needs into `r`: arrays receptor_id, receptor_x (x y z per
    /// receptor, in receptors() order) and receptor_ligand (no_ligand when free).
    void save(StateRecord& r) const;
    /// Takes back what save wrote, onto the receptors placed from the same case: InputError
    /// naming the array when a count or a receptor id differs, a position is not finite, or
    /// a ligand does not exist or is bound twice.
    void restore(const StateRecord& r);

  private:
    void anchor(const std::array<std::array<bool, 2>, 3>& no_slip, const VelocityField* pinning,
                bool strict);
    void kinetics(real dt, std::uint64_t step);
    void update_bounds(BodyReceptors& b);
    /// Contact (receptor_motion = rigid): a body with a receptor exactly on a no-slip wall
    /// (carry_rigidly put it there) and pulled towards it by its bonds is pushed back by the
    /// wall at that receptor with the normal part of the pull: a rigid body pressed on a rigid
    /// wall does not move into it, so the wall carries that part (stats().wall_support).
    void support_on_walls(const BodyReceptors& b, RigidLoad& load);
    /// Adds the force F acting at x to `load` (its moment about load.point, the lever arm by
    /// the minimum image).
    void add_to_load(RigidLoad& load, const Real3& x, const Real3& F) const;
    /// Stores the moved positions x_ (checked inside the walls) and wraps the clouds.
    void place_moved();
    /// Throws RunError naming the first receptor (index into receptors_) outside a wall.
    void check_inside(std::span<const Real3> at) const;
    std::string body_name_of(std::size_t k) const;
    /// x wrapped into the domain along the periodic directions.
    Real3 canonical(Real3 x) const;
    /// The periodic image of x nearest to `anchor`.
    Real3 image_near(Real3 x, const Real3& anchor) const;
    /// Is some ligand box within `d` of the box [lo, hi] or of one of its periodic images?
    bool may_reach(const Real3& lo, const Real3& hi, real d) const;
    /// Appends the receptors of b to work_ as the kinetics and the forces see them: a bound
    /// receptor at its image nearest its ligand, a free one wrapped into the domain.
    void copy_to_work(BodyReceptors& b);
    [[noreturn]] void report_unstable_body(const BodyReceptors& b, real dt, real number) const;

    bool active_ = false;
    const Decomposition* dec_ = nullptr;
    AdhesionParameters p_;
    real max_step_displacement_ = 0.5;
    ReceptorMotion motion_ = ReceptorMotion::flow;
    std::optional<Kinetics> kin_;
    LigandSet ligands_;
    std::vector<Receptor> receptors_;
    std::vector<BodyReceptors> bodies_;
    SpringLimits limits_;
    VelocityInterpolator interpolator_;
    HeldSpreader held_spreader_;
    const VelocityField* pinning_ = nullptr;
    std::vector<LigandAnchor> anchor_;
    std::array<std::array<bool, 2>, 3> no_slip_{}; ///< no-slip walls of the domain (anchor)
    std::vector<Real3> held_x_, held_f_;
    std::vector<Real3> x_, v_;
    std::vector<Receptor> work_;
    std::vector<Proposal> proposals_;
    std::vector<BondLoad> loads_;
    std::vector<RigidLoad> rigid_loads_;
    RigidLoad scratch_load_;
    CouplingStats stats_;
};

} // namespace efsi::adhesion
