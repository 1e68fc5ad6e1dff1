// efsi: command-line entry point. Parses, builds, runs; nothing else.
#include "config/config.hpp"
#include "core/error.hpp"
#include "linear/structured_solver.hpp"
#include "parallel/decomposition.hpp"
#include "simulation/simulation.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <mpi.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace fs = std::filesystem;
using namespace efsi;

namespace {

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

} // namespace

int main(int argc, char** argv) {
    // Open MPI 4.1's default MPI-IO component (ompio) intermittently drops whole blocks of
    // collective HDF5 writes (seen on 4 ranks: half of a checkpoint dataset left at zero);
    // ROMIO does not. Prefer ROMIO unless the user chose a component.
    setenv("OMPI_MCA_io", "romio321", 0);
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    int code = 0;
    {
        LinearAlgebraScope linear_algebra;
        CLI::App app{"efsi: full Eulerian fluid-structure and fluid-membrane solver"};
        app.set_version_flag("--version", std::string("efsi ") + EFSI_VERSION);
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

        auto* keys = app.add_subcommand("keys", "print the table of every case key (Markdown)");

        try {
            app.parse(argc, argv);
            if (*keys) {
                if (rank == 0) std::cout << case_reference_markdown();
            } else {
                const Config cfg = load_case(case_path, parse_sets(sets));
                // The rank count is checked against the grid before anything is allocated.
                Decomposition::choose_ranks(size, cfg.grid, cfg.ranks);
                if (*check) {
                    if (rank == 0)
                        std::cout << fmt::format(
                                         "# case '{}' is valid ({}D, {} cells, {} rank(s))\n",
                                         cfg.name, cfg.grid.dim, cfg.grid.total_cells(), size)
                                  << cfg.resolved_toml << "\n";
                } else {
                    RunOptions opt;
                    opt.output_dir = output.empty() ? fs::path("out") / cfg.name : fs::path(output);
                    opt.restart_file = restart;
                    opt.quiet = quiet;
                    Simulation sim(cfg, opt, MPI_COMM_WORLD);
                    code = sim.run();
                }
            }
        } catch (const CLI::ParseError& e) {
            code = rank == 0 ? app.exit(e) : (e.get_exit_code() != 0 ? 2 : 0);
        } catch (const InputError& e) {
            if (rank == 0) std::cerr << "efsi: input error: " << e.what() << std::endl;
            code = 2;
        } catch (const std::exception& e) {
            if (rank == 0) std::cerr << "efsi: error: " << e.what() << std::endl;
            code = 1;
        }
    }
    MPI_Finalize();
    return code;
}
