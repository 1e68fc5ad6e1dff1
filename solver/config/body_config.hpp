// Case-file description of the bodies ([[body]] sections) and of their VOF transport.
#pragma once

#include "core/types.hpp"
#include "grid/grid.hpp"

#include <algorithm>
#include <array>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace efsi {

class TableReader;

// The choices of a [[body]] section, parsed once by read_bodies (an unknown name is an error
// naming the key); everything past the config boundary compares enums, never strings.
// `keyword` gives the case-file spelling back (the resolved echo, the case fingerprint).

/// passive (phi only) | solid (carries B; `pinned` makes it a fixed wall) | membrane (Gs).
enum class BodyKind { Passive, Solid, Membrane };
enum class BodyShape { Sphere, Ellipsoid, Biconcave, Cylinder, Box, Slab, Mask, Tube };
/// sharp: cell volume fractions; smoothed: the tanh profile of the membranes' smoothed VOF.
enum class InterfaceKind { Sharp, Smoothed };
/// The membrane's surface strain energy Ws (MODEL.md).
enum class MembraneLawKind { NeoHookean, Skalak };
/// The velocity that carries a membrane's Gs.
enum class StrainVelocity { Surface, Local };
/// How a membrane's Gs outside the band core is rebuilt after each step.
enum class StrainExtension { Normal, Layers };
/// What a membrane carries to know its surface strain: Gs itself (transported with the
/// velocity gradient) or the reference map X(x, t) (advected, Gs rebuilt from its gradient).
enum class StrainModel { Tensor, ReferenceMap };
/// How the reference map is interpolated at the foot points when it is extended.
enum class MapInterpolation { Cubic, Linear };

inline constexpr std::array<std::string_view, 3> body_kind_names{"passive", "solid", "membrane"};
inline constexpr std::array<std::string_view, 8> body_shape_names{
    "sphere", "ellipsoid", "biconcave", "cylinder", "box", "slab", "mask", "tube"};
inline constexpr std::array<std::string_view, 2> interface_names{"sharp", "smoothed"};
inline constexpr std::array<std::string_view, 2> membrane_law_names{"neo_hookean", "skalak"};
inline constexpr std::array<std::string_view, 2> strain_velocity_names{"surface", "local"};
inline constexpr std::array<std::string_view, 2> strain_extension_names{"normal", "layers"};
inline constexpr std::array<std::string_view, 2> strain_model_names{"tensor", "reference_map"};
inline constexpr std::array<std::string_view, 2> map_interpolation_names{"cubic", "linear"};

inline std::string_view keyword(BodyKind v) {
    return body_kind_names[int(v)];
}
inline std::string_view keyword(BodyShape v) {
    return body_shape_names[int(v)];
}
inline std::string_view keyword(InterfaceKind v) {
    return interface_names[int(v)];
}
inline std::string_view keyword(MembraneLawKind v) {
    return membrane_law_names[int(v)];
}
inline std::string_view keyword(StrainVelocity v) {
    return strain_velocity_names[int(v)];
}
inline std::string_view keyword(StrainExtension v) {
    return strain_extension_names[int(v)];
}
inline std::string_view keyword(StrainModel v) {
    return strain_model_names[int(v)];
}
inline std::string_view keyword(MapInterpolation v) {
    return map_interpolation_names[int(v)];
}

/// The membrane law named `name` (neo_hookean, skalak); InputError naming `key` otherwise.
MembraneLawKind parse_membrane_law(const std::string& name, const std::string& key = "body.law");

struct BodyConfig {
    std::string name;
    BodyKind kind = BodyKind::Passive;
    bool bending = false; ///< membrane with bending_modulus > 0: carries kappa_R
    BodyShape shape = BodyShape::Sphere;
    Real3 centre{0, 0, 0};             ///< [m]
    real radius = 0;                   ///< sphere, cylinder; biconcave R0 [m]
    Real3 semi_axes{0, 0, 0};          ///< ellipsoid [m]
    Real3 half_sizes{0, 0, 0};         ///< box [m]
    Real3 normal{0, 1, 0};             ///< slab normal
    real thickness = 0;                ///< slab [m]
    real lumen_diameter = 0;           ///< tube: the wall is farther than this / 2 from its axis
    Real3 axis{0, 0, 1};               ///< orientation: rotation axis
    real angle = 0;                    ///< orientation: rotation angle [rad]
    std::string mask_file;             ///< mask: HDF5 file (relative to the case folder)
    std::string mask_dataset = "mask"; ///< mask: dataset [nz][ny][nx] of values in [0,1]
    /// mask: how it maps onto the grid (copied or resampled), found when the case is read
    std::string mask_mapping;
    InterfaceKind interface = InterfaceKind::Sharp;
    real smoothing_width = 1.0; ///< smoothed: eps of the tanh profile, in cells
    int subsamples = 8;         ///< sharp: sub-samples per direction in cut cells
    int margin = 4;             ///< cells kept around the body on its patch
    // Solid (visco neo-Hookean): sigma_s' = 2 mu_s D' + G B'.
    real shear_modulus = 0;    ///< G [Pa]
    real solid_viscosity = -1; ///< mu_s [Pa s]; < 0: the fluid's viscosity
    /// B where phi < this is the extension of B from the cells above it (docs/method.md,
    /// Solids); 0 turns the extension off. < 0: the default (0.5 sharp, 0 smoothed).
    real extension_threshold = -1;
    /// Solid held in place: not transported, velocity inside penalised to zero by
    /// -(chi / tau) v with tau = pin_tau_over_dt * dt (docs/method.md, Solids).
    bool pinned = false;
    real pin_tau_over_dt = 1e-8;
    // Membrane: surface strain energy Ws of the law, with modulus Es.
    MembraneLawKind law = MembraneLawKind::NeoHookean;
    real elastic_modulus = 0; ///< Es [N/m]
    real area_dilation = 1;   ///< Skalak's C (alpha)
    real bending_modulus = 0; ///< Eb [N m] of m = Eb (kappa - kappa_R P); 0: no bending
    /// Viscosity of the enclosed fluid over the fluid's (lambda); 1: one viscosity.
    real viscosity_ratio = 1;
    /// Velocity that carries Gs: "surface" (the surface's, extended along the normals:
    /// every layer of the band shares the membrane's strain) or "local" (each layer its own).
    StrainVelocity strain_velocity = StrainVelocity::Surface;
    real surface_velocity_reach = 5.0; ///< cells (strain_velocity = surface)
    /// How Gs outside the band core is rebuilt after each step: "normal" (closest-point
    /// extension of the core's Gs along the normals, P Gs P, I beyond the band) or "layers"
    /// (the mean of known neighbours marched out from t <= phi <= 1 - t, extension_threshold).
    StrainExtension strain_extension = StrainExtension::Normal;
    real strain_core = 1.0; ///< cells: half-thickness of the core (strain_extension = normal)
    /// "tensor": Gs transported, D Gs/Dt = L Gs + Gs L^T; "reference_map": the reference map's
    /// offset X - x transported (no velocity gradient), extended along the normals and Gs
    /// rebuilt from grad X each step (membrane/reference_map.hpp).
    StrainModel strain_model = StrainModel::ReferenceMap;
    MapInterpolation map_interpolation = MapInterpolation::Cubic;
    /// strain_model = reference_map on a shape: X put back onto the reference shape's surface
    /// (its closest point) in the band each step, since X(x) of a surface point lies on it.
    bool map_projection = true;
    /// strain_model = reference_map: the area ratio J of the strain rebuilt from X is
    /// low-passed over the valid cells near the surface ((1, 2, 1) in each direction) and
    /// each band cell's Gs rescaled to the J interpolated at its foot point (docs/method.md,
    /// "The area ratio, low-passed").
    bool map_area_filter = true;
    /// Pseudo-steps per time step of the conservative restoration of phi's tanh profile.
    int profile_iterations = 2;
    /// A band cell takes the membrane force only where |grad psi| >= this
    /// (MembraneForceSettings::min_distance_gradient).
    real min_distance_gradient = 0.5;
    /// strain_extension = normal: foot points psi / |grad psi| along the normal, not psi
    /// (NormalExtension's newton_foot).
    bool newton_foot_points = false;
    /// strain_model = tensor, strain_extension = normal: Gs transported only near the
    /// extension's band (BodyTransport::advance's band_phi), not on the whole patch.
    bool band_transport = true;

    /// A membrane whose strain is derived from a transported reference map.
    bool carries_reference_map() const {
        return kind == BodyKind::Membrane && strain_model == StrainModel::ReferenceMap;
    }
    /// A moving membrane whose Gs (or map) is carried by the surface velocity.
    bool carried_by_surface_velocity() const {
        return kind == BodyKind::Membrane && !pinned && strain_velocity == StrainVelocity::Surface;
    }
    /// A solid's viscosity mu_s: solid_viscosity, or the fluid's (`fluid_viscosity`) when unset.
    real solid_viscosity_or(real fluid_viscosity) const {
        return solid_viscosity >= 0 ? solid_viscosity : fluid_viscosity;
    }
    /// The viscosity that damps a membrane's modes (its time-step limits): the smaller of the
    /// two its band mixes, the outer fluid's and the enclosed fluid's.
    real membrane_damping_viscosity(real fluid_viscosity) const {
        return std::min(real(1), viscosity_ratio) * fluid_viscosity;
    }
};

struct VofConfig {
    std::string scheme = "mthinc"; ///< mthinc | thinc
    real beta_thinc = 3.5;
    real beta_mthinc = 2.0;
};

/// Half-extent of the body's initial bounding box about its centre (conservative when
/// rotated); negative entries mean "unbounded along that direction" (slab, mask, tube,
/// the cylinder's axis).
Real3 body_half_extent(const BodyConfig& b, int dim);

/// The exact half-extent of the body's initial shape along each axis (rotation included)
/// for an ellipsoid or a box, that of the cylinder holding it for a biconcave disc (radius
/// R0, its largest half-thickness, about its rotated axis); body_half_extent otherwise. The
/// check that a body lies inside the domain uses it, so that an ellipsoid lying flat by a
/// wall, or a red cell turned edge-on to it, is not refused for its radius.
Real3 body_axis_extent(const BodyConfig& b, int dim);

/// Read and check the [[body]] sections against the grid (a body outside the domain is an
/// error naming it). Called by the case reader, which then checks the mask files and keys
/// that belong to another shape (check_shape_keys).
/// `length_unit` labels lengths in the messages.
std::vector<BodyConfig> read_bodies(TableReader& top, const GlobalGrid& grid,
                                    const std::array<bool, 3>& periodic,
                                    std::string_view length_unit = "m");
/// Keys set for a shape the body does not have (lumen_diameter on a non-tube): checked last,
/// so a shape changed by hand is reported for what the new shape misses.
void check_shape_keys(const std::vector<BodyConfig>& bodies);
/// A mask body's file: mask_file relative to the case folder (an absolute one as it is;
/// std::filesystem's `/` keeps an absolute right side).
inline std::filesystem::path mask_path(const BodyConfig& b, const std::filesystem::path& case_dir) {
    return case_dir / b.mask_file;
}
VofConfig read_vof(TableReader& top);

} // namespace efsi
