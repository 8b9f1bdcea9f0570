// Luding's hysteretic plastic-adhesive normal law (thesis Sec. 5.3.1, Eqs. 5.5-5.7) as a pure function:
// a prescribed overlap path (load to delta_1, unload into tension, reload past delta_1) must reproduce
// the equations to 1e-12 (relative to the force scale k1 delta_max). The expected values are computed
// here from the equations, independently of the kernel's functions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "Contacts/ComposedLaw.h"
#include "Contacts/ContactLaw.h"
#include "Contacts/NormalLaws.h"

using namespace pdpm;

namespace {

struct LudingModel {
    double k2hat, k1, kc, phiF, a1, a2;
    double dmax = 0;  // history

    double deltaStar() const { return k2hat / (k2hat - k1) * phiF * 2 * a1 * a2 / (a1 + a2); }  // Eq. (5.6)
    double k2() const {                                                                             // Eq. (5.7)
        const double ds = deltaStar();
        return dmax >= ds ? k2hat : k1 + (k2hat - k1) * dmax / ds;
    }
    double delta0() const { return (1 - k1 / k2()) * dmax; }
    double deltaMin() const { return (k2() - k1) * dmax / (k2() + kc); }
    double force(double delta) {  // Eq. (5.5)
        dmax = std::max(dmax, delta);
        const double unload = k2() * (delta - delta0());
        if (unload >= k1 * delta) return k1 * delta;
        if (-kc * delta >= unload) return -kc * delta;
        return unload;
    }
};

ContactParameters ludingParameters() {
    ContactParameters p;
    p.k = 1e4;   // k2-hat
    p.k1 = 2e3;
    p.kc = 500;
    p.phiF = 0.05;
    p.gamma = 0;
    return p;
}

/// Runs the path 0 -> d1 -> dLow -> dHigh through the law and the model; returns the largest deviation
/// relative to the force scale k1 * max overlap. Also checks the characteristic points.
void runPath(double d1, bool expectBelowStar) {
    const ContactParameters p = ludingParameters();
    const double a1 = 1e-3, a2 = 0.6e-3;
    LudingModel model{p.k, p.k1, p.kc, p.phiF, a1, a2};
    const double dStar = model.deltaStar();
    ASSERT_EQ(d1 < dStar, expectBelowStar) << "d1 = " << d1 << ", delta*_max = " << dStar;

    const auto law = makeContactLaw("luding");
    law->validate(p, "test");
    std::vector<double> h(static_cast<std::size_t>(law->historySize()), 0.0);
    ContactState s;
    s.n = {0, 0, 1};
    s.rEff = a1 * a2 / (a1 + a2);
    s.mEff = 1e-5;
    s.dt = 1e-6;
    s.overlapRate = 0;

    const double scale = p.k1 * 1.5 * d1;
    double worst = 0;
    auto eval = [&](double delta) {
        s.overlap = delta;
        ContactOutput o;
        law->evaluate(p, s, h.data(), o);
        const double expected = model.force(delta);
        const double dev = std::fabs(o.fn - expected) / scale;
        worst = std::max(worst, dev);
        EXPECT_LE(dev, 1e-12) << "delta = " << delta << ": law " << o.fn << ", Eq. (5.5) " << expected;
        EXPECT_EQ(h[0], model.dmax);  // delta_max is the history
        return o.fn;
    };
    const int n = 400;
    // 1) loading along k1 to d1
    for (int i = 1; i <= n; ++i) {
        const double d = d1 * i / n;
        const double f = eval(d);
        EXPECT_LE(std::fabs(f - p.k1 * d), 1e-12 * scale);
    }
    // characteristic overlaps of the unloading branch for delta_max = d1
    const double k2 = std::min(p.k, p.k1 + (p.k - p.k1) * d1 / dStar);
    const double delta0 = (1 - p.k1 / k2) * d1;
    const double deltaMin = (k2 - p.k1) * d1 / (k2 + p.kc);
    std::printf("luding d1=%.3e (delta*=%.3e): k2=%.6e delta0=%.6e deltaMin=%.6e\n", d1, dStar, k2, delta0, deltaMin);
    EXPECT_NEAR(model.k2(), k2, 1e-12 * p.k);
    if (!expectBelowStar) {
        EXPECT_EQ(k2, p.k);
    }
    // 2) unloading: force zero at delta0, minimum -kc deltaMin at deltaMin, adhesive branch below
    for (int i = n - 1; i >= 1; --i) eval(d1 * i / n);
    EXPECT_LE(std::fabs(eval(delta0)), 1e-12 * scale);
    EXPECT_LE(std::fabs(eval(deltaMin) + p.kc * deltaMin), 1e-12 * scale);
    EXPECT_LE(std::fabs(eval(0.5 * deltaMin) + p.kc * 0.5 * deltaMin), 1e-12 * scale);
    EXPECT_LE(std::fabs(eval(0.5 * (delta0 + d1)) - k2 * (0.5 * (delta0 + d1) - delta0)), 1e-12 * scale);
    // 3) reloading along k2 up to d1 (force k1 d1 there), then along k1 with a new delta_max
    for (int i = 1; i <= n; ++i) eval(d1 * i / n);
    EXPECT_LE(std::fabs(eval(d1) - p.k1 * d1), 1e-12 * scale);
    for (int i = 1; i <= n; ++i) {
        const double d = d1 * (1 + 0.5 * i / n);
        const double f = eval(d);
        EXPECT_LE(std::fabs(f - p.k1 * d), 1e-12 * scale);
    }
    EXPECT_EQ(h[0], 1.5 * d1);
    // 4) unloading from the new maximum uses the new k2(delta_max)
    const double dNew = 1.5 * d1;
    const double k2New = std::min(p.k, p.k1 + (p.k - p.k1) * dNew / dStar);
    const double d0New = (1 - p.k1 / k2New) * dNew;
    EXPECT_LE(std::fabs(eval(d0New)), 1e-12 * scale);
    const double probe = 0.5 * (d0New + dNew);
    EXPECT_LE(std::fabs(eval(probe) - k2New * (probe - d0New)), 1e-12 * scale);
    std::printf("luding d1=%.3e: worst deviation %.2e (relative to k1 delta_max)\n", d1, worst);

    // The normal part alone (NormalLuding::apply) gives the same force.
    double hn[1] = {0};
    ContactOutput o;
    s.overlap = d1;
    NormalLuding::apply(p, s, hn, o);
    EXPECT_LE(std::fabs(o.fn - p.k1 * d1), 1e-12 * scale);
    s.overlap = delta0;
    NormalLuding::apply(p, s, hn, o);
    EXPECT_LE(std::fabs(o.fn), 1e-12 * scale);
    EXPECT_EQ(hn[0], d1);
}

} // namespace

TEST(ContactLuding, PathBelowPlasticFlowLimit) {
    // delta*_max = 1e4/8e3 * 0.05 * 2 * 3.75e-4 = 4.6875e-5
    runPath(2.0e-5, true);
}

TEST(ContactLuding, PathAbovePlasticFlowLimit) { runPath(8.0e-5, false); }

TEST(ContactLuding, DeltaMaxStarAndK2Interpolation) {
    const ContactParameters p = ludingParameters();
    const double rEff = 1e-3 * 0.6e-3 / 1.6e-3;
    const double dStar = p.k / (p.k - p.k1) * p.phiF * 2 * rEff;
    EXPECT_NEAR(NormalLuding::deltaMaxStar(p, rEff), dStar, 1e-12 * dStar);
    EXPECT_NEAR(NormalLuding::k2(p, rEff, 0.25 * dStar), p.k1 + 0.25 * (p.k - p.k1), 1e-12 * p.k);
    EXPECT_EQ(NormalLuding::k2(p, rEff, dStar), p.k);
    EXPECT_EQ(NormalLuding::k2(p, rEff, 3 * dStar), p.k);
}
