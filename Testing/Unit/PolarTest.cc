// Verification of the polar analysis (Tools/Polar): recovery of a known sixth-order contact
// distribution by the fit methods M1-M3, isotropy, normalisations, the fabric relation, force pdf.
#include "Core/Error.h"
#include "Polar.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

using namespace pdpm;
using namespace pdpm::tools;

namespace {

/// n contacts whose normals have the density a0 [1 + ε2 Y2 + ε4 Y4 + ε6 Y6] on the sphere about z
/// (rejection sampling), normal forces exponential with mean 1, tangential forces 0.3 f_n.
ContactSnapshot sampleContacts(int n, std::array<double, 3> eps, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(0, 1);
    std::exponential_distribution<double> E(1.0);
    const double bound = 1 + 2 * std::abs(eps[0]) + 8 * std::abs(eps[1]) + 16 * std::abs(eps[2]);
    ContactSnapshot s;
    s.boxLo = {0, 0, 0};
    s.boxHi = {1, 1, 1};
    while (int(s.contacts.size()) < n) {
        const double c = 2 * U(rng) - 1;
        const double p = 1 + eps[0] * harmonicY(2, c) + eps[1] * harmonicY(4, c) + eps[2] * harmonicY(6, c);
        if (U(rng) * bound > p) continue;
        const double phi = 2 * std::numbers::pi * U(rng), sn = std::sqrt(1 - c * c);
        ContactRecord r;
        r.i = int(s.contacts.size());
        r.j = r.i + 1;
        r.normal = {sn * std::cos(phi), sn * std::sin(phi), c};
        r.fn = E(rng);
        r.ft = 0.3 * r.fn * Vec3{-std::sin(phi), std::cos(phi), 0};
        s.contacts.push_back(r);
    }
    return s;
}

/// Stratified ("exact quantile") sample: cos θ_k = CDF⁻¹((k + 1/2)/n), golden-angle azimuths. Free of
/// sampling noise, so it measures the bias of the binning and fit methods alone.
ContactSnapshot stratifiedContacts(int n, std::array<double, 3> eps) {
    auto iy = [](int l, double h) {
        const double h2 = h * h;
        switch (l) {
        case 2: return h * (h2 - 1);
        case 4: return h * ((7 * h2 - 10) * h2 + 3);
        default: return h * (((33 * h2 - 63) * h2 + 35) * h2 - 5);
        }
    };
    auto cdf = [&](double h) {
        double v = h + 1;
        for (int l = 0; l < 3; ++l) v += eps[l] * (iy(2 * l + 2, h) - iy(2 * l + 2, -1));
        return 0.5 * v;
    };
    ContactSnapshot s;
    for (int k = 0; k < n; ++k) {
        const double u = (k + 0.5) / n;
        double a = -1, b = 1;
        for (int it = 0; it < 60; ++it) {
            const double m = 0.5 * (a + b);
            (cdf(m) < u ? a : b) = m;
        }
        const double c = 0.5 * (a + b), sn = std::sqrt(std::max(0.0, 1 - c * c));
        const double phi = k * std::numbers::pi * (3 - std::sqrt(5.0));
        ContactRecord r;
        r.i = k;
        r.j = k + 1;
        r.normal = {sn * std::cos(phi), sn * std::sin(phi), c};
        r.fn = 1;
        s.contacts.push_back(r);
    }
    return s;
}

} // namespace

TEST(PolarTest, MethodsHaveNegligibleBias) {
    const std::array<double, 3> eps{0.1, -0.03, 0.01};
    const PolarResult r = analysePolar(stratifiedContacts(100000, eps), PolarConfig{});
    // M2 integrates the model exactly over each bin: only the sample's discreteness is left (measured
    // 3.5e-6 ... 4.9e-6). M1 and M3 evaluate P(theta) at the bin centres, a midpoint-rule bias of the
    // default bins (measured 1.3e-4 ... 1.9e-4, about 2 % of eps6 = 0.01); each bound is about 2.5 x
    // its measurement, so a bias of a few per cent of eps2 or a sign slip in eps4 or eps6 fails.
    for (const HarmonicFit* f : {&r.m1, &r.m2, &r.m3})
        for (int l = 0; l < 3; ++l)
            EXPECT_NEAR(f->eps[l], eps[l], f == &r.m2 ? 1.2e-5 : 5e-4) << f->method << " eps" << 2 * l + 2;
    EXPECT_NEAR(r.eps2Fabric, eps[0], 1e-4);
    std::cout << "bias (stratified sample): M1 " << r.m1.eps[0] - eps[0] << " " << r.m1.eps[1] - eps[1] << " "
              << r.m1.eps[2] - eps[2] << "; M2 " << r.m2.eps[0] - eps[0] << " " << r.m2.eps[1] - eps[1] << " "
              << r.m2.eps[2] - eps[2] << "; M3 " << r.m3.eps[0] - eps[0] << " " << r.m3.eps[1] - eps[1] << " "
              << r.m3.eps[2] - eps[2] << "\n";
}

TEST(PolarTest, RecoversSixthOrderDistributionByAllMethods) {
    const std::array<double, 3> eps{0.1, -0.03, 0.01};
    const ContactSnapshot s = sampleContacts(100000, eps, 42);
    const PolarResult r = analysePolar(s, PolarConfig{});
    for (const HarmonicFit* f : {&r.m1, &r.m2, &r.m3}) {
        for (int l = 0; l < 3; ++l) {
            EXPECT_NEAR(f->eps[l], eps[l], 0.005) << f->method << " eps" << 2 * l + 2;
            EXPECT_GT(f->se[l], 0);
            EXPECT_LT(std::abs(f->eps[l] - eps[l]), 3 * f->se[l]);  // consistent with the reported error
        }
        std::cout << f->method << ": a0 = " << f->a0 << " eps2 = " << f->eps[0] << " ± " << f->se[0]
                  << ", eps4 = " << f->eps[1] << " ± " << f->se[1] << ", eps6 = " << f->eps[2] << " ± " << f->se[2] << "\n";
    }
    EXPECT_NEAR(r.m1.a0, 0.5, 0.01);
    EXPECT_NEAR(r.m3.a0, 0.5, 0.01);
    // the second-moment (fabric) relation: ε2 = 15/4 (F_zz − 1/3), independent of ε4, ε6
    EXPECT_NEAR(r.eps2Fabric, eps[0], 0.01);
    std::cout << "fabric: eps2_fabric = " << r.eps2Fabric << ", Fdev/sqrt3 = " << r.Fdev / std::sqrt(3.0) << "\n";
}

TEST(PolarTest, IsotropicSetGivesZeroWithinErrors) {
    const ContactSnapshot s = sampleContacts(100000, {0, 0, 0}, 7);
    const PolarResult r = analysePolar(s, PolarConfig{});
    for (const HarmonicFit* f : {&r.m1, &r.m2, &r.m3})
        for (int l = 0; l < 3; ++l) {
            EXPECT_LT(std::abs(f->eps[l]), 3.5 * f->se[l] + 1e-4) << f->method << " eps" << 2 * l + 2;
            std::cout << f->method << " eps" << 2 * l + 2 << " = " << f->eps[l] << " ± " << f->se[l] << "\n";
        }
}

TEST(PolarTest, NormalisationsAndForceDistributions) {
    const ContactSnapshot s = sampleContacts(20000, {0.05, 0, 0}, 3);
    for (bool cosNorm : {false, true}) {
        PolarConfig cfg;
        cfg.cosNormalisation = cosNorm;
        cfg.pdfMax = 50;  // everything inside the range
        const PolarResult r = analysePolar(s, cfg);
        double sumB = 0, intB = 0, sumH = 0, intH = 0;
        for (const PolarBin& b : r.binWidth) {
            sumB += b.fraction;
            intB += 2 * b.P * (cosNorm ? std::cos(b.lo) - std::cos(b.hi) : std::sin(b.theta) * (b.hi - b.lo));
            EXPECT_NEAR(b.ft, 0.3 * b.fn, 1e-12);
            EXPECT_NEAR(b.psi, 0.3 / cfg.mu, 1e-12);
        }
        for (const PolarBin& b : r.constHeight) {
            sumH += b.fraction;
            intH += 2 * b.P * (std::cos(b.lo) - std::cos(b.hi));
        }
        EXPECT_NEAR(sumB, 1, 1e-12);
        EXPECT_NEAR(sumH, 1, 1e-12);
        EXPECT_NEAR(intH, 1, 1e-12);
        EXPECT_NEAR(intB, 1, 1e-12);
        for (int a = 0; a < 4; ++a) {
            double integral = 0;
            for (double p : r.pdf[a]) integral += p * cfg.pdfMax / cfg.pdfBins;
            EXPECT_NEAR(integral, 1, 1e-12);
        }
        EXPECT_LT(r.pdfCounts[0], r.pdfCounts[2]);  // more contacts near z for ε2 > 0
        EXPECT_EQ(r.pdfCounts[3], 20000);
    }
}

TEST(PolarTest, BadConfigurationThrows) {
    const ContactSnapshot s = sampleContacts(100, {0, 0, 0}, 1);
    PolarConfig cfg;
    cfg.axis = {0, 0, 0};
    EXPECT_THROW(analysePolar(s, cfg), InputError);
    cfg = PolarConfig{};
    cfg.chi = 1;
    EXPECT_THROW(analysePolar(s, cfg), InputError);
    EXPECT_THROW(analysePolar(ContactSnapshot{}, PolarConfig{}), InputError);
}
