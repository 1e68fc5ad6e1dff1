// Voxel masks from HDF5: an aligned mask is copied, a finer one is resampled conserving
// its volume, a mask that does not cover the box or is malformed is refused by name.
#include "core/error.hpp"
#include "io/voxel_mask.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <unistd.h>

using namespace efsi;
using ::testing::HasSubstr;

namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("efsi_mask_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir / name;
}

/// Write a mask [nz][ny][nx] of doubles with the given attributes (omitted when empty).
fs::path write_mask(const std::string& name, Int3 n, std::vector<double> spacing,
                    std::vector<double> origin, const std::function<double(int, int, int)>& v) {
    const fs::path p = temp_file(name);
    const hid_t f = H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t dims[3] = {hsize_t(n[2]), hsize_t(n[1]), hsize_t(n[0])};
    const hid_t s = H5Screate_simple(3, dims, nullptr);
    const hid_t d =
        H5Dcreate2(f, "wall", H5T_NATIVE_DOUBLE, s, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    std::vector<double> data;
    for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
            for (int i = 0; i < n[0]; ++i)
                data.push_back(v(i, j, k));
    H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
    auto attr = [&](const char* an, const std::vector<double>& x) {
        if (x.empty()) return;
        const hsize_t m = x.size();
        const hid_t as = H5Screate_simple(1, &m, nullptr);
        const hid_t a = H5Acreate2(d, an, H5T_NATIVE_DOUBLE, as, H5P_DEFAULT, H5P_DEFAULT);
        H5Awrite(a, H5T_NATIVE_DOUBLE, x.data());
        H5Aclose(a);
        H5Sclose(as);
    };
    attr("spacing", spacing);
    attr("origin", origin);
    H5Dclose(d);
    H5Sclose(s);
    H5Fclose(f);
    return p;
}

GlobalGrid grid16() {
    GlobalGrid g;
    g.cells = {16, 16, 16};
    g.length = {1.6e-5, 1.6e-5, 1.6e-5};
    g.origin = {0, 0, 0};
    return g;
}

/// A tube wall: 1 outside radius 5 um around the x axis through the box centre.
double tube(double y, double z) {
    return std::hypot(y - 8e-6, z - 8e-6) > 5e-6 ? 1.0 : 0.0;
}

} // namespace

TEST(VoxelMask, AnAlignedMaskIsCopied) {
    const auto p =
        write_mask("aligned.h5", {16, 16, 16}, {1e-6, 1e-6, 1e-6}, {0, 0, 0},
                   [](int, int j, int k) { return tube((j + 0.5) * 1e-6, (k + 0.5) * 1e-6); });
    const VoxelMask m = read_voxel_mask(p, "wall");
    const GlobalGrid g = grid16();
    EXPECT_TRUE(check_mask_against_grid(m, g).aligned);
    LocalBlock b{g.cells, {0, 0, 0}};
    Field phi("phi", Location::Cell, b, 3);
    mask_volume_fraction(m, g, b, phi);
    for (int k = 0; k < 16; ++k)
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 16; ++i)
                ASSERT_EQ(phi(i, j, k), m.at(i, j, k));
}

TEST(VoxelMask, AFinerShiftedMaskIsResampledAndKeepsItsVolume) {
    // 0.5 um voxels, shifted by a quarter voxel, covering the box with a margin
    const int n = 34;
    const auto p =
        write_mask("fine.h5", {n, n, n}, {0.5e-6, 0.5e-6, 0.5e-6},
                   {-0.625e-6, -0.625e-6, -0.625e-6}, [](int, int j, int k) {
                       return tube(-0.625e-6 + (j + 0.5) * 0.5e-6, -0.625e-6 + (k + 0.5) * 0.5e-6);
                   });
    const VoxelMask m = read_voxel_mask(p, "wall");
    const GlobalGrid g = grid16();
    const MaskMapping map = check_mask_against_grid(m, g);
    EXPECT_FALSE(map.aligned);
    EXPECT_THAT(map.description, HasSubstr("resampled"));
    LocalBlock b{g.cells, {0, 0, 0}};
    Field phi("phi", Location::Cell, b, 3);
    mask_volume_fraction(m, g, b, phi, 8);
    double vol = 0;
    for (int k = 0; k < 16; ++k)
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 16; ++i) {
                ASSERT_GE(phi(i, j, k), 0.0);
                ASSERT_LE(phi(i, j, k), 1.0);
                vol += phi(i, j, k) * 1e-18;
            }
    // the wall's volume: box minus the lumen cylinder (pi 5^2 x 16 um^3), to the voxel size
    const double exact = 1.6e-5 * 1.6e-5 * 1.6e-5 - M_PI * 25e-12 * 1.6e-5;
    EXPECT_NEAR(vol / exact, 1.0, 0.02);
}

TEST(VoxelMask, AMaskThatDoesNotCoverTheBoxIsRefusedWithBothExtents) {
    const auto p = write_mask("short.h5", {12, 16, 16}, {1e-6, 1e-6, 1e-6}, {0, 0, 0},
                              [](int, int, int) { return 1.0; });
    const VoxelMask m = read_voxel_mask(p, "wall");
    try {
        check_mask_against_grid(m, grid16());
        FAIL() << "accepted a mask shorter than the box";
    } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr("covers [0, 1.2e-05] m in x"));
        EXPECT_THAT(e.what(), HasSubstr("grid spans [0, 1.6e-05] m"));
    }
}

TEST(VoxelMask, AMaskWithoutPlacementIsOnTheGridsOwnCellsOrRefused) {
    const auto p = write_mask("bare.h5", {16, 16, 16}, {}, {},
                              [](int i, int, int) { return i < 4 ? 1.0 : 0.25; });
    VoxelMask m = read_voxel_mask(p, "wall");
    EXPECT_FALSE(m.placed);
    GlobalGrid g = grid16();
    g.origin = {1e-6, -2e-6, 0};
    place_on_grid(m, g);
    EXPECT_TRUE(m.placed);
    EXPECT_TRUE(check_mask_against_grid(m, g).aligned);
    LocalBlock b{g.cells, {0, 0, 0}};
    Field phi("phi", Location::Cell, b, 3);
    mask_volume_fraction(m, g, b, phi);
    EXPECT_EQ(phi(3, 5, 7), 1.0);
    EXPECT_EQ(phi(4, 5, 7), 0.25);

    VoxelMask other = read_voxel_mask_header(p, "wall");
    GlobalGrid finer = grid16();
    finer.cells = {32, 16, 16};
    try {
        place_on_grid(other, finer, "um");
        FAIL() << "placed a 16^3 mask on a 32 x 16 x 16 grid";
    } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr("16 x 16 x 16 voxels and no spacing/origin"));
        EXPECT_THAT(e.what(), HasSubstr("grid's 32 x 16 x 16 cells"));
        EXPECT_THAT(e.what(), HasSubstr("origin in um"));
    }
}

TEST(VoxelMask, ARankReadsOnlyTheVoxelsItsCellsCoverAndGetsTheSameFractions) {
    const int n = 34;
    const auto p = write_mask(
        "part.h5", {n, n, n}, {0.5e-6, 0.5e-6, 0.5e-6}, {-0.625e-6, -0.625e-6, -0.625e-6},
        [](int i, int j, int k) { return (i + 2 * j + 3 * k) % 5 == 0 ? 1.0 : 0.1 * (i % 7); });
    const VoxelMask whole = read_voxel_mask(p, "wall");
    const GlobalGrid g = grid16();
    // One rank's block: cells [8, 16) x [0, 16) x [4, 11) of the grid, and a patch in it.
    const LocalBlock block{{8, 16, 7}, {8, 0, 4}};
    Field all("all", Location::Cell, block, 3), part("part", Location::Cell, block, 3);
    mask_volume_fraction(whole, g, block, all, 4);
    VoxelMask mine = read_voxel_mask_header(p, "wall");
    const Box cells = all.owned();
    const Box need = mask_voxels_for(mine, g, block, cells, 4);
    EXPECT_EQ(read_voxel_values(mine, need), -1);
    EXPECT_LT(mine.values.size(), whole.values.size() / 3);
    mask_volume_fraction(mine, g, block, part, 4);
    for_each_in(cells, [&](int i, int j, int k) { ASSERT_EQ(part(i, j, k), all(i, j, k)); });
    // A bad value inside the part is found (its index over the whole image); outside, not.
    const auto q = write_mask(
        "partbad.h5", {n, n, n}, {0.5e-6, 0.5e-6, 0.5e-6}, {-0.625e-6, -0.625e-6, -0.625e-6},
        [](int i, int j, int k) { return i == 30 && j == 3 && k == 12 ? 1.5 : 0.0; });
    VoxelMask bad = read_voxel_mask_header(q, "wall");
    EXPECT_EQ(read_voxel_values(bad, need), 30 + n * (3 + n * 12));
    EXPECT_EQ(read_voxel_values(bad, Box{{0, 0, 0}, {20, n, n}}), -1);
    EXPECT_THROW(read_voxel_values(bad, Box{{0, 0, 0}, {n + 1, n, n}}), InputError);
}

TEST(VoxelMask, MessagesCarryTheCasesLengthUnit) {
    const auto p = write_mask("unit.h5", {12, 16, 16}, {1, 1, 1}, {0, 0, 0},
                              [](int, int, int) { return 1.0; });
    GlobalGrid g;
    g.cells = {16, 16, 16};
    g.length = {16, 16, 16};
    try {
        check_mask_against_grid(read_voxel_mask(p, "wall"), g, "um");
        FAIL() << "accepted a mask shorter than the box";
    } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr("covers [0, 12] um in x but the grid spans [0, 16] um"));
    }
}

TEST(VoxelMask, MalformedMasksAreRefusedByName) {
    auto expect_error = [](const fs::path& p, const std::string& ds, const std::string& what) {
        try {
            read_voxel_mask(p, ds);
            FAIL() << "accepted " << p << ":" << ds;
        } catch (const InputError& e) {
            EXPECT_THAT(e.what(), HasSubstr(what));
        }
    };
    const auto ok =
        write_mask("ok.h5", {4, 4, 4}, {1, 1, 1}, {0, 0, 0}, [](int, int, int) { return 0.5; });
    expect_error(ok, "nope", "no dataset 'nope'");
    expect_error(temp_file("missing.h5"), "wall", "not a readable file");
    expect_error(
        write_mask("nospacing.h5", {4, 4, 4}, {}, {0, 0, 0}, [](int, int, int) { return 1.0; }),
        "wall", "attribute 'spacing' (3 numbers) is missing");
    expect_error(
        write_mask("noorigin.h5", {4, 4, 4}, {1, 1, 1}, {}, [](int, int, int) { return 1.0; }),
        "wall", "attribute 'origin' (3 numbers) is missing");
    expect_error(write_mask("twospacing.h5", {4, 4, 4}, {1, 1}, {0, 0, 0},
                            [](int, int, int) { return 1.0; }),
                 "wall", "must hold 3 numbers");
    expect_error(write_mask("negspacing.h5", {4, 4, 4}, {1, -1, 1}, {0, 0, 0},
                            [](int, int, int) { return 1.0; }),
                 "wall", "spacing must be > 0");
    expect_error(write_mask("nan.h5", {4, 4, 4}, {1, 1, 1}, {0, 0, 0},
                            [](int i, int, int) { return i == 2 ? NAN : 1.0; }),
                 "wall", "is not in [0, 1]");
    expect_error(
        write_mask("big.h5", {4, 4, 4}, {1, 1, 1}, {0, 0, 0}, [](int, int, int) { return 2.0; }),
        "wall", "is not in [0, 1]");
    const fs::path text = temp_file("text.h5");
    { std::ofstream(text) << "not hdf5\n"; }
    expect_error(text, "wall", "not an HDF5 file");
    EXPECT_THROW(read_voxel_mask(ok, "wall", 10), InputError); // 64 voxels over the limit
}
