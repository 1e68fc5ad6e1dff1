#include "config/adhesion_config.hpp"

#include "config/reader.hpp"
#include "core/error.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace efsi {

namespace {

/// Receptors are replicated on every rank (the coupling's choice, docs/method.md): a cap
/// that keeps them a small share of memory and of a step.
constexpr std::uint64_t max_receptors = 1'000'000;
constexpr std::uint64_t max_ligand_sites = 50'000'000;

adhesion::AdhesionParameters read_parameters(TableReader& r) {
    adhesion::AdhesionParameters p;
    const adhesion::AdhesionParameters d;
    const Range nn = Range::non_negative(), pos = Range::positive();
    p.k_on = r.number("k_on", d.k_on, nn, "1/s",
                      "forward rate of a free receptor with a free ligand within reach (model "
                      "choice, docs/method.md)");
    p.k_off0 = r.number("k_off0", d.k_off0, nn, "1/s",
                        "unstressed GPIb-alpha / vWF-A1 off-rate (Doggett et al. 2002)");
    p.reactive_compliance = r.number("reactive_compliance", d.reactive_compliance, nn, "m",
                                     "Bell's gamma: k_off = k_off0 exp(gamma F / kB T)");
    p.bond_stiffness =
        r.number("bond_stiffness", d.bond_stiffness, nn, "N/m", "bond spring constant sigma");
    p.bond_rest_length =
        r.number("bond_rest_length", d.bond_rest_length, nn, "m", "bond rest length lambda");
    p.reactive_distance = r.number("reactive_distance", d.reactive_distance, pos, "m",
                                   "a free receptor binds a free ligand at most this far away");
    p.margin = r.number("margin", d.margin, nn, "m",
                        "slack of the skip test: bodies and receptors farther than "
                        "reactive_distance + margin from every ligand region get no work");
    p.temperature = r.number("temperature", d.temperature, pos, "K", "absolute temperature");
    const std::string law = r.string("law", "bell", {"bell", "catch_slip"},
                                     "force dependence of k_off: bell, or the two-pathway "
                                     "catch_slip law (needs the four catch/slip keys)");
    p.law = law == "catch_slip" ? adhesion::DissociationLaw::catch_slip
                                : adhesion::DissociationLaw::bell;
    p.catch_rate = r.number("catch_rate", 0.0, nn, "1/s", "catch_slip: catch-pathway rate");
    p.catch_distance =
        r.number("catch_distance", 0.0, nn, "m", "catch_slip: catch-pathway distance");
    p.slip_rate = r.number("slip_rate", 0.0, nn, "1/s", "catch_slip: slip-pathway rate");
    p.slip_distance = r.number("slip_distance", 0.0, nn, "m", "catch_slip: slip-pathway distance");
    return p;
}

} // namespace

adhesion::SurfaceEllipsoid receptor_surface(const BodyConfig& b) {
    adhesion::SurfaceEllipsoid s;
    s.centre = b.centre;
    if (b.shape == BodyShape::Sphere) {
        s.semi_axes = {b.radius, b.radius, b.radius};
    } else if (b.shape == BodyShape::Ellipsoid) {
        s.semi_axes = b.semi_axes;
        if (b.angle != 0) s.rotation = axis_angle_rotation(b.axis, b.angle);
    } else {
        throw InputError(fmt::format("body '{}': receptors need a sphere or an ellipsoid, not "
                                     "shape '{}'",
                                     b.name, keyword(b.shape)));
    }
    return s;
}

AdhesionConfig read_adhesion(TableReader& top, const GlobalGrid& grid,
                             const std::vector<BodyConfig>& bodies, bool check_receptor_bodies) {
    const bool documenting = KeyCatalogue::instance().documenting;
    AdhesionConfig a;
    a.enabled = top.has("adhesion");
    if (!a.enabled && !documenting) return a; // nothing read, nothing allocated
    TableReader r = top.sub("adhesion", "platelet adhesion: GPIb-alpha / vWF bonds by kinetic "
                                        "Monte Carlo, coupled to the flow (docs/method.md)");
    a.parameters = read_parameters(r);
    a.seed = static_cast<std::uint64_t>(
        r.integer("seed", 1, Range::closed(0, std::numeric_limits<int>::max()),
                  "seed of every random draw (placement and kinetics; the same run on any "
                  "rank count)"));
    a.max_step_displacement =
        r.number("max_step_displacement", 0.5, Range{0, 1, true}, "cells",
                 "a bond whose force would move its receptor farther than this in one step stops "
                 "the run (the per-bond force limit, docs/method.md)");
    a.receptor_motion =
        r.string(
            "receptor_motion", "flow", {"flow", "rigid"},
            "how the receptors move: \"flow\" each with the flow interpolated at its "
            "position (they follow the body as it deforms, and slide over its surface); "
            "\"rigid\" with the rigid motion fitted to the flow over their body, whose "
            "bonds then load it as a rigid body, with contact on the walls (docs/method.md)") ==
                "rigid"
            ? ReceptorMotion::rigid
            : ReceptorMotion::flow;
    for (TableReader& t : r.tables(
             "ligand_regions", "vWF ligands on a wall box (a patch on a wall is a box of zero "
                               "thickness): within half a cell of a no-slip wall of the "
                               "domain, or on a pinned solid, which take the bonds' reaction")) {
        adhesion::LigandRegion region;
        region.lo = t.vector3("lo", std::nullopt, Range{}, "m", "low corner of the box");
        region.hi = t.vector3("hi", std::nullopt, Range{}, "m", "high corner of the box");
        const real density = t.number("density", std::nullopt, Range::positive(), "1/m^2",
                                      "ligand sites per wall area (a square lattice of spacing "
                                      "1/sqrt(density))");
        t.finish();
        region.spacing = 1 / std::sqrt(density);
        a.ligand_regions.push_back(region);
        a.ligand_density.push_back(density);
    }
    std::vector<TableReader> groups =
        r.tables("receptors", "GPIb-alpha receptors on a body's initial surface");
    for (TableReader& t : groups) {
        ReceptorGroupConfig g;
        g.body = t.string("body", std::nullopt, {},
                          "name of the [[body]] (kind = \"solid\", a sphere or an ellipsoid)");
        const int count = t.integer("count", 0, Range::closed(0, max_receptors),
                                    "number of receptors (or give density)");
        g.density = t.number("density", 0.0, Range::non_negative(), "1/m^2",
                             "receptors per surface area of the initial shape (or give count)");
        t.finish();
        g.count = static_cast<std::uint64_t>(count);
        a.receptors.push_back(g);
    }
    r.finish();
    if (documenting) return a;

    // ---- checks, before anything is allocated ----
    if (grid.dim != 3)
        throw InputError("adhesion: needs a 3D grid (grid.cells[2] > 1): receptors sit on a "
                         "body's surface in 3D");
    a.parameters.validate();
    const Real3 dlo = grid.origin;
    const Real3 dhi{grid.origin[0] + grid.length[0], grid.origin[1] + grid.length[1],
                    grid.origin[2] + grid.length[2]};
    std::uint64_t sites = 0;
    for (std::size_t i = 0; i < a.ligand_regions.size(); ++i) {
        const std::string key = fmt::format("adhesion.ligand_regions[{}]", i);
        const adhesion::LigandRegion& reg = a.ligand_regions[i];
        // Site count first, so that a huge density is named as such.
        real n = 1;
        for (int d = 0; d < 3; ++d)
            n *= std::max(real(1), std::round((reg.hi[d] - reg.lo[d]) / reg.spacing));
        if (!(n <= static_cast<real>(max_ligand_sites)) ||
            (sites += static_cast<std::uint64_t>(n)) > max_ligand_sites)
            throw InputError(fmt::format("{}.density = {:g} /m^2: the regions would hold more than "
                                         "{} ligand sites",
                                         key, a.ligand_density[i], max_ligand_sites));
    }
    adhesion::validate_ligand_regions(a.ligand_regions, dlo, dhi, max_ligand_sites);

    std::uint64_t total = 0;
    for (std::size_t i = 0; check_receptor_bodies && i < a.receptors.size(); ++i) {
        ReceptorGroupConfig& g = a.receptors[i];
        const std::string key = fmt::format("adhesion.receptors[{}]", i);
        const auto it = std::find_if(bodies.begin(), bodies.end(),
                                     [&](const BodyConfig& b) { return b.name == g.body; });
        if (it == bodies.end())
            throw InputError(
                fmt::format("{}.body = \"{}\": there is no [[body]] of that name", key, g.body));
        const BodyConfig& b = *it;
        g.body_index = static_cast<std::size_t>(it - bodies.begin());
        if (b.kind != BodyKind::Solid || b.pinned)
            throw InputError(fmt::format(
                "{}.body = \"{}\": receptors go on a platelet, a free [[body]] of kind = "
                "\"solid\"; this body is {}",
                key, g.body,
                b.pinned ? std::string("a pinned solid (a wall)")
                         : "of kind \"" + std::string(keyword(b.kind)) + "\""));
        if (b.shape != BodyShape::Sphere && b.shape != BodyShape::Ellipsoid)
            throw InputError(fmt::format("{}.body = \"{}\": receptors are placed on a sphere or "
                                         "an ellipsoid (a platelet), not on shape '{}'",
                                         key, g.body, keyword(b.shape)));
        for (std::size_t j = 0; j < i; ++j)
            if (a.receptors[j].body == g.body)
                throw InputError(fmt::format("{}.body = \"{}\": the body already has receptors "
                                             "(adhesion.receptors[{}])",
                                             key, g.body, j));
        if ((g.count > 0) == (g.density > 0))
            throw InputError(fmt::format("{}: give exactly one of count (receptors) and density "
                                         "(receptors per m^2)",
                                         key));
        const adhesion::SurfaceEllipsoid s = receptor_surface(b);
        if (g.density > 0) {
            const real n = std::round(g.density * adhesion::ellipsoid_area(s.semi_axes));
            if (!(n >= 1) || n > static_cast<real>(max_receptors))
                throw InputError(fmt::format("{}.density = {:g} /m^2: gives {:g} receptors on "
                                             "the body's surface; need 1 to {}",
                                             key, g.density, n, max_receptors));
            g.count = static_cast<std::uint64_t>(n);
        }
        total += g.count;
        if (total > max_receptors)
            throw InputError(fmt::format("{}: more than {} receptors in all (they are held on "
                                         "every rank)",
                                         key, max_receptors));
    }
    return a;
}

std::string adhesion_fingerprint(const AdhesionConfig& a) {
    if (!a.enabled) return "";
    // One line per key, so that a checkpoint refused for another case names the key.
    const adhesion::AdhesionParameters& p = a.parameters;
    std::string out;
    auto line = [&](const std::string& key, const std::string& value) {
        out += "adhesion." + key + " = " + value + "\n";
    };
    auto num = [](real x) { return fmt::format("{:.17g}", x); };
    line("seed", std::to_string(a.seed));
    line("k_on", num(p.k_on));
    line("k_off0", num(p.k_off0));
    line("reactive_compliance", num(p.reactive_compliance));
    line("bond_stiffness", num(p.bond_stiffness));
    line("bond_rest_length", num(p.bond_rest_length));
    line("reactive_distance", num(p.reactive_distance));
    line("margin", num(p.margin));
    line("temperature", num(p.temperature));
    line("law", p.law == adhesion::DissociationLaw::bell ? "bell" : "catch_slip");
    line("catch_slip", fmt::format("catch_rate {:.17g} catch_distance {:.17g} slip_rate {:.17g} "
                                   "slip_distance {:.17g}",
                                   p.catch_rate, p.catch_distance, p.slip_rate, p.slip_distance));
    line("max_step_displacement", num(a.max_step_displacement));
    // Only when not the default, so that checkpoints from before the key keep their fingerprint.
    if (a.receptor_motion == ReceptorMotion::rigid) line("receptor_motion", "rigid");
    line("ligand_regions.count", std::to_string(a.ligand_regions.size()));
    for (std::size_t i = 0; i < a.ligand_regions.size(); ++i) {
        const adhesion::LigandRegion& r = a.ligand_regions[i];
        line(fmt::format("ligand_regions[{}]", i),
             fmt::format("lo [{:.17g}, {:.17g}, {:.17g}] hi [{:.17g}, {:.17g}, {:.17g}] density "
                         "{:.17g}",
                         r.lo[0], r.lo[1], r.lo[2], r.hi[0], r.hi[1], r.hi[2],
                         a.ligand_density[i]));
    }
    line("receptors.count", std::to_string(a.receptors.size()));
    for (std::size_t i = 0; i < a.receptors.size(); ++i) {
        line(fmt::format("receptors[{}].body", i), a.receptors[i].body);
        line(fmt::format("receptors[{}].count", i), std::to_string(a.receptors[i].count));
    }
    return out;
}

} // namespace efsi
