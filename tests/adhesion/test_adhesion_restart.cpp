// The adhesion's restart state (Coupling::save / restore) through a checkpoint file: the
// receptors' positions and bonds come back bit for bit on a fresh coupling of the same case,
// on any rank count, and the restored coupling then steps exactly as the one that never
// stopped (positions, bonds and face forces). A checkpoint without the adhesion record, one
// holding it for a case without adhesion, a corrupted array and a record of another receptor
// count are refused naming the problem.
#include "adhesion_scene.hpp"
#include "io/checkpoint.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <string>

using namespace efsi;
using namespace efsi::adhesion;
using efsi::test::adhesion_config;
using efsi::test::input_error_of;
using efsi::test::um;
using efsi::test::zero_field;
using ::testing::HasSubstr;

namespace {

std::filesystem::path checkpoint_file(const std::string& name) {
    return std::filesystem::temp_directory_path() /
           ("efsi_test_adhesion_" + name + "_np" + std::to_string(test::world_size()) + ".h5");
}

void remove_file(const std::filesystem::path& f) {
    MPI_Barrier(MPI_COMM_WORLD);
    if (test::world_rank() == 0) std::filesystem::remove(f);
}

} // namespace

TEST(AdhesionRestart, StateComesBackThroughTheCheckpointAndContinuesBitForBit) {
    const real G = 800, dt = 1e-7;
    test::Channel c = test::make_channel({16, 16, 16}, 0.25 * um, 0, G * 4 * um);
    const VelocityField u = test::velocity_from(c, [&](int comp, const Real3& x) {
        return comp == 0   ? G * x[1] + 3e-4 * std::sin(x[2] / um)
               : comp == 2 ? 1e-4 * std::cos(x[0] / um) * std::sin(x[1] * 0.7 / um)
                           : 0.0;
    });
    std::vector<BodyConfig> bodies{test::sphere_body("p", {2 * um, 1.03 * um, 2 * um}, 1 * um)};
    AdhesionConfig cfg = adhesion_config(1, 2000, {1.0 * um, 0, 1.0 * um}, {3.0 * um, 0, 3.0 * um});
    cfg.parameters.k_on = 2e6;
    Coupling a(cfg, bodies, *c.dec, 1000, 1e-3);
    VelocityField fa = zero_field(c), fb = zero_field(c);
    std::uint64_t step = 0;
    for (; step < 10; ++step) {
        a.add_bond_forces(fa, dt);
        a.advance(u, dt, step);
    }
    ASSERT_GT(a.bond_count(), 3u);

    const auto file = checkpoint_file("restart");
    StateRecord saved;
    saved.description = "receptors and bonds";
    a.save(saved);
    FlowState flow(c.dec->block(), 3);
    flow.step = long(step);
    RunClock clock;
    write_checkpoint(file, *c.dec, flow, clock, {}, "", {{"adhesion", &saved}});

    Coupling b(cfg, bodies, *c.dec, 1000, 1e-3);
    StateRecord back;
    back.description = "receptors and bonds";
    FlowState flow_back(c.dec->block(), 3);
    read_checkpoint(file, *c.dec, flow_back, clock, {}, "", {{"adhesion", &back}});
    EXPECT_EQ(flow_back.step, long(step));
    b.restore(back);
    ASSERT_EQ(b.bond_count(), a.bond_count());
    for (std::size_t k = 0; k < a.receptors().size(); ++k) {
        const Receptor &x = a.receptors()[k], &y = b.receptors()[k];
        ASSERT_EQ(x.id, y.id);
        ASSERT_EQ(x.ligand, y.ligand) << "receptor " << k;
        for (int d = 0; d < 3; ++d)
            ASSERT_EQ(x.x[d], y.x[d]) << "receptor " << k;
    }
    for (std::uint64_t l = 0; l < a.ligands().size(); ++l)
        ASSERT_EQ(a.ligands().bound_receptor(l), b.ligands().bound_receptor(l)) << "ligand " << l;
    for (std::size_t n = 0; n < a.bodies().size(); ++n) {
        EXPECT_EQ(a.bodies()[n].bonds, b.bodies()[n].bonds);
        EXPECT_EQ(a.bodies()[n].lo, b.bodies()[n].lo);
        EXPECT_EQ(a.bodies()[n].hi, b.bodies()[n].hi);
    }

    // Both step on: the same bonds, positions and face forces, bit for bit.
    std::size_t formed = 0, broken = 0;
    for (; step < 30; ++step) {
        for (int comp = 0; comp < 3; ++comp) {
            fa[comp].fill(0);
            fb[comp].fill(0);
        }
        a.add_bond_forces(fa, dt);
        b.add_bond_forces(fb, dt);
        for (int comp = 0; comp < 3; ++comp)
            for_each_cell(c.dec->block().cells, [&](int i, int j, int k) {
                ASSERT_EQ(fa[comp](i, j, k), fb[comp](i, j, k)) << "step " << step;
            });
        a.advance(u, dt, step);
        b.advance(u, dt, step);
        formed += a.stats().kinetics.formed;
        broken += a.stats().kinetics.broken;
        ASSERT_EQ(a.stats().kinetics.formed, b.stats().kinetics.formed);
        ASSERT_EQ(a.stats().kinetics.broken, b.stats().kinetics.broken);
    }
    EXPECT_GT(formed + broken, 0u) << "the kinetics did something after the restart";
    for (std::size_t k = 0; k < a.receptors().size(); ++k) {
        ASSERT_EQ(a.receptors()[k].ligand, b.receptors()[k].ligand) << "receptor " << k;
        for (int d = 0; d < 3; ++d)
            ASSERT_EQ(a.receptors()[k].x[d], b.receptors()[k].x[d]) << "receptor " << k;
    }

    // A case with another receptor count does not take the record.
    AdhesionConfig fewer = cfg;
    fewer.receptors[0].count = 1000;
    Coupling d(fewer, bodies, *c.dec, 1000, 1e-3);
    EXPECT_THAT(input_error_of([&] { d.restore(back); }), HasSubstr("receptor_id"));

    // The case has no adhesion, the checkpoint holds it: refused, naming the record.
    EXPECT_THAT(input_error_of([&] { read_checkpoint(file, *c.dec, flow_back, clock, {}, ""); }),
                HasSubstr("holds 'adhesion' state (receptors and bonds)"));

    // A flipped value in the stored positions is caught by the array's checksum.
    MPI_Barrier(MPI_COMM_WORLD);
    if (test::world_rank() == 0) {
        const hid_t h5 = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
        const hid_t dset = H5Dopen2(h5, "adhesion/receptor_x", H5P_DEFAULT);
        std::vector<double> x(saved.reals.at("receptor_x"));
        x[7] = std::nextafter(x[7], 1.0);
        H5Dwrite(dset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, x.data());
        H5Dclose(dset);
        H5Fclose(h5);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    EXPECT_THAT(input_error_of([&] {
                    read_checkpoint(file, *c.dec, flow_back, clock, {}, "", {{"adhesion", &back}});
                }),
                HasSubstr("dataset 'adhesion/receptor_x' does not match its checksum"));
    remove_file(file);

    // The case has adhesion, the checkpoint does not hold it: refused, naming the record.
    const auto bare = checkpoint_file("bare");
    write_checkpoint(bare, *c.dec, flow, clock);
    EXPECT_THAT(input_error_of([&] {
                    read_checkpoint(bare, *c.dec, flow_back, clock, {}, "", {{"adhesion", &back}});
                }),
                HasSubstr("holds no 'adhesion' state (receptors and bonds)"));
    remove_file(bare);
}

TEST(AdhesionRestart, ARecordThatDoesNotFitIsRefused) {
    test::Channel c = test::make_channel({16, 16, 16}, 0.25 * um);
    std::vector<BodyConfig> bodies{test::sphere_body("p", {2 * um, 1.03 * um, 2 * um}, 1 * um)};
    AdhesionConfig cfg = adhesion_config(1, 200, {1.0 * um, 0, 1.0 * um}, {3.0 * um, 0, 3.0 * um});
    Coupling a(cfg, bodies, *c.dec, 1000, 1e-3);
    StateRecord saved;
    a.save(saved);
    // A ligand bound twice, a ligand that does not exist, an array missing: refused.
    StateRecord twice = saved;
    twice.integers["receptor_ligand"][0] = twice.integers["receptor_ligand"][1] = 3;
    Coupling b(cfg, bodies, *c.dec, 1000, 1e-3);
    EXPECT_THAT(input_error_of([&] { b.restore(twice); }), HasSubstr("bound to receptors"));
    StateRecord missing = saved;
    missing.integers["receptor_ligand"][0] = a.ligands().size();
    EXPECT_THAT(input_error_of([&] { b.restore(missing); }), HasSubstr("does not exist"));
    StateRecord absent = saved;
    absent.reals.erase("receptor_x");
    EXPECT_THAT(input_error_of([&] { b.restore(absent); }), HasSubstr("receptor_x"));
}
