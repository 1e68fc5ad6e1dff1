// A body on the fixed grid: its volume fraction phi and only the fields its physics asks
// for (a solid carries B; a membrane carries Gs, and kappa_R when it has bending), all
// stored on the body's patch (its bounding box plus a margin), never on the whole grid.
#pragma once

#include "bodies/patch.hpp"
#include "bodies/symmetric_tensor.hpp"
#include "config/body_config.hpp"
#include "grid/field.hpp"

#include <optional>
#include <string>
#include <vector>

namespace efsi {

class Body {
  public:
    /// `carries_tensor` false makes a passive body: phi only (a tracer of the flow);
    /// `reference_map` true adds the membrane's reference map offset X - x (dim fields).
    Body(std::string name, BodyKind kind, bool bending, int dim, bool carries_tensor = true,
         bool reference_map = false);

    const std::string& name() const { return name_; }
    BodyKind kind() const { return kind_; }
    bool has_bending() const { return bending_; }
    const Patch& patch() const { return patch_; }

    /// Allocate the fields on `patch` (phi = 0, tensor = identity, kappa_R = 0).
    void allocate(const Patch& patch);
    /// Move to a new patch keeping the values where old and new overlap; new points
    /// get phi = 0 and the tensor copied from the nearest old point (extension).
    void move_to(const Patch& patch);

    Field& phi() { return phi_; }
    const Field& phi() const { return phi_; }
    /// B (solid) or Gs (membrane).
    SymmetricTensorField& tensor() { return tensor_; }
    const SymmetricTensorField& tensor() const { return tensor_; }
    /// Reference mean curvature, only for membranes with bending.
    Field* reference_curvature() { return kappa_r_ ? &*kappa_r_ : nullptr; }
    const Field* reference_curvature() const { return kappa_r_ ? &*kappa_r_ : nullptr; }

    /// The reference map stored as its offset from the position, X(x, t) - x, one field per
    /// direction (membranes with strain_model = reference_map; empty otherwise).
    std::vector<Field>& reference_map() { return refmap_; }
    const std::vector<Field>& reference_map() const { return refmap_; }

    /// Bytes held by this body's fields on this rank.
    std::size_t bytes() const;

  private:
    Field make_field(const std::string& n) const;

    std::string name_;
    BodyKind kind_;
    bool bending_;
    int dim_;
    bool carries_tensor_;
    bool carries_refmap_;
    Patch patch_;
    Field phi_;
    SymmetricTensorField tensor_;
    std::optional<Field> kappa_r_;
    std::vector<Field> refmap_;
};

} // namespace efsi
