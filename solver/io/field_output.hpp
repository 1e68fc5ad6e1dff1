// Field snapshots: one parallel-HDF5 file per snapshot under <output>/fields/, the mesh
// once in mesh.h5, and fields.xdmf (XDMF 3, temporal collection) that ParaView opens and
// meshio's TimeSeriesReader reads. The mesh is written as explicit hexahedra
// (quadrilaterals in 2D) because meshio reads only unstructured topologies.
//
// Each snapshot holds cell-centred `pressure` and `velocity` (3 components; w = 0 in
// 2D), the raw staggered components `faces/u`, `faces/v` (`faces/w`) as [nz][ny][nx]
// arrays (index i is the low face of cell i), and attributes `time` and `step`.
#pragma once

#include "parallel/decomposition.hpp"
#include "time/flow_state.hpp"

#include <filesystem>
#include <vector>

namespace efsi {

class FieldOutput {
  public:
    FieldOutput(const std::filesystem::path& output_dir, const Decomposition& dec);
    /// Write a snapshot (collective). Extra cell fields can be added by later physics.
    void write(const FlowState& s);
    int count() const { return int(index_.size()); }

  private:
    void write_mesh();
    void write_xdmf() const;

    std::filesystem::path dir_;
    const Decomposition& dec_;
    struct Entry {
        long step;
        double time;
        std::string file;
    };
    std::vector<Entry> index_;
};

} // namespace efsi
