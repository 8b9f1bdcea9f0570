// Unit tests of the element-test box controller (Kernel/Boundaries/BoxController.h).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "Boundaries/BoxController.h"
#include "Boundaries/PeriodicBox.h"
#include "Core/Error.h"
#include "Neighbours/NeighbourList.h"
#include "Particles/ParticleData.h"
#include "Walls/Wall.h"

using namespace pdpm;

namespace {
struct Fixture {
    PeriodicBox box;
    ParticleData P;
    Fixture() {
        box.set({0, 0, 0}, {2, 3, 4}, true, true, true);
        P.add({0.5, 1.0, 1.0}, 0.1, 1000, 0);
        P.add({1.5, 2.5, 3.5}, 0.2, 1000, 0);
        P.add({0.0, 0.1, 0.2}, 0.3, 1000, 0);
    }
};
double frac(const PeriodicBox& b, const Vec3& x, int a) { return (x[a] - b.lo()[a]) / b.length()[a]; }
} // namespace

// Homogeneous strain rate: box length follows L0 exp(rate t) and the particles' fractional
// coordinates along the driven axis are exactly preserved (affine remap); other axes untouched.
TEST(BoxControl, StrainRateAffineRemapIsExact) {
    Fixture f;
    BoxController c;
    const double rate = -3.0, dt = 1e-3;
    c.setStrainRate(2, rate);
    std::vector<double> f0;
    for (const auto& x : f.P.x) f0.push_back(frac(f.box, x, 2));
    const auto x0 = f.P.x;
    const int n = 200;
    for (int k = 0; k < n; ++k) c.step(f.box, f.P, k * dt, dt);
    EXPECT_NEAR(f.box.length().z / (4 * std::exp(rate * n * dt)), 1.0, 1e-12);
    EXPECT_DOUBLE_EQ(f.box.length().x, 2.0);
    EXPECT_DOUBLE_EQ(f.box.length().y, 3.0);
    // the centre of the box stays put
    EXPECT_NEAR(0.5 * (f.box.lo().z + f.box.hi().z), 2.0, 1e-12);
    for (std::size_t i = 0; i < f.P.size(); ++i) {
        EXPECT_NEAR(frac(f.box, f.P.x[i], 2), f0[i], 1e-12) << i;
        EXPECT_EQ(f.P.x[i].x, x0[i].x);
        EXPECT_EQ(f.P.x[i].y, x0[i].y);
    }
    EXPECT_NEAR(c.strain(f.box).rate.z, rate, 1e-9);
}

// Cosine law (Eq. 2.2): L(t) = Lf + (L0 - Lf)/2 (1 + cos 2 pi (t - t0)/T); reaches Lf at T/2 and L0
// again at T. Wall-driven mode leaves the particles alone; the affine variant remaps them.
TEST(BoxControl, CosineLawPositions) {
    for (bool affine : {false, true}) {
        Fixture f;
        BoxController c;
        const double L0 = 4, Lf = 3.2, T = 1.0, t0 = 0.25, dt = 1e-3;
        c.setCosine(2, L0, Lf, T, t0, affine);
        const auto x0 = f.P.x;
        double t = 0;
        // before t0 nothing happens
        while (t < t0 - 0.5 * dt) {
            c.step(f.box, f.P, t, dt);
            t += dt;
        }
        EXPECT_DOUBLE_EQ(f.box.length().z, L0);
        double worst = 0;
        for (int k = 0; k < 1000; ++k) {
            c.step(f.box, f.P, t, dt);
            t += dt;
            const double expected = Lf + 0.5 * (L0 - Lf) * (1 + std::cos(2 * std::numbers::pi * (t - t0) / T));
            worst = std::max(worst, std::fabs(f.box.length().z - expected));
            if (k == 499) {
                EXPECT_NEAR(f.box.length().z, Lf, 1e-9);
            }
        }
        EXPECT_LT(worst, 1e-12);
        EXPECT_NEAR(f.box.length().z, L0, 1e-9);
        if (!affine) {
            for (std::size_t i = 0; i < f.P.size(); ++i) EXPECT_EQ(f.P.x[i].z, x0[i].z);
        } else {
            // after a full period, the fractional positions are back where they were
            Fixture g;
            for (std::size_t i = 0; i < f.P.size(); ++i) EXPECT_NEAR(f.P.x[i].z, g.P.x[i].z, 1e-9);
        }
    }
}

// Stress control (Eq. 3.3) on a model material with sigma_zz = K (L* - L)/L*: the virtual wall settles
// where sigma_zz = sigma_goal, i.e. at L = L*(1 - sigma_goal/K), and the axes not under stress control
// keep their length.
TEST(BoxControl, StressControlConvergesToGoal) {
    Fixture f;
    BoxController c;
    const double K = 1e5, Lstar = 4.0, goal = 2e3;
    const double area = 2.0 * 3.0;
    // critical damping for the wall: gamma = 2 sqrt(m k_eff), k_eff = K A / L*
    const double m = 10.0, kEff = K * area / Lstar, gamma = 2 * std::sqrt(m * kEff);
    c.setStress(2, goal, m, gamma);
    const double dt = 0.05 * std::sqrt(m / kEff);
    double sigma = 0;
    for (int k = 0; k < 4000; ++k) {
        sigma = K * (Lstar - f.box.length().z) / Lstar;
        c.step(f.box, f.P, k * dt, dt, {0, 0, sigma});
    }
    sigma = K * (Lstar - f.box.length().z) / Lstar;
    EXPECT_NEAR(sigma / goal, 1.0, 1e-3);
    EXPECT_NEAR(f.box.length().z, Lstar * (1 - goal / K), 1e-3 * Lstar * goal / K);
    EXPECT_DOUBLE_EQ(f.box.length().x, 2.0);
    EXPECT_DOUBLE_EQ(f.box.length().y, 3.0);
    EXPECT_EQ(c.mode(2), AxisMode::Stress);
    EXPECT_TRUE(c.needsStress());
}

// Mixed control: stress on x and y, strain rate on z (the triaxial test) with the same model
// material per axis: lateral stresses reach the goal while z follows its rate exactly.
TEST(BoxControl, MixedStressStrainControl) {
    Fixture f;
    BoxController c;
    const double K = 1e5, goal = 1e3, m = 5.0, dt = 1e-4, rate = -0.5;
    const Vec3 Lstar{2, 3, 4};
    for (int a = 0; a < 2; ++a) {
        const double kEff = K * (f.box.length()[(a + 1) % 3] * f.box.length()[(a + 2) % 3]) / Lstar[a];
        c.setStress(a, goal, m, 2 * std::sqrt(m * kEff));
    }
    c.setStrainRate(2, rate);
    const int n = 20000;
    for (int k = 0; k < n; ++k) {
        Vec3 s;
        for (int a = 0; a < 3; ++a) s[a] = K * (Lstar[a] - f.box.length()[a]) / Lstar[a];
        c.step(f.box, f.P, k * dt, dt, s);
    }
    for (int a = 0; a < 2; ++a) EXPECT_NEAR(K * (Lstar[a] - f.box.length()[a]) / Lstar[a] / goal, 1.0, 1e-2) << a;
    EXPECT_NEAR(f.box.length().z / (4 * std::exp(rate * n * dt)), 1.0, 1e-10);
}

// Strain bookkeeping: true, engineering, volumetric and deviatoric strains (Eq. 2.3, 2.4) for boxes
// deformed by hand into the modes of Table 2.1.
TEST(BoxControl, StrainFormulas) {
    PeriodicBox box;
    box.set({0, 0, 0}, {1, 1, 1}, true, true, true);
    BoxController c;
    c.setReference(box);
    const double e = 0.02;
    // uniaxial: (0, 0, -e) -> eps_dev = e, eps_v = -e
    box.setAxis(2, 0, std::exp(-e));
    StrainState s = c.strain(box);
    EXPECT_NEAR(s.trueStrain.z, -e, 1e-14);
    EXPECT_NEAR(s.volumetricTrue, -e, 1e-14);
    EXPECT_NEAR(s.deviatoric, e, 1e-14);
    EXPECT_NEAR(s.engineeringStrain.z, std::exp(-e) - 1, 1e-14);
    EXPECT_NEAR(s.volumetricEngineering, std::exp(-e) - 1, 1e-14);
    // D2: (e, 0, -e) -> eps_dev = sqrt(3) e, volume conserved
    box.setAxis(0, 0, std::exp(e));
    s = c.strain(box);
    EXPECT_NEAR(s.volumetricTrue, 0, 1e-14);
    EXPECT_NEAR(s.deviatoric, std::sqrt(3.0) * e, 1e-14);
    EXPECT_NEAR(std::log(box.volume()), s.volumetricTrue, 1e-14);
    // D3: (e/2, e/2, -e) -> eps_dev = 3/2 e
    box.setAxis(0, 0, std::exp(e / 2));
    box.setAxis(1, 0, std::exp(e / 2));
    s = c.strain(box);
    EXPECT_NEAR(s.deviatoric, 1.5 * e, 1e-14);
    // isotropic: no deviatoric strain
    box.set({0, 0, 0}, {0.9, 0.9, 0.9}, true, true, true);
    s = c.strain(box);
    EXPECT_NEAR(s.deviatoric, 0, 1e-14);
    EXPECT_NEAR(s.volumetricTrue, 3 * std::log(0.9), 1e-14);
    EXPECT_NEAR(deviatoricMagnitude({1, 2, 3}), std::sqrt(3.0), 1e-14);
}

// Swelling dr/dt = g r: radii grow as exp(g t) and masses as r^3 (density kept).
TEST(BoxControl, SwellingUpdatesRadiusAndMass) {
    Fixture f;
    BoxController c;
    const double g = 2.0, dt = 1e-3;
    c.setSwelling(g);
    const auto r0 = f.P.r;
    const auto m0 = f.P.m;
    for (int k = 0; k < 100; ++k) c.step(f.box, f.P, k * dt, dt, {}, {1000.0});
    for (std::size_t i = 0; i < f.P.size(); ++i) {
        const double s = std::exp(g * 100 * dt);
        EXPECT_NEAR(f.P.r[i] / (r0[i] * s), 1.0, 1e-12);
        EXPECT_NEAR(f.P.m[i] / (m0[i] * s * s * s), 1.0, 1e-12);
        EXPECT_NEAR(f.P.invM[i] * f.P.m[i], 1.0, 1e-12);
    }
    EXPECT_DOUBLE_EQ(f.box.length().z, 4.0);
    // swelling without densities is refused
    EXPECT_THROW(c.step(f.box, f.P, 0, dt), InputError);
}

// Swelling closes gaps without moving anything: the neighbour list must count the radii's growth
// against its skin, or two resting spheres that swell into each other are never paired. Two spheres of
// 1 mm 3 skins apart are not in the list; swelling by g = 10 1/s for 1 ms grows each by 1e-5 m, more
// than the gap (3e-6 m) and the skin (1e-6 m): a rebuild must be asked for, and it finds the pair.
TEST(BoxControl, SwellingConsumesTheNeighbourSkin) {
    ParticleData P;
    PeriodicBox box;
    box.set({0, 0, 0}, {0.01, 0.01, 0.01}, true, true, true);
    const double r = 1e-3, skin = 1e-6;
    P.add({0.004, 0.005, 0.005}, r, 1000, 0);
    P.add({0.004 + 2 * r + 3 * skin, 0.005, 0.005}, r, 1000, 0);
    NeighbourList nl;
    nl.setSkin(skin);
    const WallList walls;
    nl.build(P, box, walls, 0);
    EXPECT_EQ(nl.pairCount(), 0u);
    EXPECT_FALSE(nl.needsRebuild(0, P, box, walls));
    BoxController c;
    c.setSwelling(10);
    c.step(box, P, 0, 1e-3, {}, {1000.0});
    EXPECT_GT(P.r[0] + P.r[1], norm(P.x[1] - P.x[0]));  // they overlap now
    EXPECT_NEAR(P.radiusGrowth, r * (std::exp(10 * 1e-3) - 1), 1e-15);
    EXPECT_TRUE(nl.needsRebuild(0, P, box, walls));
    nl.build(P, box, walls, 0);
    EXPECT_EQ(nl.pairCount(), 1u);
    EXPECT_FALSE(nl.needsRebuild(0, P, box, walls));
    // shrinking never closes a gap: no growth is counted
    c.setSwelling(-10);
    c.step(box, P, 1e-3, 1e-3, {}, {1000.0});
    EXPECT_FALSE(nl.needsRebuild(0, P, box, walls));
}

TEST(BoxControl, SaveLoadRoundTripAndBadInput) {
    BoxController c;
    c.setCosine(2, 4, 3, 0.5, 0.1, true);
    c.setStress(0, 123.5, 2.0, 0.25);
    c.setStrainRate(1, -0.75);
    c.setSwelling(0.125);
    PeriodicBox box;
    box.set({0, 0, 0}, {1, 2, 3}, true, true, true);
    c.setReference(box);
    std::vector<std::pair<std::string, std::string>> kv;
    c.save(kv);
    BoxController d;
    d.load(kv);
    EXPECT_EQ(d.mode(0), AxisMode::Stress);
    EXPECT_EQ(d.mode(1), AxisMode::StrainRate);
    EXPECT_EQ(d.mode(2), AxisMode::Cosine);
    EXPECT_EQ(d.axis(0).stressGoal, 123.5);
    EXPECT_EQ(d.axis(1).rate, -0.75);
    EXPECT_EQ(d.axis(2).lengthFinal, 3.0);
    EXPECT_TRUE(d.axis(2).affine);
    EXPECT_EQ(d.swelling(), 0.125);
    EXPECT_EQ(d.referenceLength().z, 3.0);
    EXPECT_THROW(c.setStress(0, 1, 0, 1), InputError);
    EXPECT_THROW(c.setCosine(0, 1, 1, 0, 0), InputError);
    EXPECT_THROW(c.setStrainRate(3, 1), InputError);
    // a file edited after it was sealed: what the setters refuse, load refuses too
    const auto edited = [&](const std::string& key, const std::string& value) {
        auto e = kv;
        for (auto& [k, v] : e)
            if (k == key) v = value;
        BoxController b;
        b.load(e);
    };
    EXPECT_NO_THROW(edited("box_2_affine", "0"));
    EXPECT_THROW(edited("box_2_affine", "abc"), InputError);
    EXPECT_THROW(edited("box_2_period", "0"), InputError);
    EXPECT_THROW(edited("box_2_l0", "-1"), InputError);
    EXPECT_THROW(edited("box_0_mass", "0"), InputError);
    EXPECT_THROW(edited("box_1_rate", "nan"), InputError);
    // every value save() writes must be there: a line dropped from an edited file is refused, not
    // left at the new controller's default
    for (const char* key : {"box_1_rate", "box_2_mode", "box_0_velocity", "box_swelling", "box_ref"}) {
        auto e = kv;
        std::erase_if(e, [&](const auto& p) { return p.first == key; });
        ASSERT_EQ(e.size() + 1, kv.size()) << key;
        BoxController b;
        EXPECT_THROW(b.load(e), InputError) << key;
    }
}

// Scaling all three axes in one pass gives bitwise the positions of three one-axis steps to the
// same bounds, and the bounds and length changes of the scaling.
TEST(BoxControl, ScaleAboutCentreEqualsThreeAxisSteps) {
    ParticleData a;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 5000; ++i) a.add({u(rng) * 2 - 0.3, u(rng) * 3, u(rng) * 0.5 + 1}, 0.01, 2000, 0);
    ParticleData b = a;
    const ParticleData before = a;
    PeriodicBox ba, bb;
    ba.set({-0.3, 0, 1}, {1.7, 3, 1.5}, true, true, false);
    bb = ba;
    const Vec3 oldLo = ba.lo(), oldHi = ba.hi();
    const Vec3 s{0.999, 1.0003, 0.97};
    ba.scaleAboutCentre(s, &a);
    // against the affine map written out independently (to round-off: the compiler may fuse differently)
    for (std::size_t i = 0; i < a.size(); ++i)
        for (int ax = 0; ax < 3; ++ax) {
            const double c = 0.5 * (oldLo[ax] + oldHi[ax]);
            ASSERT_NEAR(a.x[i][ax], c + (before.x[i][ax] - c) * s[ax], 1e-14) << i;
        }
    for (int ax = 0; ax < 3; ++ax) bb.setAxis(ax, ba.lo()[ax], ba.hi()[ax], &b);
    for (int ax = 0; ax < 3; ++ax) {
        EXPECT_NEAR(ba.hi()[ax] - ba.lo()[ax], (bb.hi()[ax] - bb.lo()[ax]), 1e-15);
        EXPECT_NEAR(0.5 * (ba.lo()[ax] + ba.hi()[ax]), ax == 0 ? 0.7 : ax == 1 ? 1.5 : 1.25, 1e-15);
        EXPECT_EQ(ba.lengthChange(ax), bb.lengthChange(ax));
    }
    EXPECT_NEAR(ba.hi()[2] - ba.lo()[2], 0.5 * 0.97, 1e-15);
    for (std::size_t i = 0; i < a.size(); ++i)
        for (int ax = 0; ax < 3; ++ax) ASSERT_EQ(a.x[i][ax], b.x[i][ax]) << i;
}

// The cosine law's rate (used for the affine flow of the fluctuation kinetic energy) is the
// derivative of its length: compared with a central difference, zero before the start, and the
// extreme rate of Sec. 2.2.2, pi f (L0 - Lf), at a quarter period.
TEST(BoxControl, CosineRateIsTheDerivativeOfTheCosineLength) {
    AxisControl c;
    c.mode = AxisMode::Cosine;
    c.lengthStart = 0.04;
    c.lengthFinal = 0.03;
    c.period = 5e-3;
    c.timeStart = 1e-3;
    EXPECT_EQ(BoxController::cosineRate(c, 0.5e-3), 0.0);
    for (double t : {1.2e-3, 2.0e-3, 3.1e-3, 4.4e-3, 5.9e-3}) {
        const double h = 1e-8;
        const double fd = (BoxController::cosineLength(c, t + h) - BoxController::cosineLength(c, t - h)) / (2 * h);
        EXPECT_NEAR(BoxController::cosineRate(c, t), fd, 1e-6 * std::abs(fd) + 1e-9) << t;
    }
    const double quarter = c.timeStart + c.period / 4;
    EXPECT_NEAR(BoxController::cosineRate(c, quarter), -std::numbers::pi / c.period * (c.lengthStart - c.lengthFinal), 1e-12);
}

// Wall-driven cosine axes (no remap) tell the box their dL/dt, remapped axes their d ln L/dt.
// A particle wrapped across a flowing axis takes the velocity of the image it becomes.
TEST(BoxControl, WallDrivenAxesFlowAndWrappingShiftsVelocity) {
    Fixture f;
    BoxController c;
    c.setCosine(2, 4.0, 3.0, 2.0, 0.0, false);
    c.setCosine(0, 2.0, 1.5, 2.0, 0.0, true);
    c.setStrainRate(1, -0.1);
    const double dt = 1e-3, t = 0.3;
    c.step(f.box, f.P, t, dt);
    EXPECT_DOUBLE_EQ(f.box.flowRate(2), BoxController::cosineRate(c.axis(2), t + dt));
    EXPECT_LT(f.box.flowRate(2), 0.0);
    EXPECT_EQ(f.box.flowRate(0), 0.0);
    EXPECT_EQ(f.box.flowRate(1), 0.0);
    EXPECT_TRUE(f.box.flowing());
    // remapped axes carry d ln L/dt instead
    EXPECT_EQ(f.box.affineRate(2), 0.0);
    EXPECT_DOUBLE_EQ(f.box.affineRate(1), -0.1);
    EXPECT_NEAR(f.box.affineRate(0),
                BoxController::cosineRate(c.axis(0), t + dt) / BoxController::cosineLength(c.axis(0), t + dt), 1e-15);
    EXPECT_NEAR(f.box.affineRate(0) * f.box.length()[0], BoxController::cosineRate(c.axis(0), t + dt), 1e-12);
    const double L = f.box.length()[2], rate = f.box.flowRate(2);
    Vec3 above{1.0, 1.0, f.box.hi()[2] + 0.25}, below{1.0, 1.0, f.box.lo()[2] - 2.25 * L};
    const Vec3 dvA = f.box.wrapWithVelocityShift(above), dvB = f.box.wrapWithVelocityShift(below);
    EXPECT_NEAR(above[2], f.box.lo()[2] + 0.25, 1e-12);
    EXPECT_DOUBLE_EQ(dvA[2], -rate);      // moved down one box: v - L'
    EXPECT_DOUBLE_EQ(dvB[2], 3 * rate);   // moved up three boxes: v + 3 L'
    EXPECT_EQ(dvA[0], 0.0);
    Vec3 inside{1.0, 1.0, 0.5 * (f.box.lo()[2] + f.box.hi()[2])};
    EXPECT_EQ(f.box.wrapWithVelocityShift(inside)[2], 0.0);
    c.setFree(2);
    c.step(f.box, f.P, t + dt, dt);
    EXPECT_FALSE(f.box.flowing());
    c.setFree(0);
    c.setFree(1);
    c.step(f.box, f.P, t + 2 * dt, dt);
    EXPECT_FALSE(f.box.affine());
}
