// Field snapshots: one parallel-HDF5 file per snapshot under <output>/fields/, the mesh
// once in mesh.h5, and fields.xdmf (XDMF 3, temporal collection) that ParaView opens and
// meshio's TimeSeriesReader reads. The mesh is written as explicit hexahedra
// (quadrilaterals in 2D) because meshio reads only unstructured topologies (meshio 5 has
// no 2DCoRectMesh / 3DCoRectMesh). fields_image.xdmf holds the same snapshots on a
// 3DCoRectMesh (origin and spacing; 2D runs one cell thick in z), which ParaView's XDMF
// readers open as image data.
//
// Each snapshot holds cell-centred `pressure` and `velocity` (3 components; w = 0 in
// 2D), the raw staggered components `faces_u`, `faces_v` (`faces_w`) as [nz][ny][nx]
// arrays (index i is the low face of cell i), attributes `time` (float) and `step`
// (integer), and for each body its phi and tensor components. Every dataset carries the
// string attributes `units` and `centring` (cell, node, x_face, y_face, z_face).
//
// Every file is written to `<name>.tmp` and renamed once complete; a failed write (disk
// full) removes the tmp file and throws IoError on every rank.
#pragma once

#include "bodies/body.hpp"
#include "parallel/decomposition.hpp"
#include "time/flow_state.hpp"

#include <filesystem>
#include <vector>

namespace efsi {

class FieldOutput {
  public:
    FieldOutput(const std::filesystem::path& output_dir, const Decomposition& dec);
    /// Write a snapshot (collective), with each body's phi and tensor components as cell
    /// data `phi_<body>`, `<body>_<component>` (zero outside the body's patch).
    void write(const FlowState& s, const std::vector<const Body*>& bodies = {});
    int count() const { return int(index_.size()); }

  private:
    void write_mesh();
    void write_xdmf() const;
    void write_image_xdmf() const;

    std::filesystem::path dir_;
    const Decomposition& dec_;
    struct Entry {
        long step;
        double time;
        std::string file;
    };
    std::vector<std::string> extra_names_; ///< cell fields of bodies, in every snapshot
    std::vector<Entry> index_;
    bool mesh_needed_ = false;
};

} // namespace efsi
