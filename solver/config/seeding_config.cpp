#include "config/seeding_config.hpp"

#include "bodies/seeding.hpp"
#include "config/reader.hpp"
#include "core/error.hpp"
#include "interface/shapes.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

namespace efsi {

namespace {

/// Replace every occurrence of `from` in `s` by `to`.
std::string replace_all(std::string s, const std::string& from, const std::string& to) {
    for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
        s.replace(at, from.size(), to);
    return s;
}

/// The kinds a cell can be: a closed shape with a known volume.
bool seedable(BodyShape s) {
    return s == BodyShape::Sphere || s == BodyShape::Ellipsoid || s == BodyShape::Biconcave ||
           s == BodyShape::Box;
}

/// Radius of a sphere about the centre that holds the shape, in any orientation.
real bounding_radius(const BodyConfig& b) {
    switch (b.shape) {
    case BodyShape::Sphere:
        return b.radius;
    case BodyShape::Ellipsoid:
        return std::max({b.semi_axes[0], b.semi_axes[1], b.semi_axes[2]});
    case BodyShape::Biconcave:
        return b.radius; // the rim; the half-thickness is below 0.7 R0 (Evans-Fung)
    case BodyShape::Box:
        return std::hypot(b.half_sizes[0], b.half_sizes[1], b.half_sizes[2]);
    default:
        return 0;
    }
}

/// The shape of a cell of kind `b` at `centre` with orientation `rot` (the fast sign test
/// of the biconcave disc: the seeding only asks inside or not).
std::unique_ptr<Shape> cell_shape(const BodyConfig& b, const Real3& centre, const Matrix3& rot) {
    switch (b.shape) {
    case BodyShape::Sphere:
        return make_sphere(centre, b.radius);
    case BodyShape::Ellipsoid:
        return make_ellipsoid(centre, b.semi_axes, rot);
    case BodyShape::Biconcave: {
        EvansFungCoefficients k;
        k.r0 = b.radius;
        return make_biconcave_disc(centre, rot, k);
    }
    default:
        return make_box(centre, b.half_sizes, rot);
    }
}

toml::array toml_triple(const Real3& v) {
    return toml::array{v[0], v[1], v[2]};
}

/// One template: its seeding keys, its body keys as TOML, and those keys read and checked.
struct Template {
    std::string name;
    int count = 0;
    bool fill = false;
    toml::table body_toml;
    BodyConfig body;
};

/// Read and check the body keys of kind `i` as the [[body]] reader would, with errors
/// naming seeding.kind[i].body.
BodyConfig read_template_body(const toml::table& body, std::size_t i, const std::string& name,
                              const BodyConfig& vessel, const GlobalGrid& grid,
                              const std::array<bool, 3>& periodic, std::string_view unit) {
    const std::string at = fmt::format("seeding.kind[{}].body", i);
    for (const char* k : {"name", "centre", "axis", "angle"})
        if (body.contains(k))
            throw InputError(
                fmt::format("{}.{}: set by the seeding for every cell (remove it)", at, k));
    // Checked as one body at the lumen's centre (always inside the box).
    toml::table t = body;
    t.insert_or_assign("name", name);
    t.insert_or_assign("centre", toml_triple(vessel.centre));
    toml::table tmp;
    tmp.insert("body", toml::array{t});
    TableReader top(&tmp, "");
    try {
        std::vector<BodyConfig> one = read_bodies(top, grid, periodic, unit);
        check_shape_keys(one);
        return one.at(0);
    } catch (const InputError& e) {
        std::string m = replace_all(e.what(), "body[0]", at);
        m = replace_all(m, fmt::format("body '{}'", name), at);
        throw InputError(m);
    }
}

} // namespace

void rotation_axis_angle(const Matrix3& r, Real3& axis, real& angle) {
    // The unit quaternion (w, x, y, z) of r (Shepperd's branch on the largest component),
    // then angle = 2 atan2(|(x, y, z)|, w), axis = (x, y, z) / |(x, y, z)|.
    real w = 0, x = 0, y = 0, z = 0;
    const real tr = r[0][0] + r[1][1] + r[2][2];
    if (tr > 0) {
        const real s = 2 * std::sqrt(tr + 1);
        w = s / 4;
        x = (r[2][1] - r[1][2]) / s;
        y = (r[0][2] - r[2][0]) / s;
        z = (r[1][0] - r[0][1]) / s;
    } else if (r[0][0] > r[1][1] && r[0][0] > r[2][2]) {
        const real s = 2 * std::sqrt(1 + r[0][0] - r[1][1] - r[2][2]);
        w = (r[2][1] - r[1][2]) / s;
        x = s / 4;
        y = (r[0][1] + r[1][0]) / s;
        z = (r[0][2] + r[2][0]) / s;
    } else if (r[1][1] > r[2][2]) {
        const real s = 2 * std::sqrt(1 + r[1][1] - r[0][0] - r[2][2]);
        w = (r[0][2] - r[2][0]) / s;
        x = (r[0][1] + r[1][0]) / s;
        y = s / 4;
        z = (r[1][2] + r[2][1]) / s;
    } else {
        const real s = 2 * std::sqrt(1 + r[2][2] - r[0][0] - r[1][1]);
        w = (r[1][0] - r[0][1]) / s;
        x = (r[0][2] + r[2][0]) / s;
        y = (r[1][2] + r[2][1]) / s;
        z = s / 4;
    }
    if (w < 0) {
        w = -w;
        x = -x;
        y = -y;
        z = -z;
    }
    const real v = std::hypot(x, y, z);
    angle = 2 * std::atan2(v, w);
    axis = v > 0 ? Real3{x / v, y / v, z / v} : Real3{0, 0, 1};
}

SeedingReport expand_seeding(toml::table& root, TableReader& top, const GlobalGrid& grid,
                             const std::array<bool, 3>& periodic, std::vector<BodyConfig>& bodies,
                             std::string_view unit) {
    SeedingReport rep;
    const bool documenting = KeyCatalogue::instance().documenting;
    if (!documenting && !top.has("seeding")) return rep;
    TableReader r = top.sub("seeding", "cells placed at random without overlap in a vessel's "
                                       "lumen to a target haematocrit; expanded into [[body]] "
                                       "entries before anything is allocated (docs/method.md)");
    // Every key is read (type and range checked) before a missing required one is named, so
    // a wrong value is reported as itself and not as a missing neighbour.
    const auto required_string = documenting ? std::nullopt : std::optional<std::string>("");
    const auto required_number = documenting ? std::nullopt : std::optional<real>(0);
    const std::string region =
        r.string("region", std::string("vessel"), {"vessel", "domain"},
                 "where the cells go: vessel (the lumen of the tube named by seeding.vessel) "
                 "or domain (the whole box, kept the gap away from its faces: a channel "
                 "between walls)");
    const std::string vessel = r.string(
        "vessel", region == "domain" ? std::optional<std::string>("") : required_string, {},
        "name of the [[body]] of shape \"tube\" whose lumen the cells fill "
        "(region = vessel)");
    const real target = r.number("target_haematocrit", required_number, Range::closed(0, 0.9), "-",
                                 "target volume of the fill kind's cells / lumen volume");
    const int seed = r.integer("seed", 1, Range::closed(0, 2147483647),
                               "seed of every random draw (the same scene on any rank count)");
    real gap = r.number("gap", 0.0, Range::non_negative(), "m",
                        "clearance kept between cells and between a cell and the wall; 0: one "
                        "grid cell");
    const int max_candidates = r.integer("max_candidates", 200000, Range::closed(1, 1e9),
                                         "candidate placements tried before giving up");
    const int max_shake_sweeps =
        r.integer("max_shake_sweeps", 2000, Range::closed(0, 1e6),
                  "Monte Carlo sweeps (every cell moved once, by a small random step kept when "
                  "it overlaps nothing) that may be spent when random addition stalls, to "
                  "open space for more cells; 0: random sequential addition only");
    std::vector<Template> kinds;
    for (TableReader& k : r.tables("kind", "the kinds of cell: one [[seeding.kind]] each")) {
        Template t;
        t.name = k.string("name", required_string, {},
                          "the kind's name; its cells are the bodies <name>_0, <name>_1, ...");
        if (!documenting && !k.has("name"))
            throw InputError(k.full("name") + ": required key is missing (the kind's name)");
        t.count = k.integer("count", 0, Range::closed(0, 100000),
                            "number of cells of this kind (placed first; 0 with fill = true)");
        t.fill = k.boolean("fill", false,
                           "this kind fills the lumen to target_haematocrit (one kind at most)");
        k.sub("body", "the cells' body keys: every body[] key but name, centre, axis and angle");
        KeyCatalogue::instance().add({k.full("body") + ".*", "body[] keys", "-", "required", "-",
                                      "the [[body]] keys of every cell of the kind (kind, "
                                      "shape, size, physics); name, centre, axis and angle are "
                                      "set by the seeding"});
        k.finish();
        kinds.push_back(std::move(t));
    }
    r.finish();
    if (documenting) return rep;
    const bool in_domain = region == "domain";
    if (!r.has("target_haematocrit"))
        throw InputError("seeding.target_haematocrit: required key is missing");
    if (!in_domain && !r.has("vessel"))
        throw InputError("seeding.vessel: required key is missing (or region = \"domain\")");
    if (in_domain && r.has("vessel"))
        throw InputError(fmt::format("seeding.vessel = \"{}\": region = \"domain\" fills the "
                                     "whole box (remove the key, or set region = \"vessel\")",
                                     vessel));

    // The vessel and its lumen; for the domain, a stand-in at the box's centre (its centre
    // is where the templates are checked).
    const BodyConfig* tube = nullptr;
    BodyConfig domain_centre;
    for (int d = 0; d < 3; ++d)
        domain_centre.centre[d] = grid.origin[d] + 0.5 * grid.length[d];
    if (in_domain)
        tube = &domain_centre;
    else
        for (const BodyConfig& b : bodies)
            if (b.name == vessel) tube = &b;
    if (!tube || (!in_domain && tube->shape != BodyShape::Tube))
        throw InputError(
            fmt::format("seeding.vessel = \"{}\": {}", vessel,
                        tube ? "that body's shape is not \"tube\"" : "no [[body]] of that name"));
    if (kinds.empty()) throw InputError("seeding.kind: give at least one [[seeding.kind]]");
    if (gap == 0) gap = grid.dx(0);

    // The templates: seeding keys and body keys, checked.
    toml::table& seeding_toml = *root.get("seeding")->as_table();
    toml::array& kind_toml = *seeding_toml.get("kind")->as_array();
    int fill = -1;
    std::set<std::string> names;
    for (const BodyConfig& b : bodies)
        names.insert(b.name);
    for (std::size_t i = 0; i < kinds.size(); ++i) {
        Template& t = kinds[i];
        const std::string at = fmt::format("seeding.kind[{}]", i);
        const toml::node* body = kind_toml[i].as_table()->get("body");
        if (!body || !body->is_table())
            throw InputError(at + ".body: required table is missing (the cells' body keys)");
        t.body_toml = *body->as_table();
        t.body = read_template_body(t.body_toml, i, t.name, *tube, grid, periodic, unit);
        if (!seedable(t.body.shape))
            throw InputError(fmt::format("{}.body.shape = \"{}\": a cell must be a sphere, "
                                         "ellipsoid, biconcave disc or box",
                                         at, keyword(t.body.shape)));
        if (t.body.pinned) throw InputError(at + ".body.pinned: a seeded cell cannot be pinned");
        if (t.fill) {
            if (fill >= 0)
                throw InputError(
                    fmt::format("{}.fill: kind[{}] already fills the lumen", at, fill));
            if (t.count != 0)
                throw InputError(at + ".count: a fill kind's count follows from the target");
            fill = int(i);
        }
        for (std::size_t j = 0; j < i; ++j)
            if (kinds[j].name == t.name)
                throw InputError(fmt::format("{}.name = \"{}\": used twice", at, t.name));
    }
    if (target > 0 && fill < 0)
        throw InputError("seeding.target_haematocrit > 0: no [[seeding.kind]] has fill = true");

    // The request: the lumen of the tube, centres drawn so no cell crosses the box ends
    // along x (the seeding does not wrap its overlap test around the periodic direction);
    // or the whole box, every face kept the gap away (walls, and periodic ends likewise).
    const real radius = 0.5 * tube->lumen_diameter;
    const Real3 half{0.5 * grid.length[0], 0.5 * grid.length[1], 0.5 * grid.length[2]};
    const auto lumen = in_domain
                           ? make_box(tube->centre, half, identity_rotation())
                           : make_cylinder(tube->centre, radius,
                                           axis_angle_rotation({0, 1, 0}, std::numbers::pi / 2));
    SeedingRequest q;
    q.region = lumen.get();
    q.region_volume = in_domain ? grid.length[0] * grid.length[1] * grid.length[2]
                                : std::numbers::pi * radius * radius * grid.length[0];
    real reach = 0;
    for (const Template& t : kinds) {
        SeedKind k;
        k.name = t.name;
        const BodyConfig b = t.body;
        k.volume = cell_shape(b, {0, 0, 0}, identity_rotation())->exact_volume();
        k.bounding_radius = bounding_radius(b) * (1 + 1e-3);
        k.make = [b](const Real3& x, const Matrix3& rot) { return cell_shape(b, x, rot); };
        reach = std::max(reach, k.bounding_radius);
        q.kinds.push_back(std::move(k));
        q.counts.push_back(t.count);
    }
    q.box_lo = {grid.origin[0] + reach + gap, tube->centre[1] - radius, tube->centre[2] - radius};
    q.box_hi = {grid.origin[0] + grid.length[0] - reach - gap, tube->centre[1] + radius,
                tube->centre[2] + radius};
    if (in_domain)
        for (int d = 0; d < 3; ++d) {
            q.box_lo[d] = grid.origin[d] + reach + gap;
            q.box_hi[d] = grid.origin[d] + grid.length[d] - reach - gap;
        }
    for (int d = 0; d < (in_domain ? 3 : 1); ++d)
        if (!(q.box_hi[d] > q.box_lo[d]))
            throw InputError(fmt::format("seeding: the box is {:.4g} {} long in {}, too short for "
                                         "a cell of {:.4g} {} across plus the gap at both ends",
                                         grid.length[d], unit, "xyz"[d], 2 * reach, unit));
    q.fill_kind = std::max(fill, 0);
    q.target_fraction = target;
    q.gap = gap;
    q.seed = std::uint64_t(seed);
    q.max_candidates = max_candidates;
    q.max_shake_sweeps = max_shake_sweeps;
    // The bodies given by hand besides the vessel: the cells keep clear of them by the gap.
    std::vector<std::unique_ptr<Shape>> by_hand;
    for (const BodyConfig& b : bodies) {
        if (b.name == vessel) continue;
        if (!seedable(b.shape))
            throw InputError(fmt::format("seeding: the body '{}' (shape \"{}\") is in the scene "
                                         "with the seeded cells, which keep clear only of closed "
                                         "shapes (sphere, ellipsoid, biconcave disc, box)",
                                         b.name, keyword(b.shape)));
        by_hand.push_back(cell_shape(b, b.centre, axis_angle_rotation(b.axis, b.angle)));
        q.obstacles.push_back({by_hand.back().get(), b.centre, bounding_radius(b) * (1 + 1e-3)});
    }
    const SeedingResult res = seed_bodies(q);

    rep.used = true;
    rep.seed = q.seed;
    rep.vessel = in_domain ? std::string("(the domain)") : vessel;
    rep.fill_kind = fill >= 0 ? kinds[fill].name : "";
    rep.target = target;
    rep.achieved = fill >= 0 ? res.achieved_fraction : 0;
    rep.lumen_volume = q.region_volume;
    rep.gap = gap;
    rep.candidates = res.candidates;
    rep.shake_sweeps = res.sweeps;
    rep.message = "seeding: " + res.message;
    if (!res.reached)
        throw InputError(fmt::format("seeding.target_haematocrit = {}: {}", target, res.message));

    // The cells as bodies, named <kind>_<n>, with their centre and orientation.
    toml::node* body_node = root.get("body");
    if (!body_node) {
        root.insert("body", toml::array{});
        body_node = root.get("body");
    }
    toml::array& body_array = *body_node->as_array();
    std::vector<int> n(kinds.size(), 0);
    for (const SeededBody& s : res.bodies) {
        const Template& t = kinds[s.kind];
        BodyConfig b = t.body;
        b.name = fmt::format("{}_{}", t.name, n[s.kind]++);
        if (!names.insert(b.name).second)
            throw InputError(fmt::format("seeding.kind[{}].name = \"{}\": the body '{}' exists "
                                         "already",
                                         s.kind, t.name, b.name));
        b.centre = s.centre;
        rotation_axis_angle(s.rotation, b.axis, b.angle);
        toml::table tt = t.body_toml;
        tt.insert_or_assign("name", b.name);
        tt.insert_or_assign("centre", toml_triple(b.centre));
        tt.insert_or_assign("axis", toml_triple(b.axis));
        tt.insert_or_assign("angle", b.angle);
        body_array.push_back(std::move(tt));
        bodies.push_back(std::move(b));
    }
    for (std::size_t k = 0; k < kinds.size(); ++k)
        rep.placed.emplace_back(kinds[k].name, n[k]);
    root.erase("seeding");
    return rep;
}

} // namespace efsi
