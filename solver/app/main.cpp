// efsi: command-line entry point. Parses, builds, runs; nothing else.
#include "config/config.hpp"
#include "core/error.hpp"
#include "core/version.hpp"
#include "io/hdf5_file.hpp"
#include "linear/structured_solver.hpp"
#include "parallel/decomposition.hpp"
#include "simulation/run_estimate.hpp"
#include "simulation/simulation.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <mpi.h>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace fs = std::filesystem;
using namespace efsi;

namespace {

/// A command-line mistake CLI11 does not describe well enough itself.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

Overrides parse_sets(const std::vector<std::string>& sets) {
    Overrides o;
    for (const auto& s : sets) {
        const auto eq = s.find('=');
        if (eq == std::string::npos || eq == 0)
            throw InputError(fmt::format("--set '{}': expected section.key=value", s));
        o.emplace_back(s.substr(0, eq), s.substr(eq + 1));
    }
    return o;
}

/// A first word that is not an option must be one of the commands; CLI11 would only say
/// that a subcommand is required, without naming the word.
void check_command(int argc, char** argv) {
    if (argc < 2) return;
    const std::string w = argv[1];
    if (w.empty() || w[0] == '-') return;
    for (const char* c : {"run", "check", "keys"})
        if (w == c) return;
    throw UsageError(fmt::format("unknown command '{}' (the commands are run, check and keys)", w));
}

/// --output must be a folder (or not exist yet): checked before anything is allocated.
void check_output_dir(const fs::path& dir) {
    std::error_code ec;
    const auto st = fs::status(dir, ec);
    if (fs::exists(st) && !fs::is_directory(st))
        throw InputError(fmt::format("--output {}: exists and is not a folder", dir.string()));
}

/// A grid that cannot be allocated is refused before anything is: at least 25 doubles per
/// cell (fields, solver work arrays, hypre) against the machine's memory and this process's
/// address-space limit (ulimit -v), per rank.
void check_memory(const Config& cfg, int ranks) {
    const double bytes_per_cell = 200; // a lower bound: the flow fields alone
    const double cells = double(cfg.grid.total_cells());
    const double per_rank = bytes_per_cell * cells / ranks;
    double limit = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE)) / ranks;
    struct rlimit rl {};
    if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY)
        limit = std::min(limit, double(rl.rlim_cur));
    if (per_rank > limit)
        throw InputError(fmt::format(
            "grid.cells = [{}, {}, {}]: {:.3g} cells need at least {:.3g} GB per rank on {} "
            "rank(s), more than the {:.3g} GB available",
            cfg.grid.cells[0], cfg.grid.cells[1], cfg.grid.cells[2], cells, per_rank / 1e9, ranks,
            limit / 1e9));
}

void check_restart_file(const fs::path& file) {
    std::error_code ec;
    const auto st = fs::status(file, ec);
    if (!fs::exists(st))
        throw InputError(fmt::format("--restart {}: no such checkpoint file", file.string()));
    if (!fs::is_regular_file(st))
        throw InputError(fmt::format("--restart {}: not a regular file", file.string()));
}

} // namespace

int main(int argc, char** argv) {
    // Open MPI 4.1's default MPI-IO component (ompio) intermittently drops whole blocks of
    // collective HDF5 writes (seen on 4 ranks: half of a checkpoint dataset left at zero);
    // ROMIO does not. Prefer ROMIO unless the user chose a component.
    setenv("OMPI_MCA_io", "romio321", 0);
    // A file-size limit (ulimit -f) makes writes fail with EFBIG, reported as an I/O error
    // (exit 3, the last good checkpoint kept), instead of killing the run with SIGXFSZ.
    std::signal(SIGXFSZ, SIG_IGN);
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    int code = 0;
    {
        LinearAlgebraScope linear_algebra;
        CLI::App app{"efsi: full Eulerian fluid-structure and fluid-membrane solver"};
        app.set_version_flag("--version", std::string("efsi ") + EFSI_VERSION + " (commit " +
                                              build_commit() + ")");
        app.require_subcommand(1);

        std::string case_path, output, restart;
        std::vector<std::string> sets;
        bool quiet = false;
        auto* run = app.add_subcommand("run", "run a case");
        run->add_option("case", case_path, "case folder (with case.toml) or .toml file")
            ->required();
        run->add_option("--set", sets, "override a case key: section.key=value (repeatable)");
        run->add_option("--output,-o", output, "output folder (default: out/<case name>)");
        run->add_option("--restart", restart, "continue from this checkpoint file");
        run->add_flag("--quiet,-q", quiet, "no progress lines");

        auto* check =
            app.add_subcommand("check", "validate a case and print the resolved configuration");
        check->add_option("case", case_path, "case folder or .toml file")->required();
        check->add_option("--set", sets, "override a case key: section.key=value (repeatable)");
        int estimate_ranks = 0;
        check
            ->add_option("--ranks", estimate_ranks,
                         "estimate memory per rank and cost for this many ranks (default: the "
                         "ranks it runs on)")
            ->check(CLI::Range(1, 1 << 20));

        auto* keys = app.add_subcommand("keys", "print the table of every case key (Markdown)");

        try {
            check_command(argc, argv);
            app.parse(argc, argv);
            if (*keys) {
                if (rank == 0) std::cout << case_reference_markdown();
            } else {
                const Config cfg = load_case(case_path, parse_sets(sets));
                // The rank count is checked against the grid before anything is allocated.
                Decomposition::choose_ranks(size, cfg.grid, cfg.ranks);
                check_memory(cfg, size);
                if (*check) {
                    const int n = estimate_ranks > 0 ? estimate_ranks : size;
                    if (rank == 0) {
                        std::cout << fmt::format(
                                         "# case '{}' is valid ({}D, {} cells, {} rank(s))\n",
                                         cfg.name, cfg.grid.dim, cfg.grid.total_cells(), size)
                                  << describe(estimate_run(cfg, n), cfg, n);
                        for (const BodyConfig& b : cfg.bodies)
                            if (!b.mask_mapping.empty())
                                std::cout
                                    << fmt::format("# body '{}': {}\n", b.name, b.mask_mapping);
                        std::cout << cfg.resolved_toml << "\n";
                    }
                } else {
                    RunOptions opt;
                    opt.output_dir = output.empty() ? fs::path("out") / cfg.name : fs::path(output);
                    check_output_dir(opt.output_dir);
                    if (!restart.empty()) check_restart_file(restart);
                    opt.restart_file = restart;
                    opt.quiet = quiet;
                    Simulation sim(cfg, opt, MPI_COMM_WORLD);
                    code = sim.run();
                }
            }
        } catch (const CLI::ParseError& e) {
            // --help and --version exit 0; every usage error exits 2 naming what is wrong.
            if (e.get_exit_code() == 0) {
                code = rank == 0 ? app.exit(e) : 0;
            } else {
                if (rank == 0)
                    std::cerr << "efsi: usage error: " << e.what() << " (efsi --help)" << std::endl;
                code = 2;
            }
        } catch (const UsageError& e) {
            if (rank == 0)
                std::cerr << "efsi: usage error: " << e.what() << " (efsi --help)" << std::endl;
            code = 2;
        } catch (const InputError& e) {
            if (rank == 0) std::cerr << "efsi: input error: " << e.what() << std::endl;
            code = 2;
        } catch (const IoError& e) {
            if (rank == 0) std::cerr << "efsi: I/O error: " << e.what() << std::endl;
            code = 3;
        } catch (const std::exception& e) {
            if (rank == 0) std::cerr << "efsi: error: " << e.what() << std::endl;
            code = 1;
        }
    }
    if (hdf5_state_broken) {
        // HDF5 could not close a file after a write error; tearing it down at MPI_Finalize
        // would crash. Everything this run writes is written: leave without it.
        std::cout.flush();
        std::cerr.flush();
        MPI_Barrier(MPI_COMM_WORLD);
        std::_Exit(code);
    }
    MPI_Finalize();
    return code;
}
