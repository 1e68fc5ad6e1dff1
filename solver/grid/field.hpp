// A field owns its values on a rank's block plus halo cells and knows its location.
//
// Indices are signed and block-local: (0,0,0) is the first owned point of the rank's
// block, -1 is the first halo layer. A field may instead cover only a sub-box of the
// block (a body's patch, `Field::on_patch`): it is indexed with the same block-local
// indices, so one pointwise kernel serves a dense sweep and a sweep over a patch; only
// [begin, begin + cells) plus halos is stored.
// In 2D (dim == 2) there is no z halo, so k is always 0 and nothing is stored twice.
#pragma once

#include "core/types.hpp"
#include "grid/box.hpp"
#include "grid/grid.hpp"

#include <cassert>
#include <limits>
#include <string>
#include <vector>

namespace efsi {

/// A field's values. (Huge pages for fields were measured and not kept: the d/16 capsule's
/// body stages came out 15-48 % slower with them; docs/method.md, "Huge pages".)
using FieldStorage = std::vector<real>;

class Field {
  public:
    Field() = default;
    Field(std::string name, Location loc, const LocalBlock& block, int dim, int halo = 2)
        : Field(std::move(name), loc, Int3{0, 0, 0}, block.cells, dim, halo) {}

    /// A field over the sub-box [begin, begin + cells) of the block (block-local indices).
    static Field on_patch(std::string name, Location loc, const Int3& begin, const Int3& cells,
                          int dim, int halo = 2) {
        return Field(std::move(name), loc, begin, cells, dim, halo);
    }

    Field(std::string name, Location loc, const Int3& begin, const Int3& cells, int dim, int halo)
        : Field(std::move(name), loc, begin, cells, dim, Int3{halo, halo, halo}) {}

    /// Halos of their own width per direction (none past dim).
    Field(std::string name, Location loc, const Int3& begin, const Int3& cells, int dim,
          const Int3& halo)
        : name_(std::move(name)), loc_(loc), begin_(begin), cells_(cells) {
        for (int d = 0; d < 3; ++d) {
            halo_[d] = (d < dim) ? halo[d] : 0;
            ext_[d] = cells_[d] + 2 * halo_[d];
        }
        stride_ = {1, std::size_t(ext_[0]), std::size_t(ext_[0]) * std::size_t(ext_[1])};
#ifdef EFSI_NAN_FILL
        const real init = std::numeric_limits<real>::quiet_NaN();
#else
        const real init = 0;
#endif
        data_.assign(std::size_t(ext_[0]) * ext_[1] * ext_[2], init);
    }

    real& operator()(int i, int j, int k) {
        return data_[index(i, j, k)];
    }
    real operator()(int i, int j, int k) const {
        return data_[index(i, j, k)];
    }
    real& operator()(const Int3& p) {
        return data_[index(p[0], p[1], p[2])];
    }
    real operator()(const Int3& p) const {
        return data_[index(p[0], p[1], p[2])];
    }

    std::size_t index(int i, int j, int k) const {
        i -= begin_[0];
        j -= begin_[1];
        k -= begin_[2];
        assert(i >= -halo_[0] && i < cells_[0] + halo_[0]);
        assert(j >= -halo_[1] && j < cells_[1] + halo_[1]);
        assert(k >= -halo_[2] && k < cells_[2] + halo_[2]);
        return std::size_t(i + halo_[0]) + std::size_t(j + halo_[1]) * stride_[1] +
               std::size_t(k + halo_[2]) * stride_[2];
    }

    const std::string& name() const {
        return name_;
    }
    Location location() const {
        return loc_;
    }
    /// Number of owned points per direction.
    const Int3& cells() const {
        return cells_;
    }
    /// The owned points as a box of block-local indices.
    Box owned() const {
        return Box{begin_, {begin_[0] + cells_[0], begin_[1] + cells_[1], begin_[2] + cells_[2]}};
    }
    /// Block-local index of the first owned point (0 for a whole-block field).
    const Int3& begin() const {
        return begin_;
    }
    const Int3& halo() const {
        return halo_;
    }
    const Int3& extent() const {
        return ext_;
    }
    FieldStorage& data() {
        return data_;
    }
    const FieldStorage& data() const {
        return data_;
    }

    void fill(real v) {
        data_.assign(data_.size(), v);
    }

  private:
    std::string name_;
    Location loc_ = Location::Cell;
    Int3 begin_{0, 0, 0};
    Int3 cells_{0, 0, 0};
    Int3 halo_{0, 0, 0};
    Int3 ext_{0, 0, 0};
    std::array<std::size_t, 3> stride_{0, 0, 0};
    FieldStorage data_;
};

/// Staggered velocity: component d lives on the faces normal to d. Only `dim`
/// components exist, so a 2D run carries no w.
struct VelocityField {
    std::array<Field, 3> comp;
    int dim = 3;

    VelocityField() = default;
    VelocityField(const std::string& name, const LocalBlock& block, int dim_, int halo = 2)
        : dim(dim_) {
        const char* axes = "uvw";
        for (int d = 0; d < dim; ++d)
            comp[d] = Field(name + "_" + axes[d], face_location(d), block, dim, halo);
    }
    Field& operator[](int d) { return comp[d]; }
    const Field& operator[](int d) const { return comp[d]; }
};

/// Loop over the owned points of a block: f(i,j,k).
template <class F>
inline void for_each_cell(const Int3& n, F&& f) {
    for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
            for (int i = 0; i < n[0]; ++i)
                f(i, j, k);
}

} // namespace efsi
