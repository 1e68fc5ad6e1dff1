#include "io/checkpoint.hpp"

#include "core/error.hpp"
#include "io/hdf5_file.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cstring>
#include <sstream>

namespace efsi {

namespace fs = std::filesystem;

namespace {
// Fixed dataset names: buffers are swapped between steps, so their own names rotate.
std::string velocity_name(int c) {
    return std::string("velocity_") + "uvw"[c];
}
std::string history_name(int c) {
    return std::string("advection_previous_") + "uvw"[c];
}

/// Version of the checkpoint layout: 2 = per-dataset checksums, case fingerprint and the
/// checksum of the scalar attributes.
// 3 (session 50): a body's datasets hold its stored patch box (attribute "box_lo"), not the
// whole grid; format 2 files (whole-grid datasets) are read as before.
constexpr double format_version = 3;
constexpr double oldest_format = 2;

/// One dataset of a checkpoint: its name, the field it is written from / read into, and the
/// index of the body whose field it is (-1: the flow's, on the whole grid).
struct Dataset {
    std::string name;
    Field* field;
    int body;
};

/// Every dataset of a checkpoint.
std::vector<Dataset> datasets(const FlowState& cs, const std::vector<Body*>& bodies) {
    FlowState& s = const_cast<FlowState&>(cs);
    std::vector<Dataset> out;
    for (int c = 0; c < s.u.dim; ++c) {
        out.push_back({velocity_name(c), &s.u[c], -1});
        out.push_back({history_name(c), &s.adv_prev[c], -1});
    }
    out.push_back({"pressure", &s.p, -1});
    out.push_back({"viscosity", &s.mu, -1});
    for (int q = 0; q < int(bodies.size()); ++q) {
        Body* b = bodies[std::size_t(q)];
        out.push_back({"body_" + b->name() + "_phi", &b->phi(), q});
        for (Field& c : b->tensor().comp)
            out.push_back({"body_" + c.name(), &c, q});
        if (Field* kr = b->reference_curvature()) out.push_back({"body_" + kr->name(), kr, q});
        for (Field& c : b->reference_map())
            out.push_back({"body_" + c.name(), &c, q});
    }
    return out;
}

/// FNV-1a 64 over the scalar attributes (name and value bits, in order) and the
/// fingerprint, so that a flipped bit in the time or a patch box is caught as well.
std::uint64_t attributes_checksum(const std::vector<std::pair<std::string, double>>& attrs,
                                  const std::string& fingerprint) {
    std::uint64_t h = 0xcbf29ce484222325ULL;
    auto add = [&](const void* p, std::size_t n) {
        const auto* b = static_cast<const unsigned char*>(p);
        for (std::size_t i = 0; i < n; ++i) {
            h ^= b[i];
            h *= 0x100000001b3ULL;
        }
    };
    for (const auto& [k, v] : attrs) {
        add(k.data(), k.size());
        add(&v, sizeof v);
    }
    add(fingerprint.data(), fingerprint.size());
    return h;
}

std::string hex(std::uint64_t x) {
    return fmt::format("{:016x}", x);
}

/// The lines of two fingerprints that differ, as "key: checkpoint X, case Y" (at most 4).
std::string fingerprint_difference(const std::string& stored, const std::string& now) {
    auto lines = [](const std::string& t) {
        std::vector<std::pair<std::string, std::string>> v;
        std::istringstream in(t);
        std::string l;
        while (std::getline(in, l)) {
            const auto eq = l.find(" = ");
            v.emplace_back(l.substr(0, eq), eq == std::string::npos ? "" : l.substr(eq + 3));
        }
        return v;
    };
    const auto a = lines(stored), b = lines(now);
    std::string out;
    int shown = 0;
    auto value_of = [](const auto& v, const std::string& key) -> std::string {
        for (const auto& [k, x] : v)
            if (k == key) return x;
        return "(absent)";
    };
    std::vector<std::string> keys;
    for (const auto& [k, x] : a)
        keys.push_back(k);
    for (const auto& [k, x] : b)
        if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
    for (const auto& k : keys) {
        const std::string x = value_of(a, k), y = value_of(b, k);
        if (x == y) continue;
        if (shown++ < 4)
            out +=
                fmt::format("{}{}: checkpoint '{}', case '{}'", out.empty() ? "" : "; ", k, x, y);
    }
    if (shown > 4) out += fmt::format("; and {} more", shown - 4);
    return out;
}

/// The root's groups that hold records (every group but /integrity).
std::vector<std::string> stored_records(const Hdf5File& f) {
    std::vector<std::string> out;
    for (const std::string& g : f.members("", true))
        if (g != "integrity") out.push_back(g);
    return out;
}

/// Refuses a checkpoint that lacks one of `records`, or holds one the case has no use for.
void check_records(const Hdf5File& f, const std::string& at,
                   const std::vector<NamedRecord>& records) {
    const std::vector<std::string> stored = stored_records(f);
    for (const auto& [group, r] : records)
        if (std::find(stored.begin(), stored.end(), group) == stored.end())
            throw InputError(fmt::format(
                "{}: the checkpoint holds no '{}' state ({}), which the case needs: it was "
                "written by a run without it (or by an efsi that did not checkpoint it), and "
                "cannot continue this case",
                at, group, r->description));
    for (const std::string& group : stored) {
        if (std::any_of(records.begin(), records.end(),
                        [&](const NamedRecord& r) { return r.first == group; }))
            continue;
        const std::string what = f.has_string_attribute("description", group)
                                     ? f.read_string_attribute("description", group)
                                     : std::string("no description");
        throw InputError(fmt::format("{}: the checkpoint holds '{}' state ({}), which this case "
                                     "does not have: it was written by a run with it, and a "
                                     "restart would drop it",
                                     at, group, what));
    }
}
} // namespace

void write_checkpoint(const fs::path& file, const Decomposition& dec, const FlowState& s,
                      const RunClock& clock, const std::vector<Body*>& bodies,
                      const std::string& fingerprint, const std::vector<NamedRecord>& records) {
    const fs::path tmp = fs::path(file.string() + ".tmp");
    std::vector<std::pair<std::string, std::uint64_t>> sums;
    try {
        {
            const auto all = datasets(s, bodies);
            // The flow's fields cover the grid; a body's, its patch box (the dataset holds
            // that box only), so the file's size follows the patches.
            auto box_for = [&](const Dataset& d) -> const Box* {
                return d.body < 0 ? nullptr : &bodies[std::size_t(d.body)]->patch().global;
            };
            std::uint64_t bytes = 0;
            for (const Dataset& d : all) {
                const Box* box = box_for(d);
                bytes += 8 * std::uint64_t(box ? std::max<std::int64_t>(0, box->count())
                                               : dec.grid().total_cells());
            }
            for (const auto& [group, r] : records) {
                for (const auto& [name, v] : r->reals)
                    bytes += 8 * v.size();
                for (const auto& [name, v] : r->integers)
                    bytes += 8 * v.size();
            }
            Hdf5File f(tmp, Hdf5File::Mode::Create, dec, bytes);
            for (const Dataset& d : all)
                sums.emplace_back(d.name, f.write_block(d.name, *d.field, box_for(d)));
            for (const auto& [group, r] : records) {
                for (const auto& [name, v] : r->reals)
                    sums.emplace_back(group + "/" + name, f.write_array(group + "/" + name, v));
                for (const auto& [name, v] : r->integers)
                    sums.emplace_back(group + "/" + name, f.write_array(group + "/" + name, v));
                f.write_string_attribute("description", r->description, group);
            }
            std::vector<std::pair<std::string, double>> attrs = {
                {"time", s.time},
                {"step", double(s.step)},
                {"dt_prev", s.dt_prev},
                {"dim", double(dec.dim())},
                {"next_fields_time", clock.next_fields_time},
                {"format", format_version}};
            for (const Body* b : bodies) {
                const std::string base = "body_" + b->name() + "_";
                for (int d = 0; d < 3; ++d) {
                    attrs.emplace_back(base + "lo" + std::to_string(d), b->patch().global.lo[d]);
                    attrs.emplace_back(base + "hi" + std::to_string(d), b->patch().global.hi[d]);
                }
                // The unwidened box the moves are decided on (a restart moves its patches
                // when the run it continues would have).
                for (int d = 0; d < 3; ++d) {
                    attrs.emplace_back(base + "fitted_lo" + std::to_string(d),
                                       b->patch().fitted.lo[d]);
                    attrs.emplace_back(base + "fitted_hi" + std::to_string(d),
                                       b->patch().fitted.hi[d]);
                }
            }
            for (const auto& [k, v] : attrs)
                f.write_attribute(k, v);
            // Strings on group /integrity: the root's attributes stay numbers.
            f.write_string_attribute("case_fingerprint", fingerprint, "integrity");
            f.write_string_attribute("attributes_checksum",
                                     hex(attributes_checksum(attrs, fingerprint)), "integrity");
            f.close();
        }
        // Verify before publishing: reopened, every dataset present and read back to the
        // checksum of the values in memory.
        {
            Hdf5File f(tmp, Hdf5File::Mode::Read, dec);
            const auto all = datasets(s, bodies);
            for (std::size_t q = 0; q < all.size(); ++q) {
                const std::uint64_t back = f.read_checksum(all[q].name, *all[q].field);
                if (back != sums[q].second || f.stored_checksum(all[q].name) != back)
                    throw IoError(fmt::format("{}: dataset '{}' read back differs from what "
                                              "was written",
                                              tmp.string(), all[q].name));
            }
            for (std::size_t q = all.size(); q < sums.size(); ++q) {
                const std::string& name = sums[q].first;
                std::uint64_t back = 0;
                if (f.is_integer(name)) {
                    const std::vector<std::uint64_t> v = f.read_integer_array(name);
                    back = Hdf5File::array_checksum(v.data(), v.size());
                } else {
                    const std::vector<double> v = f.read_real_array(name);
                    back = Hdf5File::array_checksum(v.data(), v.size());
                }
                if (back != sums[q].second)
                    throw IoError(fmt::format("{}: dataset '{}' read back differs from what "
                                              "was written",
                                              tmp.string(), name));
            }
            f.close();
        }
    } catch (const std::exception& e) {
        dec.barrier();
        std::error_code ec;
        if (dec.rank() == 0) fs::remove(tmp, ec);
        const bool kept = fs::exists(file, ec);
        throw IoError(fmt::format(
            "writing the checkpoint at step {} (t = {:.6e} s) failed: {}. The unfinished file "
            "was removed; {}",
            s.step, s.time, e.what(),
            kept ? fmt::format("the last good checkpoint is {} (unchanged)", file.string())
                 : std::string("there is no earlier checkpoint of this run")));
    }
    dec.barrier();
    int failed = 0;
    if (dec.rank() == 0) {
        std::error_code ec;
        fs::rename(tmp, file, ec);
        failed = ec ? ec.value() : 0;
    }
    MPI_Bcast(&failed, 1, MPI_INT, 0, dec.comm());
    if (failed)
        throw IoError(fmt::format("renaming {} to {} failed ({}); the verified checkpoint is "
                                  "{}",
                                  tmp.string(), file.string(), std::strerror(failed),
                                  tmp.string()));
    dec.barrier();
}

void read_checkpoint(const fs::path& file, const Decomposition& dec, FlowState& s, RunClock& clock,
                     const std::vector<Body*>& bodies, const std::string& fingerprint,
                     const std::vector<NamedRecord>& records) {
    const std::string at = "--restart " + file.string();
    if (!fs::exists(file)) throw InputError(at + ": no such checkpoint file");
    try {
        Hdf5File f(file, Hdf5File::Mode::Read, dec);
        if (!f.has_attribute("format") || !f.has_string_attribute("case_fingerprint", "integrity"))
            throw InputError(at + ": not a checkpoint with checksums (written by an efsi "
                                  "older than checkpoint format 2, or not a checkpoint)");
        if (const double v = f.read_attribute("format"); v != format_version && v != oldest_format)
            throw InputError(fmt::format("{}: checkpoint format {} is neither {} nor {}", at, v,
                                         oldest_format, format_version));
        check_records(f, at, records);
        const std::string stored = f.read_string_attribute("case_fingerprint", "integrity");
        if (!fingerprint.empty() && stored != fingerprint)
            throw InputError(fmt::format("{}: the checkpoint was written for another case ({})", at,
                                         fingerprint_difference(stored, fingerprint)));
        if (int(f.read_attribute("dim")) != dec.dim())
            throw InputError(fmt::format("{}: checkpoint is {}D but the case is {}D", at,
                                         int(f.read_attribute("dim")), dec.dim()));
        std::vector<std::pair<std::string, double>> attrs;
        for (const char* k : {"time", "step", "dt_prev", "dim", "next_fields_time", "format"})
            attrs.emplace_back(k, f.read_attribute(k));
        for (Body* b : bodies) {
            const std::string base = "body_" + b->name() + "_";
            for (int d = 0; d < 3; ++d)
                for (const char* side : {"lo", "hi"}) {
                    const std::string k = base + side + std::to_string(d);
                    attrs.emplace_back(k, f.read_attribute(k));
                }
            // Checkpoints before session 38 have no fitted box: the stored one serves.
            if (f.has_attribute(base + "fitted_lo0"))
                for (int d = 0; d < 3; ++d)
                    for (const char* side : {"fitted_lo", "fitted_hi"}) {
                        const std::string k = base + side + std::to_string(d);
                        attrs.emplace_back(k, f.read_attribute(k));
                    }
        }
        // Same order as written: lo0 hi0 lo1 hi1 ...
        if (hex(attributes_checksum(attrs, stored)) !=
            f.read_string_attribute("attributes_checksum", "integrity"))
            throw InputError(at + ": the checkpoint's attributes (time, step, patches) do not "
                                  "match their checksum: the file is corrupted");
        std::vector<Box> written_box; // each body's stored (written) box
        for (Body* b : bodies) {
            const std::string base = "body_" + b->name() + "_";
            Box box;
            for (int d = 0; d < 3; ++d) {
                box.lo[d] = int(f.read_attribute(base + "lo" + std::to_string(d)));
                box.hi[d] = int(f.read_attribute(base + "hi" + std::to_string(d)));
            }
            // The stored (widened) box, widened again for this layout: it holds every value
            // written. The moves follow the stored fitted box. A box stored across the
            // periodic x seam stays so (only a body allowed to cross it has one), on a layout
            // that keeps x whole.
            const int nx = dec.grid().cells[0];
            if ((box.lo[0] < 0 || box.hi[0] > nx) && dec.ranks_per_dim()[0] != 1)
                throw InputError(fmt::format(
                    "{}: body '{}' crosses the periodic x seam in this checkpoint (its patch "
                    "spans x cells {} to {} of {}), which a layout with {} ranks along x cannot "
                    "hold; restart with 1 rank along x (parallel.ranks = [1, ...])",
                    at, b->name(), box.lo[0], box.hi[0], nx, dec.ranks_per_dim()[0]));
            Patch patch = make_patch(box, dec, 2, true);
            if (f.has_attribute(base + "fitted_lo0"))
                for (int d = 0; d < 3; ++d) {
                    patch.fitted.lo[d] =
                        int(f.read_attribute(base + "fitted_lo" + std::to_string(d)));
                    patch.fitted.hi[d] =
                        int(f.read_attribute(base + "fitted_hi" + std::to_string(d)));
                }
            b->allocate(patch);
            written_box.push_back(box);
        }
        // A body's datasets hold its stored box; on this layout its patch may be wider (the
        // widening depends on the layout), so their checksums cover the stored box only.
        for (const Dataset& d : datasets(s, bodies))
            f.read_block(d.name, *d.field, true,
                         d.body < 0 ? nullptr : &written_box[std::size_t(d.body)]);
        for (const auto& [group, r] : records) {
            r->reals.clear();
            r->integers.clear();
            for (const std::string& name : f.members(group, false)) {
                const std::string path = group + "/" + name;
                if (f.is_integer(path))
                    r->integers[name] = f.read_integer_array(path);
                else
                    r->reals[name] = f.read_real_array(path);
            }
        }
        s.time = attrs[0].second;
        s.step = long(attrs[1].second);
        s.dt_prev = attrs[2].second;
        clock.next_fields_time = attrs[4].second;
    } catch (const std::runtime_error& e) {
        // One mention of the file: "--restart FILE: what is wrong".
        std::string m = e.what();
        if (m.rfind("--restart", 0) == 0) throw InputError(m);
        const std::string prefix = file.string() + ": ";
        if (m.rfind(prefix, 0) == 0) m = m.substr(prefix.size());
        throw InputError(at + ": " + m);
    }
}

} // namespace efsi
