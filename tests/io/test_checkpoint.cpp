// Checkpoints with bodies (io/checkpoint.cpp): every body's phi, tensor and kappa_R come
// back bit for bit on a fresh BodySystem of the same case, on its stored patch; a checkpoint
// of another case is refused; the case fingerprint spells the body choices by their
// case-file names (so checkpoints written before the kinds became enums still restart).
#include "bodies/body_test_support.hpp"
#include "io/checkpoint.hpp"

#include <filesystem>

using namespace efsi;
using namespace efsi::test;
using ::testing::HasSubstr;

namespace {

const std::string scene = grid_2d() + R"(
[[body]]
name = "particle"
kind = "solid"
shear_modulus = 8.0
shape = "cylinder"
centre = [0.3, 0.5, 0.0]
radius = 0.15

[[body]]
name = "capsule"
kind = "membrane"
law = "skalak"
elastic_modulus = 0.5
bending_modulus = 1e-4
shape = "cylinder"
centre = [0.85, 0.5, 0.0]
radius = 0.2
interface = "smoothed"
)";

std::vector<Body*> list(Bodies& s) {
    std::vector<Body*> out;
    for (auto& b : s.system.bodies())
        out.push_back(b.get());
    return out;
}

/// Largest |a - b| over the owned cells of two fields on the same patch.
real difference(const Field& a, const Field& b) {
    real m = 0;
    for_each_in(a.owned(),
                [&](int i, int j, int k) { m = std::max(m, std::abs(a(i, j, k) - b(i, j, k))); });
    return global_max(m);
}

} // namespace

TEST(Checkpoint, BodiesComeBackBitForBit) {
    const auto file = std::filesystem::temp_directory_path() /
                      ("efsi_test_checkpoint_np" + std::to_string(world_size()) + ".h5");
    Bodies a(scene);
    // A state that is not the initial one: B and Gs perturbed, the solid moved a little.
    a.body(0).tensor().comp[2].fill(0.125);
    a.body(1).tensor().comp[0].fill(1.0 / 3.0);
    const VelocityField u = uniform_velocity(a, 0.5, -0.25);
    StageTimers timers;
    a.system.advance(u, 0.02, 0, timers);
    FlowState flow(a.dec.block(), a.dec.dim());
    flow.time = 0.02;
    flow.step = 1;
    RunClock clock;
    write_checkpoint(file, a.dec, flow, clock, list(a), case_fingerprint(a.cfg));

    Bodies b(scene);
    FlowState back(b.dec.block(), b.dec.dim());
    read_checkpoint(file, b.dec, back, clock, list(b), case_fingerprint(b.cfg));
    EXPECT_EQ(back.step, 1);
    for (std::size_t n = 0; n < 2; ++n) {
        const Body &x = a.body(n), &y = b.body(n);
        ASSERT_EQ(x.patch().global.lo, y.patch().global.lo);
        ASSERT_EQ(x.patch().global.hi, y.patch().global.hi);
        EXPECT_EQ(difference(x.phi(), y.phi()), 0.0) << x.name();
        ASSERT_EQ(x.tensor().comp.size(), y.tensor().comp.size());
        for (std::size_t c = 0; c < x.tensor().comp.size(); ++c)
            EXPECT_EQ(difference(x.tensor().comp[c], y.tensor().comp[c]), 0.0) << x.name() << c;
    }
    ASSERT_NE(b.body(1).reference_curvature(), nullptr);
    EXPECT_EQ(difference(*a.body(1).reference_curvature(), *b.body(1).reference_curvature()), 0.0);

    // Another case (the law changed) is refused.
    std::string other = scene;
    other.replace(other.find("\"skalak\""), 8, "\"neo_hookean\"");
    Bodies c(other);
    FlowState f3(c.dec.block(), c.dec.dim());
    EXPECT_THROW(read_checkpoint(file, c.dec, f3, clock, list(c), case_fingerprint(c.cfg)),
                 InputError);
    MPI_Barrier(MPI_COMM_WORLD);
    if (world_rank() == 0) std::filesystem::remove(file);
}

TEST(Checkpoint, FingerprintSpellsTheCaseFileNames) {
    const std::string f = case_fingerprint(case_from(scene));
    EXPECT_THAT(f, HasSubstr("body[0].kind = solid pinned false"));
    EXPECT_THAT(f, HasSubstr("body[1].kind = membrane pinned false"));
    EXPECT_THAT(f, HasSubstr("body[1].shape = cylinder centre"));
    EXPECT_THAT(f, HasSubstr("body[1].interface = smoothed smoothing_width"));
    EXPECT_THAT(f, HasSubstr("body[1].membrane = skalak elastic_modulus"));
    EXPECT_THAT(f, HasSubstr("strain_velocity surface"));
}
