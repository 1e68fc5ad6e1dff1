#include "io/field_output.hpp"

#include "core/error.hpp"
#include "io/hdf5_file.hpp"
#include "operators/flow_operators.hpp"

#include <fmt/core.h>

#include <cerrno>
#include <cstring>
#include <fstream>

namespace efsi {

namespace fs = std::filesystem;

namespace {
/// Publish `tmp` as `file` on rank 0 once every rank got there; on a failure anywhere the
/// tmp file is removed and IoError thrown on every rank.
void publish(const Decomposition& dec, const fs::path& tmp, const fs::path& file) {
    int failed = 0;
    if (dec.rank() == 0) {
        std::error_code ec;
        fs::rename(tmp, file, ec);
        failed = ec ? ec.value() : 0;
        if (failed) fs::remove(tmp, ec);
    }
    MPI_Bcast(&failed, 1, MPI_INT, 0, dec.comm());
    if (failed)
        throw IoError(fmt::format("renaming {} to {} failed ({})", tmp.string(), file.string(),
                                  std::strerror(failed)));
}

/// Write an HDF5 file through `body` into `<file>.tmp`, closed and checked, then rename it:
/// a failed write leaves no file behind (and no partial one under the final name).
template <class F>
void write_h5(const Decomposition& dec, const fs::path& file, std::uint64_t bytes, F&& body) {
    const fs::path tmp = file.string() + ".tmp";
    try {
        Hdf5File f(tmp, Hdf5File::Mode::Create, dec, bytes);
        body(f);
        f.close();
    } catch (...) {
        dec.barrier();
        std::error_code ec;
        if (dec.rank() == 0) fs::remove(tmp, ec);
        throw;
    }
    dec.barrier();
    publish(dec, tmp, file);
}

/// Units and centring of the snapshot datasets (stored as their attributes).
std::vector<std::pair<std::string, std::string>> meta(const std::string& units,
                                                      const std::string& centring) {
    return {{"units", units}, {"centring", centring}};
}

/// Write a small text file on rank 0 via a tmp file; IoError (on rank 0) if it failed.
void write_text(const fs::path& file, const std::string& text, bool append) {
    if (append) {
        std::ofstream out(file, std::ios::app);
        out << text;
        out.close();
        if (!out)
            throw IoError(
                fmt::format("{}: write failed ({})", file.string(), std::strerror(errno)));
        return;
    }
    const fs::path tmp = file.string() + ".tmp";
    std::ofstream out(tmp);
    out << text;
    out.close();
    if (!out) {
        const int e = errno;
        std::error_code ec;
        fs::remove(tmp, ec);
        throw IoError(fmt::format("{}: write failed ({})", file.string(), std::strerror(e)));
    }
    fs::rename(tmp, file);
}
} // namespace

FieldOutput::FieldOutput(const fs::path& output_dir, const Decomposition& dec)
    : dir_(output_dir / "fields"), dec_(dec) {
    if (dec.rank() == 0) fs::create_directories(dir_);
    dec.barrier();
    // Keep the snapshots of an earlier part of this run (restart) in the series.
    std::ifstream in(dir_ / "index.txt");
    Entry e;
    while (in >> e.step >> e.time >> e.file)
        index_.push_back(e);
    // The mesh is written with the first snapshot (so that a failure is reported by the
    // run like any other write failure).
    mesh_needed_ = !fs::exists(dir_ / "mesh.h5");
    dec.barrier();
}

void FieldOutput::write_mesh() {
    const GlobalGrid& g = dec_.grid();
    const LocalBlock& b = dec_.block();
    const int dim = g.dim;
    // Nodes: this rank writes its own and, at the high end of the box, the closing layer.
    Int3 nodes{1, 1, 1}, noff = b.offset, ncount{1, 1, 1};
    for (int d = 0; d < dim; ++d) {
        nodes[d] = g.cells[d] + 1;
        ncount[d] = b.cells[d] + (dec_.coords()[d] == dec_.ranks_per_dim()[d] - 1 ? 1 : 0);
    }
    std::vector<double> xyz;
    for (int k = 0; k < ncount[2]; ++k)
        for (int j = 0; j < ncount[1]; ++j)
            for (int i = 0; i < ncount[0]; ++i) {
                const Int3 idx{i, j, k};
                for (int d = 0; d < 3; ++d)
                    xyz.push_back(d < dim ? g.origin[d] + (b.offset[d] + idx[d]) * g.dx(d)
                                          : g.origin[d] + 0.5 * g.dx(d));
            }
    std::vector<std::int64_t> topo;
    auto node = [&](int i, int j, int k) {
        return std::int64_t(i) + std::int64_t(nodes[0]) * (j + std::int64_t(nodes[1]) * k);
    };
    for_each_cell(b.cells, [&](int i, int j, int k) {
        const int I = b.offset[0] + i, J = b.offset[1] + j, K = b.offset[2] + k;
        // VTK / XDMF ordering: counter-clockwise bottom face, then the top face.
        topo.insert(topo.end(),
                    {node(I, J, K), node(I + 1, J, K), node(I + 1, J + 1, K), node(I, J + 1, K)});
        if (dim == 3)
            topo.insert(topo.end(), {node(I, J, K + 1), node(I + 1, J, K + 1),
                                     node(I + 1, J + 1, K + 1), node(I, J + 1, K + 1)});
    });
    std::uint64_t npoints = 1;
    for (int d = 0; d < dim; ++d)
        npoints *= std::uint64_t(nodes[d]);
    const std::uint64_t bytes =
        npoints * 3 * 8 + std::uint64_t(g.total_cells()) * (dim == 3 ? 8 : 4) * 8;
    write_h5(dec_, dir_ / "mesh.h5", bytes, [&](Hdf5File& f) {
        f.write_flat("geometry", nodes, noff, ncount, 3, xyz);
        f.write_dataset_attributes("geometry", meta("m", "node"));
        f.write_flat("topology", g.cells, b.offset, b.cells, dim == 3 ? 8 : 4, topo);
    });
}

void FieldOutput::write(const FlowState& s, const std::vector<const Body*>& bodies) {
    const GlobalGrid& g = dec_.grid();
    const LocalBlock& b = dec_.block();
    const std::string name = fmt::format("fields_{:08d}.h5", s.step);
    if (mesh_needed_) {
        write_mesh();
        mesh_needed_ = false;
    }
    std::vector<std::string> extra;
    // The flow's fields cover the grid; a body's, its patch: stored in deflated chunks
    // (io/hdf5_detail.hpp), the zeros around it take almost nothing and its values do not
    // shrink, so a snapshot's size follows the patches (10 bytes per patch value: the
    // values, the chunks' zeros and their index).
    std::uint64_t bytes = (1 + 3 + std::uint64_t(s.u.dim)) * std::uint64_t(g.total_cells()) * 8;
    for (const Body* body : bodies)
        bytes += (1 + body->tensor().comp.size() + (body->reference_curvature() ? 1 : 0)) *
                 std::uint64_t(std::max<std::int64_t>(0, body->patch().global.count())) * 10;
    write_h5(dec_, dir_ / name, bytes, [&](Hdf5File& f) {
        std::vector<double> p, vel;
        for_each_cell(b.cells, [&](int i, int j, int k) {
            p.push_back(s.p(i, j, k));
            for (int c = 0; c < 3; ++c)
                vel.push_back(c < s.u.dim ? cell_centre_velocity(s.u, c, {i, j, k}) : 0.0);
        });
        f.write_flat("pressure", g.cells, b.offset, b.cells, 1, p);
        f.write_dataset_attributes("pressure", meta("Pa", "cell"));
        f.write_flat("velocity", g.cells, b.offset, b.cells, 3, vel);
        f.write_dataset_attributes("velocity", meta("m/s", "cell"));
        const char* names[3] = {"faces_u", "faces_v", "faces_w"};
        const char* faces[3] = {"x_face", "y_face", "z_face"};
        for (int c = 0; c < s.u.dim; ++c) {
            f.write_block(names[c], s.u[c]);
            f.write_dataset_attributes(names[c], meta("m/s", faces[c]));
        }
        f.write_attribute("time", s.time);
        f.write_integer_attribute("step", s.step);
        for (const Body* body : bodies) {
            auto write_patch_field = [&](const std::string& dataset, const Field& fld,
                                         const std::string& units) {
                std::vector<double> v;
                Box lb = body->patch().local;
                if (body->patch().crosses_seam() && !body->patch().empty()) {
                    // Its indices run past [0, n) along x: written over the whole of x, each
                    // value at its index modulo n, zeros where the patch has no cell (the
                    // dataset's chunks hold those almost for free).
                    const int n = body->patch().seam_period;
                    Box whole = lb;
                    whole.lo[0] = 0;
                    whole.hi[0] = n;
                    std::vector<double> row(std::size_t(n), 0.0);
                    for (int k = whole.lo[2]; k < whole.hi[2]; ++k)
                        for (int j = whole.lo[1]; j < whole.hi[1]; ++j) {
                            std::fill(row.begin(), row.end(), 0.0);
                            for (int i = lb.lo[0]; i < lb.hi[0]; ++i)
                                row[std::size_t(((i % n) + n) % n)] = fld(i, j, k);
                            v.insert(v.end(), row.begin(), row.end());
                        }
                    lb = whole;
                } else if (!body->patch().empty()) {
                    for_each_in(fld.owned(),
                                [&](int i, int j, int k) { v.push_back(fld(i, j, k)); });
                }
                const Int3 off{b.offset[0] + lb.lo[0], b.offset[1] + lb.lo[1],
                               b.offset[2] + lb.lo[2]};
                f.write_flat(dataset, g.cells, off,
                             body->patch().empty() ? Int3{0, 0, 0} : lb.size(), 1, v);
                f.write_dataset_attributes(dataset, meta(units, "cell"));
                extra.push_back(dataset);
            };
            write_patch_field("phi_" + body->name(), body->phi(), "1");
            for (const Field& c : body->tensor().comp)
                write_patch_field(c.name(), c, "1");
            if (const Field* kr = body->reference_curvature())
                write_patch_field(kr->name(), *kr, "1/m");
        }
    });
    extra_names_ = extra;
    index_.push_back({s.step, s.time, name});
    // index.txt and fields.xdmf on rank 0; the outcome is shared so that every rank stops.
    std::string failure;
    if (dec_.rank() == 0) {
        try {
            write_text(dir_ / "index.txt", fmt::format("{} {:.17g} {}\n", s.step, s.time, name),
                       true);
            write_xdmf();
        } catch (const std::exception& e) {
            failure = e.what();
        }
    }
    int failed = failure.empty() ? 0 : 1;
    MPI_Bcast(&failed, 1, MPI_INT, 0, dec_.comm());
    if (failed)
        throw IoError(dec_.rank() == 0 ? failure
                                       : std::string("writing the snapshot index failed"));
}

void FieldOutput::write_xdmf() const {
    const GlobalGrid& g = dec_.grid();
    const long long ncells = g.total_cells();
    long long npoints = 1;
    for (int d = 0; d < g.dim; ++d)
        npoints *= g.cells[d] + 1;
    const int per = g.dim == 3 ? 8 : 4;
    const char* topo = g.dim == 3 ? "Hexahedron" : "Quadrilateral";
    std::string text;
    {
        text += fmt::format("<?xml version=\"1.0\"?>\n<Xdmf Version=\"3.0\" "
                            "xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n<Domain>\n");
        text +=
            fmt::format("<Grid Name=\"mesh\" GridType=\"Uniform\">\n"
                        "  <Topology TopologyType=\"{0}\" NumberOfElements=\"{1}\" "
                        "NodesPerElement=\"{2}\">\n"
                        "    <DataItem Dimensions=\"{1} {2}\" NumberType=\"Int\" Precision=\"8\" "
                        "Format=\"HDF\">mesh.h5:/topology</DataItem>\n  </Topology>\n"
                        "  <Geometry GeometryType=\"XYZ\">\n"
                        "    <DataItem Dimensions=\"{3} 3\" NumberType=\"Float\" Precision=\"8\" "
                        "Format=\"HDF\">mesh.h5:/geometry</DataItem>\n  </Geometry>\n</Grid>\n",
                        topo, ncells, per, npoints);
        text += fmt::format(
            "<Grid Name=\"fields\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
        auto attribute = [&](const std::string& name, const char* type, int ncomp,
                             const std::string& file) {
            const std::string dims =
                ncomp > 1 ? fmt::format("{} {}", ncells, ncomp) : fmt::format("{}", ncells);
            text += fmt::format(
                "    <Attribute Name=\"{0}\" AttributeType=\"{1}\" Center=\"Cell\">\n"
                "      <DataItem Dimensions=\"{2}\" NumberType=\"Float\" Precision=\"8\" "
                "Format=\"HDF\">{3}:/{0}</DataItem>\n    </Attribute>\n",
                name, type, dims, file);
        };
        for (const auto& e : index_) {
            text +=
                fmt::format("  <Grid Name=\"step_{}\" GridType=\"Uniform\">\n"
                            "    <xi:include xpointer=\"xpointer(/Xdmf/Domain/Grid[@Name='mesh']/"
                            "*[self::Topology or self::Geometry])\"/>\n"
                            "    <Time Value=\"{:.17g}\"/>\n",
                            e.step, e.time);
            attribute("pressure", "Scalar", 1, e.file);
            attribute("velocity", "Vector", 3, e.file);
            // Body fields: the same bodies in every snapshot of a run.
            for (const auto& n : extra_names_)
                attribute(n, "Scalar", 1, e.file);
            text += fmt::format("  </Grid>\n");
        }
        text += fmt::format("</Grid>\n</Domain>\n</Xdmf>\n");
    }
    write_text(dir_ / "fields.xdmf", text, false);
    write_image_xdmf();
}

void FieldOutput::write_image_xdmf() const {
    // The same snapshots on the uniform grid as an image (3DCoRectMesh: origin and spacing,
    // no mesh file; a 2D run is one cell thick in z), which ParaView reads as image data.
    // XDMF orders dimensions, origin and spacing slowest first: z, y, x.
    const GlobalGrid& g = dec_.grid();
    const int nx = g.cells[0], ny = g.cells[1], nz = g.cells[2];
    std::string text =
        fmt::format("<?xml version=\"1.0\"?>\n<Xdmf Version=\"3.0\" "
                    "xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n<Domain>\n"
                    "<Grid Name=\"fields\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
    const std::string geometry = fmt::format(
        "    <Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"{} {} {}\"/>\n"
        "    <Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n"
        "      <DataItem Dimensions=\"3\" NumberType=\"Float\" Precision=\"8\" "
        "Format=\"XML\">{:.17g} {:.17g} {:.17g}</DataItem>\n"
        "      <DataItem Dimensions=\"3\" NumberType=\"Float\" Precision=\"8\" "
        "Format=\"XML\">{:.17g} {:.17g} {:.17g}</DataItem>\n    </Geometry>\n",
        nz + 1, ny + 1, nx + 1, g.origin[2], g.origin[1], g.origin[0], g.dx(2), g.dx(1), g.dx(0));
    auto attribute = [&](const std::string& name, const char* type, int ncomp,
                         const std::string& file) {
        const std::string dims = ncomp > 1 ? fmt::format("{} {} {} {}", nz, ny, nx, ncomp)
                                           : fmt::format("{} {} {}", nz, ny, nx);
        text += fmt::format("    <Attribute Name=\"{0}\" AttributeType=\"{1}\" Center=\"Cell\">\n"
                            "      <DataItem Dimensions=\"{2}\" NumberType=\"Float\" "
                            "Precision=\"8\" Format=\"HDF\">{3}:/{0}</DataItem>\n"
                            "    </Attribute>\n",
                            name, type, dims, file);
    };
    for (const auto& e : index_) {
        text += fmt::format("  <Grid Name=\"step_{}\" GridType=\"Uniform\">\n{}"
                            "    <Time Value=\"{:.17g}\"/>\n",
                            e.step, geometry, e.time);
        attribute("pressure", "Scalar", 1, e.file);
        attribute("velocity", "Vector", 3, e.file);
        for (const auto& n : extra_names_)
            attribute(n, "Scalar", 1, e.file);
        text += "  </Grid>\n";
    }
    text += "</Grid>\n</Domain>\n</Xdmf>\n";
    write_text(dir_ / "fields_image.xdmf", text, false);
}

} // namespace efsi
