#include "bodies/body.hpp"

#include <algorithm>
#include <cstdlib>
#include <vector>

namespace efsi {

Body::Body(std::string name, BodyKind kind, bool bending, int dim, bool carries_tensor,
           bool reference_map)
    : name_(std::move(name)), kind_(kind), bending_(bending), dim_(dim),
      carries_tensor_(carries_tensor), carries_refmap_(reference_map) {
    tensor_.dim = dim;
}

Field Body::make_field(const std::string& n) const {
    return Field::on_patch(name_ + "_" + n, Location::Cell, patch_.local.lo, patch_.local.size(),
                           dim_);
}

void Body::allocate(const Patch& patch) {
    patch_ = patch;
    phi_ = make_field("phi");
    phi_.fill(0);
    const std::string base = kind_ == BodyKind::Membrane ? "Gs" : "B";
    tensor_.comp.clear();
    for (int s = 0; carries_tensor_ && s < SymmetricTensorField::count(dim_); ++s) {
        tensor_.comp.push_back(make_field(SymmetricTensorField::component_name(base, s, dim_)));
        // Identity on the diagonal: the undeformed state (for Gs, its extension off the band).
        const bool diagonal = s < dim_;
        tensor_.comp.back().fill(diagonal ? 1.0 : 0.0);
    }
    if (kind_ == BodyKind::Membrane && bending_) {
        kappa_r_ = make_field("kappa_R");
        kappa_r_->fill(0);
    } else {
        kappa_r_.reset();
    }
    refmap_.clear();
    for (int d = 0; carries_refmap_ && d < dim_; ++d) {
        refmap_.push_back(make_field(std::string("refmap_") + "xyz"[d]));
        refmap_.back().fill(0); // X = x: the undeformed state
    }
}

void Body::move_to(const Patch& patch) {
    const Patch old_patch = patch_;
    Field old_phi = std::move(phi_);
    std::vector<Field> old_tensor = std::move(tensor_.comp);
    std::optional<Field> old_kappa = std::move(kappa_r_);
    std::vector<Field> old_refmap = std::move(refmap_);
    allocate(patch);
    if (old_patch.empty() || patch_.empty()) return;
    const Box& ob = old_patch.local;
    const Box& nb = patch_.local;
    // Every new owned point takes the value of the nearest old owned point: exact where
    // they overlap, a zero-gradient extension elsewhere (phi is ~0 there by the margin).
    // Across the periodic x seam (either box crossing it) an x index and its images a period
    // apart are the same cells: each new x takes the image that lies in the old box, or the
    // nearest one.
    const int period = std::max(old_patch.seam_period, patch_.seam_period);
    const int nx = nb.hi[0] - nb.lo[0];
    std::vector<int> from_x(std::size_t(std::max(0, nx)));
    std::vector<char> inside_x(from_x.size());
    for (int i = nb.lo[0]; i < nb.hi[0]; ++i) {
        int best = std::clamp(i, ob.lo[0], ob.hi[0] - 1), dist = std::abs(best - i);
        for (const int image : {i - period, i + period}) {
            if (period == 0) break;
            const int c = std::clamp(image, ob.lo[0], ob.hi[0] - 1);
            if (std::abs(c - image) < dist) {
                best = c;
                dist = std::abs(c - image);
            }
        }
        from_x[std::size_t(i - nb.lo[0])] = best;
        inside_x[std::size_t(i - nb.lo[0])] = dist == 0;
    }
    auto nearest = [&](int i, int j, int k) {
        Int3 q{from_x[std::size_t(i - nb.lo[0])], j, k};
        for (int d = 1; d < 3; ++d)
            q[d] = std::clamp(q[d], ob.lo[d], ob.hi[d] - 1);
        return q;
    };
    for_each_in(patch_.local, [&](int i, int j, int k) {
        const Int3 p{i, j, k};
        const Int3 q = nearest(i, j, k);
        const bool inside = inside_x[std::size_t(i - nb.lo[0])] && q[1] == j && q[2] == k;
        phi_(p) = inside ? old_phi(q) : 0.0;
        for (std::size_t s = 0; s < old_tensor.size(); ++s)
            tensor_.comp[s](p) = old_tensor[s](q);
        if (kappa_r_ && old_kappa) (*kappa_r_)(p) = (*old_kappa)(q);
        for (std::size_t d = 0; d < std::min(refmap_.size(), old_refmap.size()); ++d)
            refmap_[d](p) = old_refmap[d](q);
    });
}

std::size_t Body::bytes() const {
    std::size_t n = phi_.data().size();
    for (const auto& c : tensor_.comp)
        n += c.data().size();
    if (kappa_r_) n += kappa_r_->data().size();
    for (const auto& c : refmap_)
        n += c.data().size();
    return n * sizeof(real);
}

} // namespace efsi
