#include "io/checkpoint.hpp"

#include "core/error.hpp"
#include "io/hdf5_file.hpp"

#include <fmt/core.h>

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
} // namespace

void write_checkpoint(const fs::path& file, const Decomposition& dec, const FlowState& s,
                      const RunClock& clock, const std::vector<Body*>& bodies) {
    const fs::path tmp = fs::path(file.string() + ".tmp");
    {
        Hdf5File f(tmp, Hdf5File::Mode::Create, dec);
        for (int c = 0; c < s.u.dim; ++c) {
            f.write_block(velocity_name(c), s.u[c]);
            f.write_block(history_name(c), s.adv_prev[c]);
        }
        f.write_block("pressure", s.p);
        f.write_block("viscosity", s.mu);
        f.write_attribute("time", s.time);
        f.write_attribute("step", double(s.step));
        f.write_attribute("dt_prev", s.dt_prev);
        f.write_attribute("dim", dec.dim());
        f.write_attribute("next_fields_time", clock.next_fields_time);
        for (const Body* b : bodies) {
            const std::string base = "body_" + b->name() + "_";
            for (int d = 0; d < 3; ++d) {
                f.write_attribute(base + "lo" + std::to_string(d), b->patch().global.lo[d]);
                f.write_attribute(base + "hi" + std::to_string(d), b->patch().global.hi[d]);
            }
            f.write_block(base + "phi", b->phi());
            for (const Field& c : b->tensor().comp)
                f.write_block("body_" + c.name(), c);
            if (const Field* kr = b->reference_curvature())
                f.write_block("body_" + kr->name(), *kr);
        }
    }
    dec.barrier();
    if (dec.rank() == 0) fs::rename(tmp, file);
    dec.barrier();
}

void read_checkpoint(const fs::path& file, const Decomposition& dec, FlowState& s, RunClock& clock,
                     const std::vector<Body*>& bodies) {
    if (!fs::exists(file))
        throw InputError(fmt::format("--restart {}: no such checkpoint file", file.string()));
    Hdf5File f(file, Hdf5File::Mode::Read, dec);
    if (int(f.read_attribute("dim")) != dec.dim())
        throw InputError(fmt::format("--restart {}: checkpoint is {}D but the case is {}D",
                                     file.string(), int(f.read_attribute("dim")), dec.dim()));
    for (int c = 0; c < s.u.dim; ++c) {
        f.read_block(velocity_name(c), s.u[c]);
        f.read_block(history_name(c), s.adv_prev[c]);
    }
    f.read_block("pressure", s.p);
    f.read_block("viscosity", s.mu);
    s.time = f.read_attribute("time");
    s.step = long(f.read_attribute("step"));
    s.dt_prev = f.read_attribute("dt_prev");
    clock.next_fields_time = f.read_attribute("next_fields_time");
    for (Body* b : bodies) {
        const std::string base = "body_" + b->name() + "_";
        Box box;
        for (int d = 0; d < 3; ++d) {
            box.lo[d] = int(f.read_attribute(base + "lo" + std::to_string(d)));
            box.hi[d] = int(f.read_attribute(base + "hi" + std::to_string(d)));
        }
        b->allocate(make_patch(box, dec));
        f.read_block(base + "phi", b->phi());
        for (Field& c : b->tensor().comp)
            f.read_block("body_" + c.name(), c);
        if (Field* kr = b->reference_curvature()) f.read_block("body_" + kr->name(), *kr);
    }
}

} // namespace efsi
