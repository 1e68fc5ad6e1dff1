// Random placement of many cells without overlap in a region (a vessel's lumen), to a
// target volume fraction (haematocrit), reproducibly from a seed.
//
// Random sequential addition: candidates (a centre drawn uniformly in the region's bounding
// box and a uniformly random orientation) are accepted when the body, dilated by the gap,
// lies inside the region and overlaps no body placed before. Addition alone jams well below
// the haematocrit of blood (a large cell finds no hole once the free space is split into
// many small ones), so when `stall_candidates` candidates in a row fail, the placed bodies
// are shaken: Monte Carlo sweeps of small random displacements and rotations, each kept
// when the moved body passes the same test, which gather the free space into holes a cell
// fits in (the hard-body fluid samples its equilibrium, far from the jammed state); then
// addition resumes. Every random number is a counter-based hash of (seed, counter,
// purpose), so the scene depends on the seed only: the same on every rank and on any rank
// count, with no MPI involved.
//
// Overlap and containment are decided on a lattice of points inside each body (spacing
// `sample_spacing`, by default 1/12 of the smallest bounding radius): two bodies whose
// dilated shapes share a lattice point overlap. Features thinner than the spacing (a red
// cell's rim) can interpenetrate by less than a spacing, which the gap absorbs.
#pragma once

#include "core/types.hpp"
#include "interface/shapes.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace efsi {

/// One kind of body to place: its shape at a centre and orientation, its exact volume and
/// the radius of a sphere about its centre that contains it.
struct SeedKind {
    std::string name;
    real volume = 0;
    real bounding_radius = 0;
    std::function<std::unique_ptr<Shape>(const Real3& centre, const Matrix3& rotation)> make;
};

/// A body already in the scene (given by hand in the case) that the placed bodies keep
/// clear of, by the gap, exactly as they keep clear of each other. It never moves.
struct SeedObstacle {
    const Shape* shape = nullptr;
    Real3 centre{};
    real bounding_radius = 0; ///< of a sphere about `centre` that holds the shape
};

struct SeedingRequest {
    const Shape* region = nullptr; ///< bodies must lie inside (level < 0 at every sample)
    real region_volume = 0;        ///< for the achieved volume fraction
    Real3 box_lo{}, box_hi{};      ///< centres are drawn in this box (the region's bounds)
    std::vector<SeedKind> kinds;
    std::vector<SeedObstacle> obstacles; ///< bodies given by hand: kept clear of
    /// Placed first: kind k gets exactly counts[k] bodies (e.g. platelets), then kind
    /// `fill_kind` is added until its volume fraction reaches `target_fraction`.
    std::vector<int> counts;
    int fill_kind = 0;
    real target_fraction = 0; ///< of the region's volume, for fill_kind
    real gap = 0;             ///< clearance kept between bodies and to the region's edge
    std::uint64_t seed = 1;
    std::int64_t max_candidates = 200000; ///< candidate placements tried in all
    /// Shake sweeps (every body moved once each) that may be spent; 0: addition only.
    std::int64_t max_shake_sweeps = 2000;
    std::int64_t stall_candidates = 1000; ///< failed candidates in a row that call a shake
    int sweeps_per_stall = 10;            ///< sweeps of one shake
    real sample_spacing = 0;              ///< 0: 1/12 of the smallest bounding radius
};

struct SeededBody {
    int kind = 0;
    Real3 centre{};
    Matrix3 rotation{};
};

struct SeedingResult {
    std::vector<SeededBody> bodies;
    real achieved_fraction = 0; ///< volume of the fill kind / region volume
    bool reached = false;       ///< target fraction and every count reached
    std::int64_t candidates = 0;
    std::int64_t sweeps = 0; ///< shake sweeps spent
    std::string message;     ///< what was reached, and why not when not
};

/// Place the bodies. Throws InputError for an inconsistent request (before any work).
SeedingResult seed_bodies(const SeedingRequest& request);

/// Counter-based uniform random number in [0, 1): a hash of (seed, counter, stream).
real counter_uniform(std::uint64_t seed, std::uint64_t counter, std::uint64_t stream);

/// A uniformly distributed random rotation from three uniform numbers in [0, 1).
Matrix3 uniform_rotation(real u1, real u2, real u3);

} // namespace efsi
