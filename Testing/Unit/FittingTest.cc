// Unit tests of Tools/Fitting: parameters of synthetic data made with known parameters (Table 2.2/2.3
// values) are recovered; with noise, the standard errors cover the truth and scale like 1/sqrt(n).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "Core/Error.h"
#include "Fitting.h"
#include "IO/AtomicFile.h"
#include "TempDir.h"

using namespace pdpm;

namespace {
std::vector<double> grid(double a, double b, int n) {
    std::vector<double> x;
    for (int i = 0; i < n; ++i) x.push_back(a + (b - a) * i / (n - 1));
    return x;
}
} // namespace

TEST(Fitting, RecoversCstarExactly) {
    const auto v = grid(0.67, 0.82, 40);
    std::vector<double> c;
    for (double x : v) c.push_back(cstarModel(x, 6, 8.37, 0.5998, 0.6625));
    const FitResult f = fitCstar(v, c, 6);
    EXPECT_TRUE(f.converged);
    EXPECT_NEAR(f.get("C1"), 8.37, 1e-4);
    EXPECT_NEAR(f.get("alpha"), 0.5998, 1e-5);
    EXPECT_NEAR(f.get("v_c"), 0.6625, 1e-6);
    EXPECT_EQ(f.get("C0"), 6.0);
    EXPECT_EQ(f.se("C0"), 0.0);
}

TEST(Fitting, RecoversRattlersPressureAndSaturation) {
    const auto v = grid(0.67, 0.82, 30);
    std::vector<double> phi, p, C;
    for (double x : v) {
        phi.push_back(rattlerModel(x, 0.1507, 15.68, 0.6625));
        C.push_back(cstarModel(x, 6, 8, 0.6, 0.66) * 0.9);
        p.push_back(pressureModel(x, C.back(), 0.04006, 0.0327, 0.6619));
    }
    const FitResult r = fitRattlers(v, phi, 0.6625);
    EXPECT_NEAR(r.get("phi_c"), 0.1507, 1e-6);
    EXPECT_NEAR(r.get("phi_v"), 15.68, 1e-4);
    const FitResult q = fitPressure(v, C, p);
    EXPECT_NEAR(q.get("p0"), 0.04006, 1e-6);
    EXPECT_NEAR(q.get("gamma_p"), 0.0327, 1e-8);  // noise-free: measured to round-off (2026-12-06)
    EXPECT_NEAR(q.get("v_c"), 0.6619, 1e-6);
    const auto e = grid(0, 0.3, 50);
    std::vector<double> s;
    for (double x : e) s.push_back(saturationModel(x, 0.12, 0.01, 30));
    const FitResult g = fitSaturation(e, s);
    EXPECT_NEAR(g.get("q_max"), 0.12, 1e-7);
    EXPECT_NEAR(g.get("q_0"), 0.01, 1e-7);
    EXPECT_NEAR(g.get("beta"), 30, 1e-4);
}

// Eq. (2.20) with Table 2.3's fabric row (Q_max fixed to 0) and stress row (free).
TEST(Fitting, RecoversVolumeDependence) {
    const auto v = grid(0.67, 0.8, 12);
    std::vector<double> f, s;
    for (double x : v) {
        f.push_back(volumeDependenceModel(x, 0, 0.1694, 4.562, 0.6653));
        s.push_back(volumeDependenceModel(x, 0.1137, 0.09166 - 0.1137, 7.916, 0.6653));
    }
    const FitResult a = fitVolumeDependence(v, f, 0.6653, true);
    EXPECT_EQ(a.get("Q_max"), 0.0);
    EXPECT_NEAR(a.get("Q_v"), 0.1694, 1e-6);
    EXPECT_NEAR(a.get("alpha"), 4.562, 1e-4);
    const FitResult b = fitVolumeDependence(v, s, 0.6653, false);
    EXPECT_NEAR(b.get("Q_max"), 0.1137, 1e-5);
    EXPECT_NEAR(b.get("alpha"), 7.916, 1e-6);  // measured 6e-15 (2026-12-06)
}

// Gaussian noise: estimates within 4 standard errors of the truth, and the standard error of C1
// shrinks by about 2 when the number of points grows by 4.
TEST(Fitting, StandardErrorsFromTheJacobian) {
    std::mt19937_64 rng(3);
    std::normal_distribution<double> noise(0, 0.05);
    double se[2];
    int k = 0;
    for (int n : {100, 400}) {
        const auto v = grid(0.67, 0.82, n);
        std::vector<double> c;
        for (double x : v) c.push_back(cstarModel(x, 6, 8.0, 0.6, 0.66) + noise(rng));
        const FitResult f = fitCstar(v, c, 6);
        EXPECT_LT(std::fabs(f.get("C1") - 8.0), 4 * f.se("C1"));
        EXPECT_LT(std::fabs(f.get("alpha") - 0.6), 4 * f.se("alpha"));
        EXPECT_LT(std::fabs(f.get("v_c") - 0.66), 4 * f.se("v_c"));
        EXPECT_NEAR(f.rms, 0.05, 0.01);
        se[k++] = f.se("C1");
    }
    EXPECT_NEAR(se[0] / se[1], 2.0, 0.4);
}

// Points at one volume fraction (a D2 test at constant volume) cannot fix C1, alpha and v_c: the fit
// says so instead of reporting the near-zero errors of the pseudo-inverse.
TEST(Fitting, UndeterminedParametersAreReportedAsSuch) {
    std::mt19937_64 rng(5);
    std::normal_distribution<double> noise(0, 0.01);
    std::vector<double> v(40, 0.78), c;
    for (double x : v) c.push_back(cstarModel(x, 6, 8.0, 0.6, 0.66) + noise(rng));
    const FitResult f = fitCstar(v, c, 6);
    EXPECT_FALSE(f.determined);
    int undetermined = 0;
    for (bool u : f.undetermined) undetermined += u ? 1 : 0;
    EXPECT_GE(undetermined, 2);
    EXPECT_FALSE(f.undetermined[0]) << "C0 is fixed";
    // a well-posed fit stays determined with finite errors
    const auto vg = grid(0.67, 0.82, 100);
    std::vector<double> cg;
    for (double x : vg) cg.push_back(cstarModel(x, 6, 8.0, 0.6, 0.66) + noise(rng));
    const FitResult g = fitCstar(vg, cg, 6);
    EXPECT_TRUE(g.determined);
    for (bool u : g.undetermined) EXPECT_FALSE(u);
}

// The reduced model: D2-like runs made from Eq. (2.17)/(2.18) with parameters following Eq. (2.20)
// give back the Eq. (2.20) parameters, and the prediction of a run made with the same law is exact.
TEST(Fitting, AnisotropyModelCalibrationAndPrediction) {
    const double vc = 0.6653;
    auto sm = [&](double v) { return volumeDependenceModel(v, 0.05, 0.08, 8.0, vc); };
    auto bs = [&](double v) { return volumeDependenceModel(v, 20, 40, 10.0, vc); };
    auto fm = [&](double v) { return volumeDependenceModel(v, 0, 0.17, 4.5, vc); };
    auto bf = [&](double v) { return volumeDependenceModel(v, 0, 58, 5.4, vc); };
    std::vector<CsvTable> runs;
    for (double v : {0.68, 0.70, 0.72, 0.75, 0.78}) {
        CsvTable t;
        t.columns = {"tau", "p_nd", "volume_fraction", "eps_dev", "s_dev", "F_dev"};
        t.source = "synthetic";
        for (double e : grid(0, 0.3, 60))
            t.rows.push_back({e / 0.3, 0.01, v, e, saturationModel(e, sm(v), 0.01, bs(v)), saturationModel(e, fm(v), 0.02, bf(v))});
        runs.push_back(t);
    }
    const AnisotropyModel m = calibrateAnisotropy(runs, vc);
    EXPECT_NEAR(m.sMax.value[0], 0.05, 1e-5);
    EXPECT_NEAR(m.sMax.value[2], 8.0, 1e-3);
    EXPECT_NEAR(m.fMax.value[1], 0.17, 1e-5);
    EXPECT_NEAR(m.betaF.value[2], 5.4, 1e-3);
    const std::vector<double> v = {0.7, 0.72, 0.75}, e = {0.01, 0.05, 0.1};
    const auto ps = m.predictS(v, e, 0.01);
    for (std::size_t i = 0; i < v.size(); ++i) EXPECT_NEAR(ps[i], saturationModel(e[i], sm(v[i]), 0.01, bs(v[i])), 1e-6);
    EXPECT_THROW(calibrateAnisotropy({runs[0], runs[1]}, vc), InputError);
    EXPECT_FALSE(m.stressQmaxFixed);
    // runs at the same volume fraction count once: four runs at two v are refused, three v fix Q_max
    EXPECT_THROW(calibrateAnisotropy({runs[0], runs[4], runs[4], runs[4]}, vc), InputError);
    const AnisotropyModel three = calibrateAnisotropy({runs[0], runs[2], runs[4], runs[4]}, vc);
    EXPECT_TRUE(three.stressQmaxFixed);
    EXPECT_TRUE(three.sMax.fixed[0]);
    EXPECT_EQ(three.sMax.value[0], 0.0);
    // below the lowest calibration run (0.68) the coefficients are held at their value there; above
    // it Eq. 2.20 applies as fitted (the 0.79 point lies above the highest run, 0.78)
    EXPECT_DOUBLE_EQ(m.vLo, 0.68);
    const auto low = m.predictS({0.671, 0.79}, {0.05, 0.05}, 0.01);
    EXPECT_NEAR(low[0], saturationModel(0.05, sm(0.68), 0.01, bs(0.68)), 1e-6);
    EXPECT_NEAR(low[1], saturationModel(0.05, sm(0.79), 0.01, bs(0.79)), 1e-6);
}

TEST(Fitting, AnisotropyTableFile) {
    const pdpm::testing::TempDir tmp;
    const std::string f = tmp.str() + "/t23.csv";
    writeWholeFile(f, "# Table 2.3\nparameter,Q_max,Q_c,alpha\ns_dev_max,0.1137,0.09166,7.916\nbeta_s,30.76,57.00,16.86\n"
                      "F_dev_max,0,0.1694,4.562\nbeta_F,0,57.89,5.366\n");
    const AnisotropyModel m = readAnisotropyTable(f, 0.6653);
    EXPECT_DOUBLE_EQ(m.sMax.value[0], 0.1137);
    EXPECT_NEAR(m.sMax.value[0] + m.sMax.value[1], 0.09166, 1e-15);  // Q_c = Q_max + Q_v
    EXPECT_DOUBLE_EQ(m.betaF.value[2], 5.366);
    EXPECT_DOUBLE_EQ(m.vLo, 0.0);  // table coefficients: no bound
    const auto p = m.predictF({0.7}, {0.1}, 0.02);
    EXPECT_NEAR(p[0], saturationModel(0.1, volumeDependenceModel(0.7, 0, 0.1694, 4.562, 0.6653), 0.02,
                                      volumeDependenceModel(0.7, 0, 57.89, 5.366, 0.6653)), 1e-12);
    for (const char* bad : {"parameter,Q_max,Q_c\ns_dev_max,1,2\n",                                      // header
                            "parameter,Q_max,Q_c,alpha\ns_dev_max,1,x,3\n",                              // number
                            "parameter,Q_max,Q_c,alpha\nbeta_x,1,2,3\n",                                 // name
                            "parameter,Q_max,Q_c,alpha\ns_dev_max,1,2,3,\n",                             // extra cell
                            "parameter,Q_max,Q_c,alpha\ns_dev_max,1,2,3\nbeta_s,1,2,3\n",             // rows missing
                            "parameter,Q_max,Q_c,alpha\ns_dev_max,1,2,3\ns_dev_max,1,2,3\n"}) {     // given twice
        writeWholeFile(f, bad);
        EXPECT_THROW(readAnisotropyTable(f, 0.6653), InputError) << bad;
    }
}

// --branch auto: a cycle (the axial strain turns back after tau = 0.5) gives its unloading rows; a
// deviatoric test, whose tau also runs to 1 but whose axial strain never turns back, gives every test
// row (before: only its second half); a file without eps_zz keeps the tau rule.
TEST(Fitting, AutoBranchTellsACycleFromAOneWayTest) {
    std::string cycle = "tau,p_nd,eps_zz\n-0.5,0,0\n", shear = cycle, old = "tau,p_nd\n";
    for (int k = 0; k <= 10; ++k) {
        const double tau = 0.1 * k;
        cycle += std::to_string(tau) + ",0.01," + std::to_string(0.1 * (0.5 - std::abs(tau - 0.5))) + "\n";
        shear += std::to_string(tau) + ",0.01," + std::to_string(0.02 * tau) + "\n";
        old += std::to_string(tau) + ",0.01\n";
    }
    const auto rows = [](const std::string& text) { return selectRows(parseCsv(text, "t.csv"), BranchSelect::Auto).size(); };
    EXPECT_EQ(rows(cycle), 5u);   // tau 0.6 ... 1.0
    EXPECT_EQ(rows(shear), 11u);  // tau 0 ... 1 (the preparation row at -0.5 left out)
    EXPECT_EQ(rows(old), 5u);
}

TEST(Fitting, RefusesTooFewPoints) {
    EXPECT_THROW(fitCstar({0.7, 0.71}, {6.5, 6.6}), InputError);
    EXPECT_THROW(fitSaturation({0.1, 0.2}, {0.1}), InputError);
}
