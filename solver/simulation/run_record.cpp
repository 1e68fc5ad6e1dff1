#include "simulation/run_record.hpp"

#include "core/error.hpp"
#include "core/version.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <fstream>

namespace efsi {

namespace fs = std::filesystem;

namespace {

nlohmann::json to_json(const Diagnostics& d) {
    return {{"step", d.step},
            {"time", d.time},
            {"dt", d.dt},
            {"max_divergence", d.max_divergence},
            {"kinetic_energy", d.kinetic_energy},
            {"max_speed", d.max_speed},
            {"cfl", d.cfl},
            {"pressure_iterations", d.pressure_iterations},
            {"pressure_residual", d.pressure_residual},
            {"viscous_iterations", d.viscous_iterations}};
}

nlohmann::json to_json(const BodyDiagnostics& b) {
    return {{"name", b.name},
            {"volume", b.volume},
            {"centroid", b.centroid},
            {"phi_min", b.phi_min},
            {"phi_max", b.phi_max},
            {"patch_cells", b.patch_cells},
            {"bytes", b.bytes},
            {"area", b.area},
            {"taylor_deformation", b.taylor_deformation},
            {"inclination_over_pi", b.inclination_over_pi},
            {"tensor_trace_max", b.tensor_trace_max},
            {"reference_area", b.reference_area}};
}

nlohmann::json to_json(const SeedingReport& sr) {
    nlohmann::json placed = nlohmann::json::object();
    for (const auto& [name, count] : sr.placed)
        placed[name] = count;
    return {{"seed", sr.seed},
            {"vessel", sr.vessel},
            {"fill_kind", sr.fill_kind},
            {"target_haematocrit", sr.target},
            {"achieved_haematocrit", sr.achieved},
            {"lumen_volume", sr.lumen_volume},
            {"gap", sr.gap},
            {"candidates", sr.candidates},
            {"shake_sweeps", sr.shake_sweeps},
            {"placed", placed},
            {"message", sr.message}};
}

} // namespace

void drop_rows_after(const fs::path& file, double t, const std::string& header) {
    std::ifstream in(file);
    if (!in) return;
    std::string line, kept, pad;
    bool first = true;
    while (std::getline(in, line)) {
        if (first) {
            first = false;
            // An older header that the current one extends: upgrade it, pad the rows.
            if (!header.empty() && header.size() > line.size() &&
                header.compare(0, line.size(), line) == 0 && header[line.size()] == ',') {
                for (std::size_t i = line.size(); i < header.size(); ++i)
                    if (header[i] == ',') pad += ",nan";
                line = header;
            }
            kept += line + "\n";
            continue;
        }
        const auto a = line.find(',');
        const auto b = a == std::string::npos ? a : line.find(',', a + 1);
        if (b != std::string::npos &&
            std::stod(line.substr(a + 1, b - a - 1)) > t + 1e-12 * std::max(1.0, std::abs(t)))
            continue;
        kept += line + pad + "\n";
    }
    in.close();
    std::ofstream(file) << kept;
}

const char* bodies_csv_header() {
    return "step,time,body,volume,centroid_x,centroid_y,centroid_z,phi_min,phi_max,"
           "clipped_volume,patch_cells,bytes,area,taylor_deformation,inclination_over_pi,"
           "tensor_trace_max,reference_area,taylor_deformation_sharp";
}

bool append_body_rows(const fs::path& file, long step, real time,
                      const std::vector<BodyDiagnostics>& bodies) {
    std::ofstream out(file, std::ios::app);
    for (const BodyDiagnostics& b : bodies)
        out << fmt::format("{},{:.10e},{},{:.12e},{:.10e},{:.10e},{:.10e},{:.6e},"
                           "{:.6e},{:.3e},{},{},{:.10e},{:.8e},{:.8e},{:.8e},{:.10e},{:.8e}\n",
                           step, time, b.name, b.volume, b.centroid[0], b.centroid[1],
                           b.centroid[2], b.phi_min, b.phi_max, b.clipped_volume, b.patch_cells,
                           b.bytes, b.area, b.taylor_deformation, b.inclination_over_pi,
                           b.tensor_trace_max, b.reference_area, b.taylor_deformation_sharp);
    out.close();
    return static_cast<bool>(out);
}

std::vector<double> machine_load() {
    std::ifstream in("/proc/loadavg");
    std::vector<double> v(3);
    if (!(in >> v[0] >> v[1] >> v[2])) return {};
    return v;
}

StageSpread stage_spread(const Decomposition& dec, const std::map<std::string, double>& mine) {
    // One reduction: each stage's seconds and their negatives (max of -t = -min), and the
    // count of stage names with a hash of them, so that ranks whose stages differ (none
    // should) give no spread rather than a wrong one.
    if (dec.size() == 1) return {};
    std::uint64_t h = 1469598103934665603ULL;
    for (const auto& [k, v] : mine)
        for (const char c : k)
            h = (h ^ std::uint64_t(static_cast<unsigned char>(c))) * 1099511628211ULL;
    const real tag = real(h >> 12); // exact in a double
    std::vector<real> x;
    for (const auto& [k, v] : mine) {
        x.push_back(v);
        x.push_back(-v);
    }
    x.insert(x.end(), {real(mine.size()), -real(mine.size()), tag, -tag});
    dec.max_in_place(x);
    const std::size_t n = mine.size();
    if (x[2 * n] != -x[2 * n + 1] || x[2 * n + 2] != -x[2 * n + 3]) return {};
    StageSpread out;
    std::size_t q = 0;
    for (const auto& [k, v] : mine) {
        out[k] = {-x[2 * q + 1], x[2 * q]};
        ++q;
    }
    return out;
}

void write_summary_json(const fs::path& file, const RunSummary& run) {
    const Config& cfg = run.cfg;
    nlohmann::json j;
    j["case"] = cfg.name;
    j["status"] = run.status;
    j["message"] = run.message;
    j["efsi_commit"] = build_commit();
    j["ranks"] = run.dec.size();
    j["load_before"] = run.load_before;
    j["load_after"] = machine_load();
    j["ranks_per_dim"] = run.dec.ranks_per_dim();
    j["cells"] = cfg.grid.total_cells();
    j["grid"] = cfg.grid.cells;
    j["dim"] = cfg.grid.dim;
    j["steps"] = run.steps;
    j["final_step"] = run.state.step;
    j["time"] = run.state.time;
    j["wall_seconds"] = run.wall_seconds;
    j["cell_updates_per_second"] =
        double(cfg.grid.total_cells()) * run.steps / std::max(run.wall_seconds, 1e-9);
    j["peak_rss_bytes_max_rank"] = run.memory.max_rank_bytes;
    j["peak_rss_bytes_sum"] = run.memory.sum_bytes;
    j["seam_copy_bytes_max_rank"] = run.seam_copy_bytes_max_rank;
    nlohmann::json stages;
    for (const auto& [k, v] : run.stage_seconds)
        stages[k] = v;
    j["stages"] = stages;
    if (!run.stage_spread.empty()) {
        nlohmann::json lo, hi;
        for (const auto& [k, v] : run.stage_spread) {
            lo[k] = v[0];
            hi[k] = v[1];
        }
        j["stages_rank_min"] = lo;
        j["stages_rank_max"] = hi;
    }
    j["linear_solvers"] = run.linear_solvers;
    // The bodies' named explicit limits and the limit that set the last step's dt.
    nlohmann::json limits = nlohmann::json::object();
    for (const TimeStepLimit& l : run.body_limits)
        limits[l.name] = l.dt;
    if (std::isfinite(run.adhesion_limit)) limits["adhesion"] = run.adhesion_limit;
    j["time_step_limits"] = limits;
    j["limited_by"] = run.limited_by;
    j["final"] = to_json(run.last);
    j["restarted_from"] = run.restarted_from.string();
    nlohmann::json bodies = nlohmann::json::array();
    for (const BodyDiagnostics& b : run.bodies)
        bodies.push_back(to_json(b));
    j["bodies"] = bodies;
    if (!run.adhesion.is_null()) j["adhesion"] = run.adhesion;
    if (cfg.seeding.used) j["seeding"] = to_json(cfg.seeding);
    const fs::path tmp = file.string() + ".tmp";
    {
        std::ofstream out(tmp);
        out << j.dump(2) << "\n";
        out.close();
        if (!out) {
            std::error_code ec;
            fs::remove(tmp, ec);
            throw IoError(fmt::format("{}: write failed", file.string()));
        }
    }
    fs::rename(tmp, file);
}

} // namespace efsi
