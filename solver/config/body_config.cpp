#include "config/body_config.hpp"

#include "config/reader.hpp"
#include "core/error.hpp"
#include "interface/shapes.hpp"
#include "interface/thinc.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace efsi {

namespace {

/// Read the string key `key` as one of `names` (the reader refuses any other value, naming
/// the key and the allowed ones) and return it as the enum at that index.
template <class E, std::size_t N>
E read_choice(TableReader& r, const std::string& key, E deflt,
              const std::array<std::string_view, N>& names, const std::string& meaning,
              bool required = false) {
    const std::vector<std::string> choices(names.begin(), names.end());
    const std::string v =
        r.string(key, required ? std::nullopt : std::optional<std::string>(names[int(deflt)]),
                 choices, meaning);
    return E(std::find(choices.begin(), choices.end(), v) - choices.begin());
}

} // namespace

Real3 body_half_extent(const BodyConfig& b, int dim) {
    const real inf = -1;
    if (b.shape == BodyShape::Sphere) return {b.radius, b.radius, b.radius};
    if (b.shape == BodyShape::Ellipsoid) {
        const real m = std::max({b.semi_axes[0], b.semi_axes[1], b.semi_axes[2]});
        return {m, m, m};
    }
    if (b.shape == BodyShape::Biconcave) return {b.radius, b.radius, b.radius};
    if (b.shape == BodyShape::Cylinder) return {b.radius, b.radius, dim == 2 ? b.radius : inf};
    if (b.shape == BodyShape::Box) {
        const real m = std::hypot(b.half_sizes[0], b.half_sizes[1], b.half_sizes[2]);
        return {m, m, m};
    }
    return {inf, inf, inf}; // slab, mask, tube: checked otherwise
}

namespace {

/// The Evans-Fung disc's largest half-thickness, max over r of
/// (R0/2) sqrt(1 - r^2) (C0 + C1 r^2 + C2 r^4): with x = r^2 the stationary points of
/// sqrt(1 - x) P(x) solve 2 (1 - x) P'(x) = P(x), a quadratic in x.
real biconcave_half_thickness(const EvansFungCoefficients& k) {
    auto g = [&](real x) { return std::sqrt(1 - x) * (k.c0 + k.c1 * x + k.c2 * x * x); };
    real best = std::max(g(0.0), g(1.0));
    const real a = -5 * k.c2, bq = 4 * k.c2 - 3 * k.c1, c = 2 * k.c1 - k.c0;
    const real disc = bq * bq - 4 * a * c;
    if (a != 0 && disc >= 0)
        for (real sign : {-1.0, 1.0}) {
            const real x = (-bq + sign * std::sqrt(disc)) / (2 * a);
            if (x > 0 && x < 1) best = std::max(best, g(x));
        }
    return 0.5 * k.r0 * best;
}

} // namespace

Real3 body_axis_extent(const BodyConfig& b, int dim) {
    if (b.shape != BodyShape::Ellipsoid && b.shape != BodyShape::Box &&
        b.shape != BodyShape::Biconcave)
        return body_half_extent(b, dim);
    // x = R y + c: the support function sqrt(sum_j (R_ij a_j)^2) of an ellipsoid,
    // sum_j |R_ij| h_j of a box; a biconcave disc lies in the cylinder rho <= R0,
    // |z| <= its half-thickness t about its axis n = R e_z, whose support function along e_i
    // is R0 sqrt(1 - n_i^2) + t |n_i| (a disc standing on its rim near a wall is not refused
    // for its radius along the wall's normal).
    const Matrix3 rot = b.angle != 0 ? axis_angle_rotation(b.axis, b.angle) : identity_rotation();
    real thickness = 0;
    if (b.shape == BodyShape::Biconcave) {
        EvansFungCoefficients k;
        k.r0 = b.radius;
        thickness = biconcave_half_thickness(k);
    }
    Real3 e{};
    for (int i = 0; i < 3; ++i) {
        if (b.shape == BodyShape::Biconcave) {
            const real n = std::min(std::abs(rot[i][2]), 1.0);
            e[i] = b.radius * std::sqrt(1 - n * n) + thickness * n;
            continue;
        }
        e[i] = b.shape == BodyShape::Ellipsoid
                   ? std::hypot(rot[i][0] * b.semi_axes[0], rot[i][1] * b.semi_axes[1],
                                rot[i][2] * b.semi_axes[2])
                   : std::abs(rot[i][0]) * b.half_sizes[0] + std::abs(rot[i][1]) * b.half_sizes[1] +
                         std::abs(rot[i][2]) * b.half_sizes[2];
    }
    return e;
}

MembraneLawKind parse_membrane_law(const std::string& name, const std::string& key) {
    for (std::size_t k = 0; k < membrane_law_names.size(); ++k)
        if (membrane_law_names[k] == name) return MembraneLawKind(k);
    throw InputError(fmt::format("{} = \"{}\": unknown membrane law (allowed: neo_hookean, "
                                 "skalak)",
                                 key, name));
}

std::vector<BodyConfig> read_bodies(TableReader& top, const GlobalGrid& grid,
                                    const std::array<bool, 3>& periodic, std::string_view unit) {
    std::vector<BodyConfig> bodies;
    std::set<std::string> names;
    for (TableReader& r : top.tables("body", "the bodies: one [[body]] section each")) {
        BodyConfig b;
        b.name = r.string("name", std::nullopt, {}, "unique name (used in output names)");
        b.kind = read_choice(r, "kind", BodyKind::Passive, body_kind_names,
                             "passive (phi only), solid (carries B) or membrane (carries Gs)");
        b.shape = read_choice(r, "shape", BodyShape::Sphere, body_shape_names, "initial shape",
                              /*required=*/true);
        b.centre = r.vector3("centre", Real3{0, 0, 0}, Range{}, "m", "centre of the shape");
        b.radius = r.number("radius", 0.0, Range::non_negative(), "m",
                            "sphere / cylinder radius; biconcave R0 (default 3.91e-6)");
        b.semi_axes = r.vector3("semi_axes", Real3{0, 0, 0}, Range::non_negative(), "m",
                                "ellipsoid semi-axes along the body axes");
        b.half_sizes = r.vector3("half_sizes", Real3{0, 0, 0}, Range::non_negative(), "m",
                                 "box half-sizes along the body axes");
        b.normal = r.vector3("normal", Real3{0, 1, 0}, Range{}, "-", "slab normal");
        b.thickness = r.number("thickness", 0.0, Range::non_negative(), "m", "slab thickness");
        b.lumen_diameter = r.number("lumen_diameter", 0.0, Range::non_negative(), "m",
                                    "tube: diameter of the lumen; the body is everything "
                                    "farther than lumen_diameter / 2 from the line along x "
                                    "through centre (a vessel wall)");
        b.axis = r.vector3("axis", Real3{0, 0, 1}, Range{}, "-", "orientation: rotation axis");
        b.angle = r.number("angle", 0.0, Range{}, "rad", "orientation: rotation angle about axis");
        b.mask_file = r.string("mask_file", "", {}, "mask: HDF5 file, relative to the case folder");
        b.mask_dataset = r.string("mask_dataset", "mask", {},
                                  "mask: dataset [nz][ny][nx] of 0/1 labels or volume fractions "
                                  "in [0,1], with attributes spacing and origin (3 numbers each, "
                                  "the case's length unit; resampled when the voxels are not the "
                                  "cells) or neither (then it has the grid's cells)");
        b.interface = read_choice(r, "interface", InterfaceKind::Sharp, interface_names,
                                  "sharp: exact cell volume fractions; smoothed: tanh profile "
                                  "(the membrane's smoothed VOF)");
        b.smoothing_width = r.number(
            "smoothing_width", 1.0,
            Range::closed(1 / mthinc_beta_max, std::numeric_limits<real>::infinity()), "cells",
            "smoothed: width eps of phi = (1 - tanh(L/eps))/2 (its VOF advection's "
            "MTHINC beta is 1/eps, at most 50)");
        b.subsamples = r.integer("subsamples", 8, Range::closed(1, 64),
                                 "sharp: sub-samples per direction in the cells the surface cuts");
        b.margin = r.integer("margin", 4, Range::closed(2, 1000),
                             "cells kept around the body on its patch");
        b.shear_modulus = r.number("shear_modulus", 0.0, Range::non_negative(), "Pa",
                                   "solid: modulus G of the neo-Hookean stress G B'");
        b.solid_viscosity = r.number("solid_viscosity", -1.0, Range{}, "Pa s",
                                     "solid: viscosity mu_s (negative: the fluid's)");
        b.extension_threshold =
            r.number("extension_threshold", -1.0, Range::closed(-1.0, 1.0), "-",
                     "solid: B in cells with phi below this is extended from the cells above it "
                     "(0: off; negative: 0.5 for a sharp interface, 0 for a smoothed one); "
                     "membrane: Gs outside the band core t <= phi <= 1 - t is extended from "
                     "the core (0: off; negative: 0.01)");
        b.pinned = r.boolean("pinned", false,
                             "solid: fixed in space (not transported; the velocity inside is "
                             "penalised to zero, e.g. a vessel wall)");
        b.pin_tau_over_dt = r.number("pin_tau_over_dt", 1e-8, Range::positive(), "-",
                                     "pinned: penalisation time tau of -(phi / tau) v, in units "
                                     "of dt (implicit; smaller holds tighter)");
        b.law = read_choice(r, "law", MembraneLawKind::NeoHookean, membrane_law_names,
                            "membrane: strain energy (MODEL.md): neo_hookean or skalak");
        b.elastic_modulus = r.number("elastic_modulus", 0.0, Range::non_negative(), "N/m",
                                     "membrane: modulus Es of the law (neo-Hookean: Es = 3 Gs)");
        b.area_dilation = r.number("area_dilation", 1.0, Range::positive(), "-",
                                   "membrane, skalak: area-dilation constant C (alpha)");
        b.bending_modulus =
            r.number("bending_modulus", 0.0, Range::non_negative(), "N m",
                     "membrane: bending modulus Eb of the moment m = Eb (kappa - kappa_R P) "
                     "(0: no bending); kappa_R starts as the initial shape's curvature (mean "
                     "curvature in 3D, the section's in 2D)");
        b.viscosity_ratio =
            r.number("viscosity_ratio", 1.0, Range::positive(), "-",
                     "membrane: viscosity of the enclosed fluid over fluid.viscosity (lambda; "
                     "1: one viscosity and the FFT viscous solve; otherwise mu varies with "
                     "phi and the viscous solve is hypre's variable-coefficient one; red "
                     "cells: ~5, physiological)");
        b.strain_velocity =
            read_choice(r, "strain_velocity", StrainVelocity::Surface, strain_velocity_names,
                        "membrane: velocity that carries Gs: surface (the velocity on phi = 1/2, "
                        "extended along the normals, so every layer of the band keeps the "
                        "membrane's strain) or local (each layer its own velocity)");
        b.surface_velocity_reach =
            r.number("surface_velocity_reach", 5.0, Range::closed(1.0, 8.0), "cells",
                     "membrane, strain_velocity = surface: faces within reach - 1 cells of the "
                     "surface take its velocity, blended into the local one by reach; 5 "
                     "covers the band, 1.5 keeps stiff membranes (Es or the Skalak area "
                     "modulus >~ 100 mu shear_rate a) stable (docs/method.md)");
        b.strain_extension = read_choice(
            r, "strain_extension", StrainExtension::Normal, strain_extension_names,
            "membrane: how Gs outside the band core is rebuilt after each step: normal (Gs "
            "kept in |psi| <= strain_core cells and projected, P Gs P, and copied outward "
            "along the normals from the foot point on phi = 1/2; I beyond the band) or layers "
            "(the mean of known neighbours marched out from the core extension_threshold <= "
            "phi <= 1 - extension_threshold)");
        b.strain_core = r.number("strain_core", 1.0, Range::closed(0.0, 4.0), "cells",
                                 "membrane, strain_extension = normal: half-thickness of the "
                                 "band core whose transported Gs is kept");
        b.strain_model = read_choice(
            r, "strain_model", StrainModel::ReferenceMap, strain_model_names,
            "membrane: what carries the surface strain: tensor (Gs transported with the "
            "velocity gradient) or reference_map (the reference map X, stored as X - x, "
            "advected with the strain velocity, extended along the normals, and Gs rebuilt "
            "each step from grad X: no velocity gradient enters; the default; docs/method.md)");
        b.map_interpolation = read_choice(
            r, "map_interpolation", MapInterpolation::Cubic, map_interpolation_names,
            "membrane, strain_model = reference_map: interpolation of the map at the foot "
            "points when it is extended along the normals: cubic (tensor-product 4-point "
            "Lagrange, error O(h^4): the default) or linear (trilinear, O(h^2): its bias "
            "feeds the core and the stored strain drifts, docs/method.md)");
        b.map_projection = r.boolean(
            "map_projection", true,
            "membrane, strain_model = reference_map, a body given by a shape (not a mask): "
            "each step the map's value X in the band is replaced by the nearest point of the "
            "shape's surface (every surface point's reference position lies on it; the "
            "extension's and transport's errors otherwise drift X off it and the stored "
            "strain with it, docs/method.md)");
        b.map_area_filter = r.boolean(
            "map_area_filter", true,
            "membrane, strain_model = reference_map: the area ratio J of the strain rebuilt "
            "from the map is low-passed ((1, 2, 1) in each direction over the cells near the "
            "surface) and every band cell's Gs is rescaled to the J at its foot point: no "
            "grid-scale area mode can grow (it did for area-stiff Skalak membranes), and no "
            "bias from averaging tensors of turning tangent planes (docs/method.md)");
        b.min_distance_gradient = r.number(
            "min_distance_gradient", 0.5, Range::closed(0.05, 1.0), "-",
            "membrane: a band cell takes the membrane force only where the length of grad psi "
            "(psi = eps atanh(2 phi - 1); 1 in a resolved tanh profile) is at least this; 0.8 "
            "delays the tearing of a red cell's drawn-out trailing rim at h = 0.125 um "
            "(5.38 -> 5.85 ms) without preventing it (docs/method.md, \"What tears the "
            "trailing rim\")");
        b.newton_foot_points = r.boolean(
            "newton_foot_points", false,
            "membrane, strain_extension = normal: a band cell's foot point on phi = 1/2 lies "
            "psi / (length of grad psi) along the normal (one Newton step, exact where psi is a "
            "distance times a constant) instead of psi; the map's gradient is corrected for "
            "that distance (docs/method.md, \"What tears the trailing rim\")");
        b.band_transport = r.boolean(
            "band_transport", true,
            "membrane, strain_model = tensor, strain_extension = normal: Gs is transported only "
            "on the cells within 2 cells of the extension's band (|psi| <= its reach), the only "
            "ones whose transported Gs the extension reads; false: on the whole patch (the same "
            "values where they are read, at more cost; docs/method.md, \"Transport on the "
            "band\")");
        b.profile_iterations =
            int(r.integer("profile_iterations", 2, Range::closed(0, 100),
                          "membrane: pseudo-steps per time step of the conservative "
                          "restoration of phi's tanh profile (docs/method.md; 0: none)"));
        b.bending = b.bending_modulus > 0;
        r.finish();
        if (KeyCatalogue::instance().documenting) continue;

        const std::string at = fmt::format("body '{}'", b.name);
        // The name becomes part of dataset and file names: letters, digits, _ and - only.
        if (b.name.empty() || b.name.size() > 64 ||
            b.name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                     "0123456789_-") != std::string::npos)
            throw InputError(fmt::format("{}.name = \"{}\": use 1 to 64 letters, digits, _ or - "
                                         "(it names datasets and output fields)",
                                         r.full("").substr(0, r.full("").size() - 1), b.name));
        if (!names.insert(b.name).second) throw InputError(at + ": the name is used twice");
        if (b.shape == BodyShape::Biconcave && b.radius == 0) b.radius = 3.91e-6;
        auto need = [&](bool ok, const char* key) {
            if (!ok)
                throw InputError(
                    fmt::format("{}: shape '{}' needs body.{} > 0", at, keyword(b.shape), key));
        };
        if (b.shape == BodyShape::Sphere || b.shape == BodyShape::Cylinder)
            need(b.radius > 0, "radius");
        if (b.shape == BodyShape::Ellipsoid)
            need(b.semi_axes[0] > 0 && b.semi_axes[1] > 0 && b.semi_axes[2] > 0, "semi_axes");
        if (b.shape == BodyShape::Box)
            need(b.half_sizes[0] > 0 && b.half_sizes[1] > 0 && b.half_sizes[2] > 0, "half_sizes");
        if (b.shape == BodyShape::Slab) need(b.thickness > 0, "thickness");
        if (b.shape == BodyShape::Tube) {
            need(b.lumen_diameter > 0, "lumen_diameter");
            if (b.angle != 0) throw InputError(at + ": a tube's axis is x; body.angle must be 0");
            if (grid.dim != 3) throw InputError(at + ": shape 'tube' needs a 3D grid");
            // The lumen must lie in the box across its axis (else it is no tube).
            for (int d = 1; d < 3; ++d) {
                const real lo = grid.origin[d], hi = grid.origin[d] + grid.length[d];
                const real lumen_r = 0.5 * b.lumen_diameter;
                if (b.centre[d] - lumen_r < lo || b.centre[d] + lumen_r > hi)
                    throw InputError(fmt::format(
                        "{}: body.lumen_diameter = {:.4g} {} about body.centre[{}] = {:.4g} {} "
                        "reaches outside the domain [{:.4g}, {:.4g}] in {}",
                        at, b.lumen_diameter, unit, d, b.centre[d], unit, lo, hi, "xyz"[d]));
            }
        }
        if (b.shape == BodyShape::Mask && b.mask_file.empty())
            throw InputError(at + ": shape 'mask' needs body.mask_file");
        if (b.kind == BodyKind::Solid && !b.pinned && !(b.shear_modulus > 0))
            throw InputError(at + ": kind = \"solid\" needs body.shear_modulus > 0 [Pa]");
        if (b.kind == BodyKind::Passive && b.extension_threshold >= 0)
            throw InputError(at + ": extension_threshold is for solids and membranes");
        if (b.kind == BodyKind::Membrane && b.extension_threshold >= 0.5)
            throw InputError(at + ": extension_threshold of a membrane must be < 0.5 (the band "
                                  "core is t <= phi <= 1 - t)");
        if (b.extension_threshold < 0)
            b.extension_threshold =
                b.kind == BodyKind::Membrane                                       ? 0.01
                : b.kind == BodyKind::Solid && b.interface == InterfaceKind::Sharp ? 0.5
                                                                                   : 0.0;
        if (b.pinned && b.kind != BodyKind::Solid)
            throw InputError(at + ": pinned = true is only for kind = \"solid\"");
        if (b.kind != BodyKind::Solid && (b.shear_modulus != 0 || b.solid_viscosity >= 0))
            throw InputError(at + ": shear_modulus / solid_viscosity are for kind = \"solid\"");
        if (b.kind == BodyKind::Membrane && !(b.elastic_modulus > 0))
            throw InputError(at + ": kind = \"membrane\" needs body.elastic_modulus > 0 [N/m]");
        if (b.kind == BodyKind::Membrane && b.interface != InterfaceKind::Smoothed)
            throw InputError(at + ": a membrane needs interface = \"smoothed\" (its force is "
                                  "spread by the smoothed delta function |grad phi|)");
        if (b.kind == BodyKind::Membrane && b.strain_model == StrainModel::ReferenceMap &&
            b.strain_extension != StrainExtension::Normal)
            throw InputError(at + ": strain_model = \"reference_map\" (the default) extends the "
                                  "map along the normals; body.strain_extension = \"layers\" "
                                  "needs body.strain_model = \"tensor\"");
        if (b.kind != BodyKind::Membrane && b.elastic_modulus != 0)
            throw InputError(at + ": elastic_modulus is for kind = \"membrane\"");
        if (b.kind != BodyKind::Membrane && b.bending_modulus != 0)
            throw InputError(at + ": bending_modulus is for kind = \"membrane\"");
        if (b.kind != BodyKind::Membrane && b.viscosity_ratio != 1)
            throw InputError(at + ": viscosity_ratio is for kind = \"membrane\" (a solid's "
                                  "own viscosity is body.solid_viscosity)");
        if (b.interface == InterfaceKind::Smoothed &&
            (b.shape == BodyShape::Box || b.shape == BodyShape::Mask))
            throw InputError(at + ": interface = \"smoothed\" needs a sphere, ellipsoid, "
                                  "biconcave disc, cylinder, slab or tube (shapes with a "
                                  "distance-like level function)");
        const real nlen = std::hypot(b.normal[0], b.normal[1], b.normal[2]);
        if (b.shape == BodyShape::Slab && !(nlen > 0))
            throw InputError(at + ": body.normal of a slab must not be zero");
        if (b.angle != 0 && !(std::hypot(b.axis[0], b.axis[1], b.axis[2]) > 0))
            throw InputError(at + ": body.axis must not be zero when body.angle is set");
        if (b.shape == BodyShape::Slab) {
            // The slab |n.(x - c)| <= t/2 must meet the box: n.(x - c) over the box corners.
            real lo = 0, hi = 0;
            for (int d = 0; d < grid.dim; ++d) {
                const real n = b.normal[d] / nlen;
                const real a = n * (grid.origin[d] - b.centre[d]);
                const real z = n * (grid.origin[d] + grid.length[d] - b.centre[d]);
                lo += std::min(a, z);
                hi += std::max(a, z);
            }
            if (hi < -0.5 * b.thickness || lo > 0.5 * b.thickness)
                throw InputError(fmt::format("{}: body.centre / normal: the slab lies entirely "
                                             "outside the domain",
                                             at));
        }
        // A body must lie inside the box along walled directions, and meet the box at all.
        const Real3 h = body_axis_extent(b, grid.dim);
        for (int d = 0; d < grid.dim; ++d) {
            if (h[d] < 0) continue;
            const real lo = grid.origin[d], hi = grid.origin[d] + grid.length[d];
            const real a = b.centre[d] - h[d], z = b.centre[d] + h[d];
            const bool outside = z <= lo || a >= hi;
            const bool crosses_wall = !periodic[d] && (a < lo || z > hi);
            if (outside || crosses_wall)
                throw InputError(fmt::format(
                    "{}: body.centre / size: the {} reaches {} from {:.4g} to {:.4g} {} in {}, "
                    "outside the domain [{:.4g}, {:.4g}]",
                    at, keyword(b.shape), outside ? "entirely" : "through a wall", a, z, unit,
                    "xyz"[d], lo, hi));
        }
        bodies.push_back(b);
    }
    return bodies;
}

void check_shape_keys(const std::vector<BodyConfig>& bodies) {
    for (const BodyConfig& b : bodies)
        if (b.shape != BodyShape::Tube && b.lumen_diameter != 0)
            throw InputError(
                fmt::format("body '{}': lumen_diameter is for shape = \"tube\"", b.name));
}

VofConfig read_vof(TableReader& top) {
    TableReader r = top.sub("vof", "VOF transport of the bodies' volume fractions");
    VofConfig v;
    v.scheme = r.string("scheme", "mthinc", {"mthinc", "thinc"},
                        "mthinc (multidimensional, planar) or thinc (1D per sweep)");
    v.beta_thinc = r.number("beta_thinc", 3.5, Range::positive(), "-", "1D THINC sharpness");
    v.beta_mthinc = r.number("beta_mthinc", 2.0, Range{0, mthinc_beta_max, true}, "-",
                             "MTHINC sharpness along the normal (unit-cell coordinates)");
    r.finish();
    return v;
}

} // namespace efsi
