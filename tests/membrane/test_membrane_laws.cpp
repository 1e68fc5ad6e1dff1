// Membrane laws (solver/membrane): closed forms of MODEL.md at round-off, zero tension of
// an unstretched membrane, isotropic tension of a uniformly inflated one.
#include "membrane/membrane_law.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace efsi;

namespace {

Matrix3 projection(const Real3& n) {
    Matrix3 P{};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            P[a][b] = (a == b ? 1.0 : 0.0) - n[a] * n[b];
    return P;
}

Real3 unit_vector(real theta, real phi) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

Matrix3 flat_tension(const MembraneLaw& law, real l1, real l2) {
    Matrix3 Gs{};
    Gs[0][0] = l1 * l1;
    Gs[1][1] = l2 * l2;
    return law.tension(membrane_kinematics({0, 0, 1}, Gs));
}

} // namespace

TEST(MembraneLaws, NeoHookeanUniaxialClosedForm) {
    const real Gs = 1.0;
    const auto law = make_membrane_law("neo_hookean", 3 * Gs);
    for (real l1 : {1.0, 1.1, 1.5, 2.0, 3.0}) {
        const real l2 = std::pow(l1, -0.5);
        const Matrix3 t = flat_tension(*law, l1, l2);
        const real t1 = Gs * (l1 * l1 * l1 - 1) / std::pow(l1, 1.5);
        EXPECT_NEAR(t[0][0], t1, 1e-14 * std::max(1.0, t1)) << "lambda1 = " << l1;
        EXPECT_NEAR(t[1][1], 0.0, 1e-14 * std::max(1.0, t1));
        EXPECT_EQ(t[2][2], 0.0); // along the normal
    }
}

TEST(MembraneLaws, SkalakUniaxialClosedForm) {
    const real Gs = 1.0;
    for (real C : {0.5, 1.0, 10.0}) {
        const auto law = make_membrane_law("skalak", 1.5 * Gs, C);
        for (real l1 : {1.0, 1.2, 1.7, 2.5}) {
            const real l2 = std::sqrt((1 + C * l1 * l1) / (1 + C * l1 * l1 * l1 * l1));
            const real J = l1 * l2;
            const real t1 = Gs / J * (l1 * l1 * (l1 * l1 - 1) + C * J * J * (J * J - 1));
            const Matrix3 t = flat_tension(*law, l1, l2);
            EXPECT_NEAR(t[0][0], t1, 1e-13 * std::max(1.0, t1)) << "C " << C << " l1 " << l1;
            EXPECT_NEAR(t[1][1], 0.0, 1e-13 * std::max(1.0, t1));
        }
    }
}

TEST(MembraneLaws, UnstretchedMembraneCarriesNoTension) {
    for (const char* name : {"neo_hookean", "skalak"}) {
        const auto law = make_membrane_law(name, 2.0, 5.0);
        for (real th : {0.1, 0.9, 2.0})
            for (real ph : {0.0, 1.3, 4.0}) {
                const Real3 n = unit_vector(th, ph);
                const MembraneKinematics k = membrane_kinematics(n, projection(n));
                EXPECT_NEAR(k.Is, 0.0, 1e-14);
                EXPECT_NEAR(k.IIs, 0.0, 1e-14);
                const Matrix3 t = law->tension(k);
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b)
                        EXPECT_NEAR(t[a][b], 0.0, 1e-14) << name;
            }
    }
}

TEST(MembraneLaws, InflatedSphereIsotropicTension) {
    // Gs = s^2 P: Bs = s^2 P, J = s^2, tau = T P with
    // T = Es/3 (1 - s^-6) (neo-Hookean), T = 2Es/3 (s^2 - 1 + alpha s^2 (s^4 - 1)) (Skalak).
    const real Es = 1.7, alpha = 3.0, s = 1.15;
    const Real3 n = unit_vector(0.7, 2.1);
    Matrix3 G = projection(n);
    for (auto& row : G)
        for (real& v : row)
            v *= s * s;
    const MembraneKinematics k = membrane_kinematics(n, G);
    EXPECT_NEAR(k.J, s * s, 1e-14);
    const real Tn = Es / 3 * (1 - std::pow(s, -6));
    const real Ts = 2 * Es / 3 * (s * s - 1 + alpha * s * s * (s * s * s * s - 1));
    const auto neo = make_membrane_law("neo_hookean", Es);
    const auto sk = make_membrane_law("skalak", Es, alpha);
    const Matrix3 tn = neo->tension(k), ts = sk->tension(k);
    const Matrix3 P = projection(n);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            EXPECT_NEAR(tn[a][b], Tn * P[a][b], 1e-14);
            EXPECT_NEAR(ts[a][b], Ts * P[a][b], 1e-13);
        }
}

TEST(MembraneLaws, TensionIsTheEnergyDerivative) {
    // Along the uniaxial path Gs = diag(l1^2, l2^2, 0), the work identity
    // d(Ws)/d(l1) = l2 T1 (Ws per reference area, T1 per current length, J = l1 l2).
    for (const char* name : {"neo_hookean", "skalak"}) {
        const auto law = make_membrane_law(name, 1.3, 2.0);
        const real l1 = 1.3, l2 = 0.9, h = 1e-6;
        auto W = [&](real a) {
            const real Is = a * a + l2 * l2 - 2, IIs = a * a * l2 * l2 - 1;
            return law->energy(Is, IIs);
        };
        const real dW = (W(l1 + h) - W(l1 - h)) / (2 * h);
        EXPECT_NEAR(dW, l2 * flat_tension(*law, l1, l2)[0][0], 1e-8) << name;
    }
}

TEST(MembraneLaws, UnknownLawIsAnInputError) {
    EXPECT_THROW(make_membrane_law("mooney", 1.0), std::exception);
}
