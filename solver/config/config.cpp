#include "config/config.hpp"

#include "config/reader.hpp"
#include "core/error.hpp"
#include "io/voxel_mask.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace efsi {

std::string to_string(ViscousScheme s) {
    switch (s) {
    case ViscousScheme::Explicit:
        return "explicit";
    case ViscousScheme::CrankNicolson:
        return "crank_nicolson";
    case ViscousScheme::BackwardEuler:
        return "backward_euler";
    }
    return "?";
}

std::string case_fingerprint(const Config& c) {
    std::string out;
    auto line = [&](const std::string& key, const std::string& value) {
        out += key + " = " + value + "\n";
    };
    auto r3 = [](const Real3& v) {
        return fmt::format("[{:.17g}, {:.17g}, {:.17g}]", v[0], v[1], v[2]);
    };
    line("grid.cells",
         fmt::format("[{}, {}, {}]", c.grid.cells[0], c.grid.cells[1], c.grid.cells[2]));
    line("grid.length", r3(c.grid.length));
    line("grid.origin", r3(c.grid.origin));
    const char* faces[3][2] = {{"x_low", "x_high"}, {"y_low", "y_high"}, {"z_low", "z_high"}};
    for (int d = 0; d < 3; ++d)
        for (int side = 0; side < 2; ++side) {
            const FaceBoundary& f = c.boundaries[d][side];
            const char* type = f.type == BoundaryType::Periodic ? "periodic"
                               : f.type == BoundaryType::Wall   ? "wall"
                                                                : "free_slip";
            line(
                std::string("boundary.") + faces[d][side],
                fmt::format("{} velocity {} frequency {:.17g}", type, r3(f.velocity), f.frequency) +
                    (std::isfinite(f.stop_time) ? fmt::format(" stop_time {:.17g}", f.stop_time)
                                                : std::string()));
        }
    line("fluid.density", fmt::format("{:.17g}", c.fluid.density));
    line("fluid.viscosity", fmt::format("{:.17g}", c.fluid.viscosity));
    line("forcing.body_force", r3(c.body_force));
    line("initial", fmt::format("{} amplitude {:.17g} velocity {}", c.initial.type,
                                c.initial.amplitude, r3(c.initial.velocity)));
    line("body.count", std::to_string(c.bodies.size()));
    for (std::size_t k = 0; k < c.bodies.size(); ++k) {
        const BodyConfig& b = c.bodies[k];
        const std::string at = fmt::format("body[{}]", k);
        line(at + ".name", b.name);
        line(at + ".kind", fmt::format("{} pinned {} pin_tau_over_dt {:.17g}", keyword(b.kind),
                                       b.pinned, b.pin_tau_over_dt));
        line(at + ".shape",
             fmt::format("{} centre {} radius {:.17g} semi_axes {} half_sizes {} normal {} "
                         "thickness {:.17g} axis {} angle {:.17g} mask {}:{}{}",
                         keyword(b.shape), r3(b.centre), b.radius, r3(b.semi_axes),
                         r3(b.half_sizes), r3(b.normal), b.thickness, r3(b.axis), b.angle,
                         b.mask_file, b.mask_dataset,
                         b.shape == BodyShape::Tube
                             ? fmt::format(" lumen_diameter {:.17g}", b.lumen_diameter)
                             : ""));
        line(at + ".interface",
             fmt::format("{} smoothing_width {:.17g} subsamples {} margin {}", keyword(b.interface),
                         b.smoothing_width, b.subsamples, b.margin));
        line(at + ".solid", fmt::format("shear_modulus {:.17g} solid_viscosity {:.17g} "
                                        "extension_threshold {:.17g}",
                                        b.shear_modulus, b.solid_viscosity, b.extension_threshold));
        line(at + ".membrane",
             fmt::format("{} elastic_modulus {:.17g} area_dilation {:.17g} bending_modulus "
                         "{:.17g} strain_velocity {} surface_velocity_reach {:.17g}",
                         keyword(b.law), b.elastic_modulus, b.area_dilation, b.bending_modulus,
                         keyword(b.strain_velocity), b.surface_velocity_reach));
    }
    if (c.contact.stiffness > 0)
        line("contact.stiffness", fmt::format("{:.17g}", c.contact.stiffness));
    out += adhesion_fingerprint(c.adhesion);
    return out;
}

namespace {

/// Apply one `a.b.c=value` override; the value is parsed as TOML (number, string in
/// quotes, array, bool), falling back to a bare string.
void apply_override(toml::table& root, const std::string& path, const std::string& value) {
    if (path.empty()) throw InputError("--set: empty key");
    toml::table* t = &root;
    std::size_t start = 0;
    for (;;) {
        const std::size_t dot = path.find('.', start);
        const std::string part = path.substr(start, dot - start);
        if (part.empty()) throw InputError(fmt::format("--set {}: malformed key", path));
        if (dot == std::string::npos) {
            // A value that is not one TOML value (a bare word, or text with quotes or
            // newlines that would not parse) is taken as the string itself.
            toml::table parsed;
            bool ok = value.find_first_of("\n\r") == std::string::npos;
            if (ok) {
                try {
                    parsed = toml::parse("v = " + value);
                    ok = parsed.size() == 1 && parsed.contains("v");
                } catch (const toml::parse_error&) {
                    ok = false;
                }
            }
            if (ok)
                t->insert_or_assign(part, *parsed.get("v"));
            else
                t->insert_or_assign(part, value);
            return;
        }
        // `name[i]` selects entry i of an array of tables ([[name]] sections).
        toml::node* n = nullptr;
        if (const auto br = part.find('['); br != std::string::npos && part.back() == ']') {
            const std::string name = part.substr(0, br);
            const std::string digits = part.substr(br + 1, part.size() - br - 2);
            if (name.empty() || digits.empty() || digits.size() > 6 ||
                digits.find_first_not_of("0123456789") != std::string::npos)
                throw InputError(fmt::format("--set {}: '{}' needs an entry number, e.g. "
                                             "body[0] (got '[{}]')",
                                             path, part, digits));
            const std::size_t index = std::stoul(digits);
            toml::array* a = t->get(name) ? t->get(name)->as_array() : nullptr;
            if (!a || index >= a->size() || !(*a)[index].is_table())
                throw InputError(
                    fmt::format("--set {}: there is no [[{}]] entry {}", path, name, index));
            n = &(*a)[index];
        } else {
            n = t->get(part);
            if (!n) {
                t->insert(part, toml::table{});
                n = t->get(part);
            }
        }
        if (!n->is_table())
            throw InputError(fmt::format("--set {}: '{}' is not a table", path, part));
        t = n->as_table();
        start = dot + 1;
    }
}

LinearSolverSettings read_solver(TableReader r, real tol, int iters) {
    LinearSolverSettings s;
    s.method =
        r.string("method", "auto", {"auto", "fft", "pcg_pfmg", "gmres_pfmg", "pcg_smg", "pfmg"},
                 "auto: the direct FFT solve where the coefficients are constant, else "
                 "pcg_pfmg; fft: always the FFT solve (an error where it cannot apply); "
                 "or a hypre Struct solver (Krylov method and multigrid preconditioner)");
    s.tolerance = r.number("tolerance", tol, Range::positive(), "-",
                           "relative residual at which the solve stops");
    s.max_iterations = r.integer("max_iterations", iters, Range::closed(1, 1e6),
                                 "iteration cap; hitting it is reported in the diagnostics");
    r.finish();
    return s;
}

FaceBoundary read_face(TableReader& parent, const std::string& key) {
    static const std::vector<std::string> types{"periodic", "wall", "free_slip"};
    FaceBoundary f;
    TableReader sub = parent.sub(
        key, "boundary condition of this box face: a table {type, velocity} or a bare string");
    const std::string type = sub.string("type", "periodic", types,
                                        "periodic, wall (no-slip, possibly moving) or free_slip");
    const Real3 velocity =
        sub.vector3("velocity", Real3{0, 0, 0}, Range{}, "m/s",
                    "wall velocity (tangential components only), for type = wall");
    const real frequency = sub.number("frequency", 0.0, Range::non_negative(), "rad/s",
                                      "wall: oscillate as velocity * sin(frequency t); 0 = steady");
    const real stop_time =
        sub.number("stop_time", 0.0, Range::non_negative(), "s",
                   "wall: stands still (velocity 0) from this time on, e.g. to let a sheared "
                   "body relax; 0 = never stops");
    sub.finish();
    f.frequency = frequency;
    if (stop_time > 0) {
        if (type != "wall")
            throw InputError(fmt::format("{} = {:g}: only a wall stops (the face is {})",
                                         sub.full("stop_time"), stop_time, type));
        f.stop_time = stop_time;
    }
    f.type = type == "periodic" ? BoundaryType::Periodic
             : type == "wall"   ? BoundaryType::Wall
                                : BoundaryType::FreeSlip;
    f.velocity = velocity;
    return f;
}

/// Turn `x_low = "wall"` into `x_low = {type = "wall"}` so one reader handles both.
void normalise_boundaries(toml::table& root) {
    toml::node* b = root.get("boundary");
    if (!b || !b->is_table()) return;
    toml::table& t = *b->as_table();
    std::vector<std::string> bare;
    for (auto&& [k, v] : t)
        if (v.is_string()) bare.emplace_back(k.str());
    for (const auto& k : bare) {
        toml::table face;
        face.insert("type", *t.get(k)->value<std::string>());
        t.insert_or_assign(k, std::move(face));
    }
}

Config read_config(toml::table& root, const std::filesystem::path& case_dir) {
    Config c;
    c.case_dir = case_dir;
    normalise_boundaries(root);
    TableReader top(&root, "");

    {
        TableReader r = top.sub("case", "name and description of the case");
        c.name = r.string("name", case_dir.filename().string(), {}, "case name (for logs)");
        c.description = r.string("description", "", {}, "one line on the physics");
        c.length_unit = r.string("length_unit", "m", {},
                                 "label of the case's length unit in the log (the solver is "
                                 "unit-agnostic: a case in um sets \"um\"; nothing is converted)");
        c.time_unit = r.string("time_unit", "s", {},
                               "label of the case's time unit in the log (a case in ms sets "
                               "\"ms\")");
        r.finish();
        for (const auto& [key, v] :
             {std::pair{"length_unit", &c.length_unit}, std::pair{"time_unit", &c.time_unit}})
            if (!KeyCatalogue::instance().documenting &&
                (v->empty() || v->size() > 16 || std::any_of(v->begin(), v->end(), [](char ch) {
                     return static_cast<unsigned char>(ch) < 32;
                 })))
                throw InputError(fmt::format("case.{} = \"{}\": a label of 1 to 16 printable "
                                             "characters",
                                             key, *v));
        // The name is the default output folder out/<name>: it must stay inside out/.
        if (!KeyCatalogue::instance().documenting &&
            (c.name.empty() || c.name.size() > 128 || c.name[0] == '.' ||
             c.name.find_first_of("/\\") != std::string::npos ||
             std::any_of(c.name.begin(), c.name.end(),
                         [](char ch) { return static_cast<unsigned char>(ch) < 32; })))
            throw InputError(fmt::format("case.name = \"{}\": a name of 1 to 128 characters, "
                                         "without / or \\, not starting with '.' (it is the "
                                         "default output folder out/<name>)",
                                         c.name));
    }
    {
        TableReader r = top.sub("grid", "the uniform Cartesian grid");
        c.grid.cells = r.ivector3("cells", std::nullopt, Range::closed(1, 1 << 20),
                                  "cells per direction; nz = 1 makes a 2D run");
        c.grid.length = r.vector3("length", std::nullopt, Range::positive(), "m", "box size");
        c.grid.origin = r.vector3("origin", Real3{0, 0, 0}, Range{}, "m", "low corner of the box");
        r.finish();
        c.grid.dim = c.grid.cells[2] == 1 ? 2 : 3;
        for (int d = 0; d < c.grid.dim; ++d)
            if (c.grid.cells[d] < 2 && !KeyCatalogue::instance().documenting)
                throw InputError(
                    fmt::format("grid.cells[{}] = {}: need at least 2 cells", d, c.grid.cells[d]));
        // Cells must be cubes (the membrane and VOF geometry assume it); allow 1e-9 slack.
        const real h = c.grid.dx(0);
        for (int d = 1; d < c.grid.dim; ++d)
            if (std::abs(c.grid.dx(d) - h) > 1e-9 * h && !KeyCatalogue::instance().documenting)
                throw InputError(fmt::format(
                    "grid: cells must be cubes, but dx = {} and d{} = {} (length / cells)", h,
                    "xyz"[d], c.grid.dx(d)));
    }
    {
        TableReader r = top.sub("fluid", "fluid properties");
        c.fluid.density = r.number("density", std::nullopt, Range::positive(), "kg/m^3",
                                   "density rho (one density everywhere)");
        c.fluid.viscosity = r.number("viscosity", std::nullopt, Range::positive(), "Pa s",
                                     "dynamic viscosity mu_f of the fluid");
        r.finish();
    }
    {
        TableReader r = top.sub("boundary", "boundary condition per box face");
        const char* names[3][2] = {{"x_low", "x_high"}, {"y_low", "y_high"}, {"z_low", "z_high"}};
        for (int d = 0; d < 3; ++d)
            for (int s = 0; s < 2; ++s)
                c.boundaries[d][s] = read_face(r, names[d][s]);
        r.finish();
        for (int d = 0; d < 3; ++d) {
            const bool p0 = c.boundaries[d][0].type == BoundaryType::Periodic;
            const bool p1 = c.boundaries[d][1].type == BoundaryType::Periodic;
            if (p0 != p1)
                throw InputError(fmt::format("boundary.{} / boundary.{}: periodic must be set "
                                             "on both faces of a direction",
                                             names[d][0], names[d][1]));
            for (int s = 0; s < 2; ++s)
                if (c.boundaries[d][s].velocity[d] != 0)
                    throw InputError(fmt::format(
                        "boundary.{}.velocity: a wall cannot move along its normal ({}-component "
                        "must be 0)",
                        names[d][s], "xyz"[d]));
        }
        if (c.grid.dim == 2 && c.boundaries[2][0].type != BoundaryType::Periodic)
            throw InputError("boundary.z_low/z_high: a 2D run (grid.cells[2] = 1) must be "
                             "periodic in z");
    }
    {
        TableReader r = top.sub("forcing", "uniform forcing");
        c.body_force = r.vector3("body_force", Real3{0, 0, 0}, Range{}, "N/m^3",
                                 "uniform force density, e.g. minus a mean pressure gradient");
        r.finish();
    }
    {
        TableReader r = top.sub("initial", "initial velocity field");
        c.initial.type = r.string(
            "type", "rest", {"rest", "uniform", "taylor_green", "couette", "poiseuille", "shear"},
            "named initial velocity (see docs/case-reference.md)");
        c.initial.amplitude =
            r.number("amplitude", 1.0, Range{}, "m/s", "velocity scale of the initial field");
        c.initial.velocity = r.vector3("velocity", Real3{0, 0, 0}, Range{}, "m/s",
                                       "type = uniform: the velocity everywhere");
        r.finish();
    }
    {
        TableReader r = top.sub("time", "time stepping");
        c.time.end_time = r.number("end_time", std::nullopt, Range::positive(), "s",
                                   "simulated time at which the run stops");
        c.time.max_steps =
            r.integer("max_steps", 100000000, Range::closed(1, 2e9), "cap on the number of steps");
        c.time.fixed_dt = r.number("dt", 0.0, Range::non_negative(), "s",
                                   "fixed time step; 0 selects the adaptive step");
        c.time.cfl = r.number("cfl", 0.5, Range{0, 1, true}, "-",
                              "safety factor applied to every stability limit of the adaptive dt");
        c.time.dt_max = r.number("dt_max", 0.0, Range::non_negative(), "s",
                                 "upper bound on the adaptive dt; 0 = none");
        const std::string v =
            r.string("viscous", "crank_nicolson", {"explicit", "crank_nicolson", "backward_euler"},
                     "viscous term: explicit, or implicit (see solver.viscous.method)");
        c.time.viscous = v == "explicit"         ? ViscousScheme::Explicit
                         : v == "crank_nicolson" ? ViscousScheme::CrankNicolson
                                                 : ViscousScheme::BackwardEuler;
        c.time.increment_damping = r.number(
            "increment_damping", 1.0, Range::closed(1, 1e6), "-",
            "F >= 1: the implicit viscous solve damps the velocity increment with the extra "
            "viscosity (F - 1) fluid.viscosity, relaxing the viscous time-step limits of the "
            "membrane and bending forces F-fold; exact at steady state, a lag of about F dt in "
            "transients (docs/method.md); 1 = off");
        c.time.increment_damping_on =
            r.string("increment_damping_on", "everywhere", {"everywhere", "membranes"},
                     "where time.increment_damping acts: the whole fluid, or only the "
                     "membranes' bands (weight 4 phi (1 - phi) summed over the membranes, at "
                     "most 1; the viscous solve is then hypre's)") == "membranes"
                ? DampingRegion::Membranes
                : DampingRegion::Everywhere;
        r.finish();
    }
    {
        TableReader r = top.sub("solver", "linear solvers");
        c.pressure_solver = read_solver(
            r.sub("pressure", "pressure Poisson solve (FFT or hypre Struct)"), 1e-10, 500);
        c.viscous_solver = read_solver(
            r.sub("viscous", "implicit viscous solve (FFT or hypre Struct)"), 1e-10, 200);
        r.finish();
    }
    {
        TableReader r = top.sub("output", "what is written and how often");
        c.output.diagnostics_every = r.integer("diagnostics_every", 10, Range::closed(1, 1e9),
                                               "steps between rows of diagnostics.csv");
        c.output.progress_every = r.integer("progress_every", 100, Range::closed(1, 1e9),
                                            "steps between progress lines on the terminal");
        c.output.fields_interval = r.number("fields_interval", 0.0, Range::non_negative(), "s",
                                            "simulated time between field snapshots; 0 = "
                                            "initial and final state only");
        c.output.fields = r.boolean("fields", true, "write field snapshots (HDF5 + XDMF)");
        c.output.checkpoint_every = r.integer("checkpoint_every", 0, Range::closed(0, 1e9),
                                              "steps between checkpoints; 0 = at the end only");
        r.finish();
    }
    {
        TableReader r = top.sub("stability", "when a run is declared unstable");
        c.stability.max_cfl = r.number("max_cfl", 2.0, Range::positive(), "-",
                                       "CFL number above which the run stops as unstable");
        c.stability.max_velocity = r.number("max_velocity", 1e6, Range::positive(), "m/s",
                                            "speed above which the run stops as a blow-up");
        c.stability.max_tensor_trace = r.number(
            "max_tensor_trace", 100.0, Range{2.0, std::numeric_limits<real>::infinity(), true}, "-",
            "trace of a body's tensor (B of a solid, 3 when unstrained; Gs of a membrane "
            "over its band, 2 when unstrained) above which the run stops as unstable "
            "(checked at each diagnostics step)");
        r.finish();
    }
    c.bodies = read_bodies(top, c.grid, periodic_directions(c.boundaries), c.length_unit);
    if (!KeyCatalogue::instance().documenting)
        for (std::size_t k = 0; k < c.bodies.size(); ++k) {
            const BodyConfig& b = c.bodies[k];
            if (b.shape != BodyShape::Mask) continue;
            namespace fs = std::filesystem;
            const fs::path file = mask_path(b, case_dir);
            std::error_code ec;
            const auto st = fs::status(file, ec);
            if (!fs::exists(st))
                throw InputError(fmt::format("body[{}].mask_file = \"{}\": no such file ({})", k,
                                             b.mask_file, file.string()));
            if (!fs::is_regular_file(st))
                throw InputError(
                    fmt::format("body[{}].mask_file = \"{}\": not a regular file", k, b.mask_file));
            // The header only (size, spacing, origin): a mask that misses the box, or has no
            // placement and another size than the grid, is refused before any allocation.
            try {
                MaskMapping map;
                read_voxel_mask_for_grid(file, b.mask_dataset, c.grid, c.length_unit, &map);
                c.bodies[k].mask_mapping = map.description;
            } catch (const InputError& e) {
                throw InputError(fmt::format("body[{}].mask_file / mask_dataset: {}", k, e.what()));
            }
        }
    if (!KeyCatalogue::instance().documenting) check_shape_keys(c.bodies);
    // Every section that does not depend on the seeded bodies is read before the seeding,
    // which can take a while (Ht 20 % in a tube): a bad key there is reported at once.
    {
        TableReader r = top.sub("contact", "short-range repulsion between bodies");
        c.contact.stiffness =
            r.number("stiffness", 0.0, Range::non_negative(), "Pa",
                     "k of the pair force -k sum a_i grad(a_j) dV between bodies (a = phi "
                     "dilated by one cell), spread over each body's volume; 0: no contact "
                     "force (docs/method.md, \"Contact between bodies\")");
        r.finish();
    }
    c.vof = read_vof(top);
    {
        TableReader r = top.sub("parallel", "MPI decomposition");
        c.ranks = r.ivector3("ranks", Int3{0, 0, 0}, Range::closed(0, 1e6),
                             "MPI ranks per direction; 0 = chosen automatically");
        r.finish();
    }
    if (top.has("seeding") && !KeyCatalogue::instance().documenting) {
        // [adhesion] but for its receptors' bodies, and the unknown sections, at once.
        read_adhesion(top, c.grid, c.bodies, /*check_receptor_bodies=*/false);
        top.finish_except({"seeding"});
    }
    c.seeding = expand_seeding(root, top, c.grid, periodic_directions(c.boundaries), c.bodies,
                               c.length_unit);
    c.adhesion = read_adhesion(top, c.grid, c.bodies);
    top.finish();

    if (!KeyCatalogue::instance().documenting) {
        // Impossible set-ups, caught before allocation.
        if (c.time.fixed_dt == 0 && c.time.viscous == ViscousScheme::Explicit && c.time.cfl > 0.9)
            throw InputError("time.cfl: must be <= 0.9 with an explicit viscous term");
        if (c.time.increment_damping > 1 && c.time.viscous == ViscousScheme::Explicit)
            throw InputError("time.increment_damping: needs an implicit viscous term "
                             "(time.viscous = \"crank_nicolson\" or \"backward_euler\"); "
                             "it is damping added to the implicit viscous solve");
        if (c.time.increment_damping_on == DampingRegion::Membranes &&
            std::none_of(c.bodies.begin(), c.bodies.end(),
                         [](const BodyConfig& b) { return b.kind == BodyKind::Membrane; }))
            throw InputError("time.increment_damping_on = \"membranes\": the case has no "
                             "membrane body to confine the damping to");
        const LinearSolverChoice choice = choose_linear_solvers(c);
        if (c.viscous_solver.method == "fft" && c.time.viscous != ViscousScheme::Explicit &&
            !choice.viscous_fft)
            throw InputError(fmt::format("solver.viscous.method = \"fft\": the FFT solve needs "
                                         "constant coefficients, but {}; use \"auto\" or a "
                                         "hypre method",
                                         choice.viscous_reason));
        for (int d = 0; d < c.grid.dim; ++d)
            if (c.boundaries[d][0].type == BoundaryType::Periodic &&
                (c.grid.cells[d] & (c.grid.cells[d] - 1)) != 0 && !choice.pressure_fft &&
                c.pressure_solver.method != "pcg_smg")
                throw InputError(fmt::format(
                    "grid.cells[{}] = {}: hypre's PFMG needs a power of two along a periodic "
                    "direction; use a power of two or solver.pressure.method = \"auto\", "
                    "\"fft\" or \"pcg_smg\"",
                    d, c.grid.cells[d]));
    }
    std::ostringstream os;
    if (c.seeding.used)
        os << fmt::format("# The [seeding] section (seed {}) was expanded into the [[body]] "
                          "entries it placed:\n# {}\n",
                          c.seeding.seed, c.seeding.message);
    os << root;
    c.resolved_toml = os.str();
    return c;
}

} // namespace

LinearSolverChoice choose_linear_solvers(const Config& c) {
    LinearSolverChoice out;
    // Pressure: -lap phi with zero normal gradient at every wall, one density everywhere
    // and a uniform grid (the reader admits nothing else), so the FFT solve always applies.
    const std::string& pm = c.pressure_solver.method;
    out.pressure_fft = pm == "auto" || pm == "fft";
    out.pressure_reason = pm == "auto"
                              ? "uniform grid and one density (solver.pressure.method = \"auto\")"
                          : pm == "fft" ? "solver.pressure.method = \"fft\""
                                        : fmt::format("solver.pressure.method = \"{}\"", pm);
    // Viscous: (I - theta dt mu / rho lap) needs a uniform mu and no pinned solid.
    std::string obstacle;
    if (c.time.viscous == ViscousScheme::Explicit) obstacle = "time.viscous = \"explicit\"";
    for (const BodyConfig& b : c.bodies) {
        if (!obstacle.empty()) break;
        if (b.pinned)
            obstacle =
                fmt::format("body '{}' is pinned (its penalisation varies in space)", b.name);
        else if (b.kind == BodyKind::Solid && b.solid_viscosity >= 0 &&
                 b.solid_viscosity != c.fluid.viscosity)
            obstacle = fmt::format("body '{}' has solid_viscosity {} != fluid.viscosity {} "
                                   "(the viscosity varies in space)",
                                   b.name, b.solid_viscosity, c.fluid.viscosity);
        else if (b.kind == BodyKind::Membrane && b.viscosity_ratio != 1)
            obstacle = fmt::format("body '{}' has viscosity_ratio {} (the viscosity varies in "
                                   "space)",
                                   b.name, b.viscosity_ratio);
    }
    if (obstacle.empty() && c.time.increment_damping > 1 &&
        c.time.increment_damping_on == DampingRegion::Membranes)
        obstacle = "time.increment_damping_on = \"membranes\" (the damping varies in space)";
    const std::string& vm = c.viscous_solver.method;
    out.viscous_fft = obstacle.empty() && (vm == "auto" || vm == "fft");
    if (!obstacle.empty())
        out.viscous_reason = obstacle;
    else
        out.viscous_reason = vm == "auto" ? "uniform viscosity, no pinned solid "
                                            "(solver.viscous.method = \"auto\")"
                                          : fmt::format("solver.viscous.method = \"{}\"", vm);
    return out;
}

Config parse_case(const std::string& toml_text, const std::filesystem::path& case_dir,
                  const Overrides& overrides) {
    toml::table root;
    try {
        root = toml::parse(toml_text);
    } catch (const toml::parse_error& e) {
        const auto& src = e.source();
        throw InputError(fmt::format("{}:{}:{}: malformed TOML: {}",
                                     (case_dir / "case.toml").string(), src.begin.line,
                                     src.begin.column, e.description()));
    }
    for (const auto& [k, v] : overrides)
        apply_override(root, k, v);
    return read_config(root, case_dir);
}

Config load_case(const std::filesystem::path& case_path, const Overrides& overrides) {
    namespace fs = std::filesystem;
    fs::path file = case_path;
    if (fs::is_directory(file)) file /= "case.toml";
    std::error_code ec;
    const auto st = fs::status(file, ec);
    if (!fs::exists(st))
        throw InputError(fmt::format("{}: no such case (expected a folder with case.toml, or "
                                     "a .toml file)",
                                     case_path.string()));
    if (!fs::is_regular_file(st))
        throw InputError(fmt::format("{}: not a regular file (expected a folder with case.toml, "
                                     "or a .toml file)",
                                     file.string()));
    // A case file is a few kB; a huge one is not a case (and would be read whole).
    if (fs::file_size(file, ec) > (1u << 20))
        throw InputError(fmt::format("{}: larger than 1 MB, not a case file", file.string()));
    std::ifstream in(file);
    if (!in) throw InputError(fmt::format("{}: cannot be read", file.string()));
    std::stringstream ss;
    ss << in.rdbuf();
    fs::path dir = fs::absolute(file).parent_path();
    Config c = parse_case(ss.str(), dir, overrides);
    return c;
}

std::string case_reference_markdown() {
    auto& cat = KeyCatalogue::instance();
    cat.documenting = true;
    toml::table root;
    read_config(root, "case");
    cat.documenting = false;
    std::string md;
    md += "| key | type | unit | default | range | meaning |\n";
    md += "|---|---|---|---|---|---|\n";
    for (const auto& k : cat.keys()) {
        if (k.type == "table") continue;
        md += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", k.key, k.type, k.unit, k.deflt,
                          k.range, k.meaning);
    }
    return md;
}

} // namespace efsi
