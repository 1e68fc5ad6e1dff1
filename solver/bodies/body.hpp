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

namespace efsi {

class Body {
  public:
    /// `carries_tensor` false makes a passive body: phi only (a tracer of the flow).
    Body(std::string name, BodyKind kind, bool bending, int dim, bool carries_tensor = true);

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

    /// Bytes held by this body's fields on this rank.
    std::size_t bytes() const;

  private:
    Field make_field(const std::string& n) const;

    std::string name_;
    BodyKind kind_;
    bool bending_;
    int dim_;
    bool carries_tensor_;
    Patch patch_;
    Field phi_;
    SymmetricTensorField tensor_;
    std::optional<Field> kappa_r_;
};

} // namespace efsi
