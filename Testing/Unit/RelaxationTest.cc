// Time-dependent relaxation ingredient (Contacts/RelaxationLaws.h) as a pure function of one contact:
//  - a held overlap decays as (1 + t/t0)^(-C) (Eq. 4.3) within 0.1 % for linear, Hertz and Luding bases;
//  - C = 0 leaves the base law untouched;
//  - reloading after a hold: elastic along the base stiffness from the relaxed state, and the clock
//    restarts once the force exceeds the pre-hold maximum;
//  - energy bookkeeping: work put in along the overlap path = stored elastic energy + relaxation work;
//  - the history is complete: continuing from a copy gives bit-identical results (restart round-trip).
// Expected curves are computed here from Eq. (4.3) and the base equations, not from kernel helpers.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "Contacts/ContactLaw.h"
#include "Contacts/RelaxationLaws.h"
#include "SingleContact.h"

using namespace pdpm;

namespace {


ContactParameters hertzParams(double C, double t0, double scale) {
    ContactParameters p;
    p.youngEff = 1e7;
    p.shearEff = 4e6;
    p.restitution = 1;
    p.muS = p.muD = 0.5;
    return test::withRelaxation(p, C, t0, scale);
}

ContactParameters ludingParams(double C, double t0, double scale) {
    ContactParameters p;
    p.k = 24067;
    p.k1 = p.k / 5;
    p.kc = 0.873 * p.k;
    p.phiF = 0.05;
    p.gamma = 0;
    p.kt = 0.286 * p.k;
    p.muS = p.muD = 0.5;
    p.kr = 0.286 * p.k;
    p.muR = 0.5;
    return test::withRelaxation(p, C, t0, scale);
}

// History of a composed law: the normal part's doubles come first; for Relaxing<NormalLinear> and
// Relaxing<NormalHertz> (no base history) h[0] = delta_p, h[1] = clock, h[2] = f_ref, h[3] = W_relax.
using Contact = test::SingleContact;

/// Load in one step to `delta`, then hold for `n` steps; return the largest relative deviation from
/// Eq. (4.3) (clock in lab seconds = steps * dt * scale).
double holdDeviation(const std::string& lawName, const ContactParameters& p, double delta, double dt, int n,
                     double* finalRatio = nullptr) {
    const auto law = makeContactLaw(lawName);
    Contact c(*law, p);
    const double f0 = c.step(delta, dt).fn;
    EXPECT_GT(f0, 0);
    double worst = 0, ratio = 1;
    for (int k = 1; k <= n; ++k) {
        const double f = c.step(delta, dt).fn;
        const double t = k * dt * p.relaxTimeScale;
        const double expected = f0 * std::pow(1 + t / p.relaxT0, -p.relaxC);
        worst = std::max(worst, std::abs(f - expected) / expected);
        ratio = f / f0;
    }
    if (finalRatio) *finalRatio = ratio;
    return worst;
}

} // namespace

TEST(Relaxation, RegisteredByName) {
    for (const char* n : {"linear-relax", "hertz-mindlin-relax", "luding-relax"}) {
        const auto law = makeContactLaw(n);
        EXPECT_EQ(law->name(), n);
    }
    EXPECT_EQ(makeContactLaw("linear-relax")->historySize(), makeContactLaw("linear")->historySize() + 4);
}

TEST(Relaxation, ValidateRefusesBadParameters) {
    const auto law = makeContactLaw("linear-relax");
    EXPECT_NO_THROW(law->validate(test::linearRelaxParams(0.08, 0.3, 1), "pair"));
    EXPECT_THROW(law->validate(test::linearRelaxParams(-0.1, 0.3, 1), "pair"), InputError);
    EXPECT_THROW(law->validate(test::linearRelaxParams(0.08, 0, 1), "pair"), InputError);
    EXPECT_THROW(law->validate(test::linearRelaxParams(0.08, 0.3, -1), "pair"), InputError);
}

TEST(Relaxation, HeldOverlapFollowsEq43Linear) {
    double ratio = 1;
    // 300 lab seconds in 3000 steps of 1e-5 s DEM time (scale 1e4 lab s per DEM s).
    const double dev = holdDeviation("linear-relax", test::linearRelaxParams(0.0792, 0.2894, 1e4), 1e-5, 1e-5, 3000, &ratio);
    EXPECT_LT(dev, 1e-9);  // the step factors telescope: exact up to round-off
    // The decay is substantial: (1 + 300/0.2894)^(-0.0792) ~ 0.58.
    EXPECT_LT(ratio, 0.62);
    EXPECT_GT(ratio, 0.54);
}

TEST(Relaxation, HeldOverlapFollowsEq43Hertz) {
    const double dev = holdDeviation("hertz-mindlin-relax", hertzParams(0.0444, 0.7462, 1e4), 2e-6, 1e-5, 3000);
    EXPECT_LT(dev, 1e-9);
}

TEST(Relaxation, HeldOverlapFollowsEq43Luding) {
    // Below and above the plastic flow limit delta*_max = k/(k-k1) phi_f 2 rEff = 1.25e-4 m.
    EXPECT_LT(holdDeviation("luding-relax", ludingParams(0.0702, 0.2274, 1e4), 2e-5, 1e-5, 3000), 1e-9);
    EXPECT_LT(holdDeviation("luding-relax", ludingParams(0.0702, 0.2274, 1e4), 2e-4, 1e-5, 3000), 1e-9);
}

TEST(Relaxation, OffMeansBaseLaw) {
    for (const auto& [relaxName, baseName, p] :
         {std::tuple{"linear-relax", "linear", test::linearRelaxParams(0, 0.3, 1e4)},
          std::tuple{"luding-relax", "luding", ludingParams(0, 0.3, 1e4)},
          std::tuple{"hertz-mindlin-relax", "hertz-mindlin", hertzParams(0, 0.3, 1e4)}}) {
        const auto a = makeContactLaw(relaxName), b = makeContactLaw(baseName);
        Contact ca(*a, p), cb(*b, p);
        for (int k = 0; k < 200; ++k) {
            const double d = 1e-5 * (1 + std::sin(0.05 * k));
            EXPECT_EQ(ca.step(d, 1e-5, 1e-3).fn, cb.step(d, 1e-5, 1e-3).fn) << relaxName << " step " << k;
        }
    }
    // hertz-rolling-relax (the driver's --hertz_modulus) has Hertz's normal force: the same as
    // hertz-mindlin's for a purely normal motion when C = 0
    {
        const auto a = makeContactLaw("hertz-rolling-relax"), b = makeContactLaw("hertz-mindlin");
        const ContactParameters p = hertzParams(0, 0.3, 1e4);
        Contact ca(*a, p), cb(*b, p);
        for (int k = 0; k < 200; ++k) {
            const double d = 1e-5 * (1 + std::sin(0.05 * k));
            EXPECT_EQ(ca.step(d, 1e-5, 1e-3).fn, cb.step(d, 1e-5, 1e-3).fn) << "hertz-rolling-relax step " << k;
        }
    }
    // Time scale 0: clock frozen, no decay even with C > 0.
    double ratio = 0;
    holdDeviation("linear-relax", test::linearRelaxParams(0.08, 0.3, 0), 1e-5, 1e-5, 100, &ratio);
    EXPECT_EQ(ratio, 1.0);
}

TEST(Relaxation, ReloadingAfterHold) {
    // Linear base: after a hold the elastic overlap is delta - delta_p. Reloading is elastic with
    // stiffness k from the relaxed force (the clock keeps running but the force is then mostly the
    // new elastic increment); once the force exceeds the pre-hold maximum f_ref the clock restarts.
    const ContactParameters p = test::linearRelaxParams(0.08, 0.3, 1e4);
    const auto law = makeContactLaw("linear-relax");
    Contact c(*law, p);
    const double dt = 1e-5, d1 = 1e-5;
    const double f0 = c.step(d1, dt).fn;
    for (int k = 0; k < 1000; ++k) c.step(d1, dt);
    const double fHeld = c.step(d1, dt).fn;
    const double dp = c.h[0];
    EXPECT_NEAR(dp, d1 - fHeld / p.k, 1e-12 * d1);  // force consistent with geometry
    EXPECT_LT(fHeld, 0.75 * f0);
    const double clockBefore = c.h[1];
    // One small reload step, still below f_ref: elastic increment k * dd, minus one step of decay.
    const double dd = 1e-7;
    const double f1 = c.step(d1 + dd, dt).fn;
    const double decay = std::pow((0.3 + clockBefore + dt * 1e4) / (0.3 + clockBefore), -0.08);
    EXPECT_NEAR(f1, (fHeld + p.k * dd) * decay, 1e-9 * f0);
    EXPECT_GT(c.h[1], clockBefore);  // clock still running
    // Reload past the old maximum: clock restarts at 0 and f_ref follows the force.
    const double dpBefore = c.h[0];
    const double dBig = d1 + 2 * (d1 - fHeld / p.k) + 1e-6;
    const double f2 = c.step(dBig, dt).fn;
    EXPECT_EQ(c.h[1], 0.0);
    EXPECT_DOUBLE_EQ(c.h[2], f2);
    EXPECT_GT(f2, f0);
    EXPECT_NEAR(f2, p.k * (dBig - dpBefore), 1e-9 * f2);  // loading is elastic from the relaxed state
    // Unloading: the force reaches zero at delta = delta_p, not at delta = 0.
    const double dpNow = c.h[0];
    EXPECT_GT(dpNow, 0);
    EXPECT_EQ(c.step(0.5 * dpNow, dt).fn, 0.0);
}

TEST(Relaxation, EnergyBookkeeping) {
    // Path: ramp up, hold, ramp further up, hold, unload halfway. Work put in, integrated by the
    // trapezoid rule along the imposed overlap path, equals the elastic energy now stored plus the
    // work dissipated by relaxation (history slot W_relax).
    for (const char* name : {"linear-relax", "hertz-mindlin-relax"}) {
        const bool hertz = std::string(name).rfind("hertz", 0) == 0;
        const ContactParameters p = hertz ? hertzParams(0.06, 0.3, 1e4) : test::linearRelaxParams(0.06, 0.3, 1e4);
        const auto law = makeContactLaw(name);
        Contact c(*law, p);
        const double dt = 1e-5, dmax = hertz ? 5e-6 : 1e-5;
        std::vector<double> path;
        for (int k = 1; k <= 500; ++k) path.push_back(dmax * k / 500);
        for (int k = 0; k < 1000; ++k) path.push_back(dmax);
        for (int k = 1; k <= 500; ++k) path.push_back(dmax * (1 + 0.5 * k / 500));
        for (int k = 0; k < 1000; ++k) path.push_back(1.5 * dmax);
        for (int k = 1; k <= 200; ++k) path.push_back(1.5 * dmax - 0.2 * dmax * k / 200);
        double work = 0, fPrev = 0, dPrev = 0;
        ContactOutput o;
        for (double d : path) {
            o = c.step(d, dt);
            work += 0.5 * (o.fn + fPrev) * (d - dPrev);
            fPrev = o.fn;
            dPrev = d;
        }
        const double wRelax = c.h[3];  // normal part first in the history; linear/Hertz own none
        EXPECT_GT(wRelax, 0.05 * work) << name;
        EXPECT_NEAR(work, o.energy + wRelax, 2e-3 * work) << name;
    }
}

TEST(Relaxation, HistoryRoundTrip) {
    // Evaluate up to the middle of a hold, copy the history (what a restart file stores), continue
    // both: every force must be bit-identical.
    const ContactParameters p = ludingParams(0.07, 0.23, 1e4);
    const auto law = makeContactLaw("luding-relax");
    Contact a(*law, p);
    for (int k = 1; k <= 100; ++k) a.step(2e-4 * k / 100, 1e-5);
    for (int k = 0; k < 300; ++k) a.step(2e-4, 1e-5);
    Contact b(*law, p);
    b.h = a.h;
    for (int k = 0; k < 300; ++k) {
        const double d = k < 150 ? 2e-4 : 2e-4 + 1e-7 * (k - 150);
        EXPECT_EQ(a.step(d, 1e-5).fn, b.step(d, 1e-5).fn) << k;
    }
    EXPECT_EQ(a.h, b.h);
    // A fresh history (clock 0, no plastic overlap) would not give the same force: the history matters.
    Contact fresh(*law, p);
    EXPECT_NE(fresh.step(2e-4, 1e-5).fn, a.step(2e-4, 1e-5).fn);
}

TEST(Relaxation, ClockMemoryShortensTheClockByTheLoadRatio) {
    // Memory m > 0: a reload f_ref -> f_new multiplies the clock by (f_ref/f_new)^(1/m) (the factors
    // of the reload's steps telescope) instead of restarting it; the next hold then continues Eq. (4.3)
    // from that age: f(t) = f_new ((t0 + t_s + t)/(t0 + t_s))^(-C).
    const double C = 0.08, t0 = 0.3, scale = 1e4, dt = 1e-5, d1 = 1e-5;
    for (double m : {0.0, 0.1, 0.5}) {
        ContactParameters p = test::linearRelaxParams(C, t0, scale);
        p.relaxMemory = m;
        const auto law = makeContactLaw("linear-relax");
        Contact c(*law, p);
        c.step(d1, dt);
        for (int k = 0; k < 3000; ++k) c.step(d1, dt);  // 300 lab s
        const double age = c.h[1], fRef = c.h[2];
        EXPECT_NEAR(age, 3000 * dt * scale, 1e-9 * age);
        // Reload in 50 equal steps to 1.5 times the old peak force (elastic from the relaxed state), with
        // the clock frozen (relaxTimeScale 0) so that only the load ratio acts on it.
        c.p.relaxTimeScale = 0;
        const double dp = c.h[0];
        const double dTarget = dp + 1.5 * fRef / p.k;
        const double dStart = d1;
        double ageAfter = age;
        for (int k = 1; k <= 50; ++k) {
            c.step(dStart + (dTarget - dStart) * k / 50, dt);
            ageAfter = c.h[1];
        }
        const double fNew = c.h[2];
        EXPECT_NEAR(fNew, 1.5 * fRef, 1e-9 * fRef);  // frozen clock: no relaxation during the reload
        if (m == 0) {
            EXPECT_EQ(ageAfter, 0.0);
        } else {
            // Steps above f_ref multiply the clock by f_ref/f_trial; the factors telescope.
            EXPECT_NEAR(ageAfter, age * std::pow(fRef / fNew, 1 / m), 1e-12 * age) << m;
        }
        c.p.relaxTimeScale = scale;
        // The next hold follows Eq. (4.3) from the clock it starts with.
        const double tStart = c.h[1];
        const double f0 = c.step(dTarget, dt).fn;
        const double tFirst = c.h[1];
        double worst = 0;
        for (int k = 1; k <= 2000; ++k) {
            const double f = c.step(dTarget, dt).fn;
            const double expected = f0 * std::pow((t0 + tFirst + k * dt * scale) / (t0 + tFirst), -C);
            worst = std::max(worst, std::abs(f - expected) / expected);
        }
        EXPECT_LT(worst, 1e-9) << m;
        EXPECT_GE(tFirst, tStart);
    }
    // An aged contact relaxes less in its next hold than a restarted one.
    auto dropAfterReload = [&](double m) {
        ContactParameters p = test::linearRelaxParams(C, t0, scale);
        p.relaxMemory = m;
        const auto law = makeContactLaw("linear-relax");
        Contact c(*law, p);
        c.step(d1, dt);
        for (int k = 0; k < 3000; ++k) c.step(d1, dt);
        const double d2 = c.h[0] + 1.2 * c.h[2] / p.k;
        const double f0 = c.step(d2, dt).fn;
        double f = f0;
        for (int k = 0; k < 3000; ++k) f = c.step(d2, dt).fn;
        return 1 - f / f0;
    };
    const double restarted = dropAfterReload(0), aged = dropAfterReload(0.2);
    std::printf("relative drop of the second hold: clock restarted %.4f, memory 0.2 %.4f\n", restarted, aged);
    EXPECT_GT(restarted, 0.35);
    EXPECT_LT(aged, 0.8 * restarted);
    // Validation refuses a negative memory.
    ContactParameters bad = test::linearRelaxParams(C, t0, scale);
    bad.relaxMemory = -1;
    EXPECT_THROW(makeContactLaw("linear-relax")->validate(bad, "pair"), InputError);
}
