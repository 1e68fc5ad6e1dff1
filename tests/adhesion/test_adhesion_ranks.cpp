// The adhesion kinetics on 1, 2 and 4 ranks give the serial result: every rank owns a
// scattered share of the receptors (receptor k on rank k mod size, the worst case for
// contested ligands) and a copy of the ligands; per step the ranks propose and rupture for
// their own receptors, gather all proposals and released ligands, resolve the same winners
// and apply them (kinetics.hpp). After every step the gathered bonds equal those of a
// serial run of the same seed on each rank.
#include "adhesion/kinetics.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <random>
#include <vector>

using namespace efsi;
using namespace efsi::adhesion;

namespace {

constexpr real nm = 1e-9, um = 1e-6;

template <class T>
std::vector<T> all_gather(const std::vector<T>& mine) {
    const int size = test::world_size();
    const int bytes = static_cast<int>(mine.size() * sizeof(T));
    std::vector<int> counts(size), displs(size, 0);
    MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
    for (int r = 1; r < size; ++r)
        displs[r] = displs[r - 1] + counts[r - 1];
    std::vector<T> all(static_cast<std::size_t>(displs[size - 1] + counts[size - 1]) / sizeof(T));
    MPI_Allgatherv(mine.data(), bytes, MPI_BYTE, all.data(), counts.data(), displs.data(), MPI_BYTE,
                   MPI_COMM_WORLD);
    return all;
}

/// (receptor id, ligand) of every receptor, sorted by id.
std::vector<std::pair<std::uint64_t, std::uint64_t>> bonds(const std::vector<Receptor>& rs) {
    std::vector<std::pair<std::uint64_t, std::uint64_t>> b;
    for (const Receptor& r : rs)
        b.emplace_back(r.id, r.ligand);
    std::sort(b.begin(), b.end());
    return b;
}

} // namespace

TEST(AdhesionRanks, ParallelStepsEqualTheSerialRun) {
    AdhesionParameters p;
    p.k_on = 2000;
    p.k_off0 = 300;
    const std::vector<LigandRegion> patch{{{0, 0, 0}, {1 * um, 0, 1 * um}, 50 * nm}};
    std::mt19937_64 gen(3);
    std::uniform_real_distribution<double> ux(-0.1 * um, 1.1 * um), uz(10 * nm, 90 * nm);
    std::vector<Receptor> all;
    for (std::uint64_t k = 0; k < 600; ++k)
        all.push_back({1000 + 7 * k, {ux(gen), uz(gen), ux(gen)}, no_ligand});
    const int size = test::world_size(), rank = test::world_rank();
    std::vector<Receptor> mine;
    for (std::size_t k = 0; k < all.size(); ++k)
        if (static_cast<int>(k % static_cast<std::size_t>(size)) == rank) mine.push_back(all[k]);

    LigandSet serial_ligands = LigandSet::from_regions(patch, p.reactive_distance);
    LigandSet ligands = LigandSet::from_regions(patch, p.reactive_distance);
    Kinetics serial(p, 77), kin(p, 77);
    std::size_t contested = 0;
    for (std::uint64_t step = 0; step < 60; ++step) {
        serial.step(all, serial_ligands, step, 5e-4);

        StepStats st;
        std::vector<Proposal> proposals;
        std::vector<std::uint64_t> released;
        kin.propose(mine, ligands, step, 5e-4, proposals, st);
        kin.rupture(mine, ligands, step, 5e-4, st, &released);
        std::vector<Proposal> gathered = all_gather(proposals);
        for (std::uint64_t id : all_gather(released))
            ligands.release(id);
        Kinetics::resolve(gathered, st);
        Kinetics::apply(mine, ligands, gathered, st);
        contested += st.contested;

        const std::vector<Receptor> everyone = all_gather(mine);
        ASSERT_EQ(everyone.size(), all.size());
        ASSERT_EQ(bonds(everyone), bonds(all)) << "step " << step;
        for (std::uint64_t id = 0; id < ligands.size(); ++id)
            ASSERT_EQ(ligands.bound_receptor(id), serial_ligands.bound_receptor(id));
    }
    EXPECT_GT(contested, 10u);
    EXPECT_GT(serial_ligands.bound_count(), 50u);
}
