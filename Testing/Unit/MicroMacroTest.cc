// Unit tests of Tools/MicroMacro on synthetic contact sets whose stress, fabric and coordination
// are known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>

#include "IO/Csv.h"
#include "MicroMacro.h"

using namespace pdpm;

namespace {
constexpr double kPi = std::numbers::pi;

// A central particle 0 (radius R at the origin) touched by one particle per direction in `dirs`
// (radius R, centre at distance d = 2R - overlap), with normal force fn[k].
struct Star {
    ParticleData P;
    std::vector<ContactRecord> C;
    double R = 1e-3, d = 1.98e-3;
    Star(const std::vector<Vec3>& dirs, const std::vector<double>& fn) {
        P.add({0, 0, 0}, R, 2000, 0);
        for (std::size_t k = 0; k < dirs.size(); ++k) {
            const Vec3 nrm = dirs[k] / norm(dirs[k]);
            const std::size_t i = P.add(d * nrm, R, 2000, 0);
            ContactRecord c;
            c.i = static_cast<int>(i);
            c.j = 0;
            c.n = nrm;  // from j (centre) to i
            c.fn = fn[k];
            c.branch = d * nrm;
            c.overlap = 2 * R - d;
            C.push_back(c);
        }
    }
};
std::vector<Vec3> axes6() { return {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}; }
} // namespace

// Six equal contacts along +-x, +-y, +-z: isotropic stress and fabric, exact coordination numbers.
TEST(MicroMacro, IsotropicStarIsExact) {
    const double f = 3.0;
    Star s(axes6(), std::vector<double>(6, f));
    MacroInput in;
    in.volume = 1e-6;
    in.stiffness = 1e5;
    const MacroResult r = computeMacro(s.P, s.C, in);
    const double V = in.volume;
    // each pair of opposite contacts adds 2 f d to the diagonal entry
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(r.stress(a, a), 2 * f * s.d / V, 1e-12 * f * s.d / V);
    EXPECT_NEAR(r.stress(0, 1), 0, 1e-15);
    EXPECT_NEAR(r.p, 2 * f * s.d / V, 1e-9);
    EXPECT_NEAR(r.sigmaDev, 0, 1e-9 * r.p);
    EXPECT_NEAR(r.sDev, 0, 1e-12);
    EXPECT_NEAR(r.pNd, 2 * s.R * 3 * r.p / (3 * in.stiffness), 1e-15);
    // fabric Eq. 2.9: each contact carries V_0 + V_k = 2 (4/3 pi R^3)
    const double vp = 2 * 4.0 / 3.0 * kPi * std::pow(s.R, 3);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(r.fabric(a, a), 2 * vp / V, 1e-12);
        EXPECT_NEAR(r.fabricNormalised(a, a), 1.0 / 3.0, 1e-15);
    }
    EXPECT_NEAR(r.Fv, 2 * vp / V, 1e-12);
    EXPECT_NEAR(r.Fdev, 0, 1e-12);
    EXPECT_NEAR(r.FnDev, 0, 1e-12);
    // coordination: z = (6, 1, 1, 1, 1, 1, 1): M = 12, only particle 0 has >= 4 contacts
    EXPECT_NEAR(r.Cr, 12.0 / 7.0, 1e-15);
    EXPECT_NEAR(r.Cm, 6.0 / 7.0, 1e-15);
    EXPECT_NEAR(r.Cstar, 6.0, 1e-15);
    EXPECT_NEAR(r.phiR, 6.0 / 7.0, 1e-15);
    EXPECT_NEAR(r.volumeFraction, 7 * 4.0 / 3.0 * kPi * std::pow(s.R, 3) / V, 1e-15);
    EXPECT_EQ(r.contacts, 6);
}

// Forces twice as large along z as along x, y on an isotropic contact network: stress anisotropy with
// isotropic fabric. sigma_zz = 2 sigma_xx -> s_dev = sigma_dev/p = 3/4, shape factor -1/2, major
// eigenvector along z; the z contacts are the strong ones.
TEST(MicroMacro, AnisotropicForceNetwork) {
    const double f = 1.0;
    Star s(axes6(), {f, f, f, f, 2 * f, 2 * f});
    MacroInput in;
    in.volume = 1e-6;
    const MacroResult r = computeMacro(s.P, s.C, in);
    const double unit = 2 * f * s.d / in.volume;
    EXPECT_NEAR(r.stress(0, 0) / unit, 1.0, 1e-12);
    EXPECT_NEAR(r.stress(2, 2) / unit, 2.0, 1e-12);
    EXPECT_NEAR(r.p / unit, 4.0 / 3.0, 1e-12);
    EXPECT_NEAR(r.sigmaDev / unit, 1.0, 1e-12);
    EXPECT_NEAR(r.sDev, 0.75, 1e-12);
    EXPECT_NEAR(r.sDevStar, 0.75, 1e-12);
    EXPECT_NEAR(r.stressAll.lambda[0] / unit, 2.0 / 3.0, 1e-12);
    EXPECT_NEAR(r.stressAll.shape, -0.5, 1e-12);
    EXPECT_NEAR(r.stressAll.theta[0], 0.0, 1e-6);
    EXPECT_NEAR(r.stressAll.theta[1], 90.0, 1e-6);
    EXPECT_NEAR(r.Fdev, 0, 1e-12);
    // strong contacts: fn = 2f > <fn> = 4f/3 -> the two z contacts
    EXPECT_NEAR(r.weakFraction, 4.0 / 6.0, 1e-15);
    EXPECT_NEAR(r.stressStrong.theta[0], 0.0, 1e-6);
    EXPECT_NEAR(r.stressWeak.theta[0], 90.0, 1e-6);  // weak network: x and y only, minor axis z
    EXPECT_NEAR(r.stressWeak.shape, 1.0, 1e-12);     // two equal major eigenvalues in the xy plane
    EXPECT_NEAR(r.fabricStrong.theta[0], 0.0, 1e-6);
}

// Fabric anisotropy: two contacts along +z and -z each counted twice, one along each of +-x, +-y:
// F (Eq. 3.16) = diag(1/4, 1/4, 1/2), deviator (-1/12, -1/12, 1/6): F_dev = F*_dev = 1/4.
TEST(MicroMacro, AnisotropicFabric) {
    std::vector<Vec3> dirs = axes6();
    dirs.push_back({0, 0, 1});
    dirs.push_back({0, 0, -1});
    Star s(dirs, std::vector<double>(8, 1.0));
    MacroInput in;
    in.volume = 1e-6;
    const MacroResult r = computeMacro(s.P, s.C, in);
    EXPECT_NEAR(r.fabricNormalised(2, 2), 0.5, 1e-15);
    EXPECT_NEAR(r.fabricNormalised(0, 0), 0.25, 1e-15);
    EXPECT_NEAR(r.FnDev, 0.25, 1e-12);
    EXPECT_NEAR(r.FnDevStar, 0.25, 1e-12);
    // Eq. 2.9 carries the factor (V_i + V_j)/V per contact: F_dev scales with it
    const double vp = 2 * 4.0 / 3.0 * kPi * std::pow(s.R, 3);
    EXPECT_NEAR(r.Fdev / (8 * vp / in.volume), 0.25, 1e-12);
    EXPECT_NEAR(r.FdevStar, r.Fdev, 1e-12);
    EXPECT_NEAR(r.fabricAll.shape, -0.5, 1e-12);
}

// Eq. 3.19 is taken in the box axes: a tensor whose deviator is a shear in the x-z plane (eigenvectors
// at 45 deg to z, eigenvalues +-c) plus a small axial part eps has t_zz - (t_xx + t_yy)/2 = eps, of
// the sign of eps. An "eigenvalue whose eigenvector is closest to z" would give about +-1.5 c and
// jump by 3 c as eps changes sign.
TEST(MicroMacro, AxialStarIsContinuousThroughIsotropy) {
    const double c = 1e-3;
    for (double eps : {1e-6, -1e-6, 0.0}) {
        Eigen::Matrix3d t = Eigen::Matrix3d::Identity();
        t(0, 2) = t(2, 0) = c;
        t(2, 2) += eps;
        const TensorSummary s = summariseTensor(t);
        EXPECT_NEAR(s.axialStar, eps, 1e-15) << "eps " << eps;
        EXPECT_NEAR(s.lambda[0], c, 1e-5);  // the eigen-analysis itself still sees the shear
    }
}

// Tilted uniaxial network: the major eigenvector makes the tilt angle with z (Eq. 3.20), for angles
// on both sides (projection into [0, 90]).
TEST(MicroMacro, EigenvectorAngleToZ) {
    for (double deg : {0.0, 20.0, 45.0, 70.0, 110.0}) {
        const double a = deg * kPi / 180;
        const Vec3 u{std::sin(a), 0, std::cos(a)};
        Star s({u, -u, u, -u, {0, 1, 0}, {0, -1, 0}}, std::vector<double>(6, 1.0));
        MacroInput in;
        in.volume = 1e-6;
        const MacroResult r = computeMacro(s.P, s.C, in);
        const double expected = deg <= 90 ? deg : 180 - deg;
        EXPECT_NEAR(r.stressAll.theta[0], expected, 1e-6) << deg;
        EXPECT_NEAR(r.fabricAll.theta[0], expected, 1e-6) << deg;
    }
}

// Kinetic stress m v (x) v / V and E_k/E_p.
TEST(MicroMacro, KineticStressAndEnergyRatio) {
    ParticleData P;
    P.add({0, 0, 0}, 1e-3, 2000, 0, {0.5, 0, 0});
    P.add({0.5, 0, 0}, 1e-3, 2000, 0, {0, 0, -0.25});
    MacroInput in;
    in.volume = 2e-6;
    in.kineticEnergy = 3.0;
    in.elasticEnergy = 1.5;
    const MacroResult r = computeMacro(P, {}, in);
    EXPECT_NEAR(r.stress(0, 0), P.m[0] * 0.25 / in.volume, 1e-15);
    EXPECT_NEAR(r.stress(2, 2), P.m[1] * 0.0625 / in.volume, 1e-15);
    EXPECT_EQ(r.stress(0, 2), 0.0);
    EXPECT_NEAR(r.ekOverEp, 2.0, 1e-15);
    EXPECT_EQ(r.Cstar, 0.0);
    EXPECT_EQ(r.phiR, 1.0);
}

// Friction classes of Sec. 3.4.4 and mobilisation |f_t|/(mu f_n).
TEST(MicroMacro, FrictionMobilisationClasses) {
    // normal forces 1,1,1,5 -> mean 2: three weak, one strong
    Star s(std::vector<Vec3>{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}}, {1, 1, 1, 5});
    const double mu = 0.5;
    s.C[0].sliding = true;
    s.C[0].ft = {0, 0.5, 0};   // fully mobilised: 0.5/(0.5*1) = 1
    s.C[1].ft = {0.25, 0, 0};  // 0.5
    s.C[2].ft = {0, 0, 0};     // 0
    s.C[3].sliding = true;
    s.C[3].ft = {0, 2.5, 0};   // 1
    MacroInput in;
    in.volume = 1e-6;
    in.mu = mu;
    const MacroResult r = computeMacro(s.P, s.C, in);
    EXPECT_NEAR(r.weakFraction, 0.75, 1e-15);
    EXPECT_NEAR(r.wsl, 0.25, 1e-15);
    EXPECT_NEAR(r.wst, 0.5, 1e-15);
    EXPECT_NEAR(r.ssl, 0.25, 1e-15);
    EXPECT_NEAR(r.sst, 0.0, 1e-15);
    EXPECT_NEAR(r.mobilisation, (1 + 0.5 + 0 + 1) / 4.0, 1e-15);
    // frictionless input: classes are zero
    in.mu = 0;
    const MacroResult r0 = computeMacro(s.P, s.C, in);
    EXPECT_EQ(r0.wsl + r0.wst + r0.ssl + r0.sst + r0.mobilisation, 0.0);
}

// Mobilisation of the face layer (within 0.1 L of a face of a moving axis) over the rest.
TEST(MicroMacro, MobilisationFaceRatio) {
    Star s(std::vector<Vec3>{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}}, {1, 1, 1, 2});
    s.C[0].ft = {0, 0.5, 0};  // psi 1
    s.C[1].ft = {0, 0, 0.4};  // psi 0.8
    s.C[2].ft = {0.2, 0, 0};  // psi 0.4
    s.C[3].ft = {0, 0.2, 0};  // psi 0.2
    // box [0, 10] x [-5, 5] x [2, 6]; contact points: z = 2.3 (d = 0.3 of 4: 0.075 L, face layer),
    // z = 7.9 (wraps to 3.9, d = 1.9: inner), z = -1.8 (wraps to 2.2, d = 0.2: face layer), z = -0.5
    // (below lo: wraps to 3.5, d = 1.5: inner)
    s.C[0].point = {5, 0, 2.3};
    s.C[1].point = {5, 0, 7.9};
    s.C[2].point = {5, 0, -1.8};
    s.C[3].point = {5, 0, -0.5};
    MacroInput in;
    in.volume = 400;
    in.mu = 0.5;
    in.boxLo = {0, -5, 2};
    in.boxHi = {10, 5, 6};
    // no face axis: not defined
    EXPECT_EQ(computeMacro(s.P, s.C, in).mobilisationFaceRatio, 0.0);
    in.faceAxes = {false, false, true};
    // face layer (1 + 0.4)/2 = 0.7 over inner (0.8 + 0.2)/2 = 0.5
    EXPECT_NEAR(computeMacro(s.P, s.C, in).mobilisationFaceRatio, 0.7 / 0.5, 1e-12);
    // x as well: every point has x = 5, the middle of [0, 10], so nothing changes
    in.faceAxes = {true, false, true};
    EXPECT_NEAR(computeMacro(s.P, s.C, in).mobilisationFaceRatio, 0.7 / 0.5, 1e-12);
    // y: y = 0 is the middle of [-5, 5] too; moving the second contact to y = 4.6 (0.4 from the face)
    // puts it in the face layer: (1 + 0.8 + 0.4)/3 over 0.2
    in.faceAxes = {false, true, true};
    s.C[1].point.y = 4.6;
    EXPECT_NEAR(computeMacro(s.P, s.C, in).mobilisationFaceRatio, (2.2 / 3) / 0.2, 1e-12);
    // frictionless: not defined
    in.mu = 0;
    EXPECT_EQ(computeMacro(s.P, s.C, in).mobilisationFaceRatio, 0.0);
}

// A macro file of an earlier version (a subset of today's columns) keeps its rows on reload, the new
// columns NaN; a file with other columns is moved aside to PATH.old.
TEST(MicroMacro, ReloadKeepsAnEarlierVersionsRowsAndMovesAForeignFileAside) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / "pdpm_macro_reload";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::vector<std::string>& cols = macroColumns();
    std::vector<std::string> older(cols.begin(), cols.end() - 1);  // without the last column
    std::vector<std::vector<double>> rows = {std::vector<double>(older.size(), 1.5), std::vector<double>(older.size(), 2.5)};
    const std::string path = (dir / "run.macro.csv").string();
    writeCsv(path, older, rows);
    MacroCsv m(path);
    m.reload();
    ASSERT_EQ(m.rows(), 2u);
    EXPECT_EQ(m.data()[1].size(), cols.size());
    EXPECT_EQ(m.data()[1][0], 2.5);
    EXPECT_EQ(m.data()[1][cols.size() - 2], 2.5);
    EXPECT_TRUE(std::isnan(m.data()[1].back()));
    EXPECT_FALSE(fs::exists(path + ".old"));
    // foreign: a column this version does not know
    std::vector<std::string> foreign = older;
    foreign[3] = "something_else";
    writeCsv(path, foreign, rows);
    MacroCsv f(path);
    f.reload();
    EXPECT_EQ(f.rows(), 0u);
    EXPECT_TRUE(fs::exists(path + ".old"));
    EXPECT_FALSE(fs::exists(path));
    fs::remove_all(dir);
}

// Many random contact directions give an isotropic fabric (F_dev -> 0 like 1/sqrt(N)); with unit
// forces the stress is proportional to the fabric.
TEST(MicroMacro, RandomDirectionsAreIsotropic) {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> g;
    std::vector<Vec3> dirs;
    for (int k = 0; k < 20000; ++k) dirs.push_back({g(rng), g(rng), g(rng)});
    Star s(dirs, std::vector<double>(dirs.size(), 1.0));
    MacroInput in;
    in.volume = 1.0;
    const MacroResult r = computeMacro(s.P, s.C, in);
    EXPECT_LT(r.FnDev, 0.02);
    // unit forces along the normals: stress is proportional to the fabric, p to its trace (1/3 of it)
    EXPECT_NEAR(r.sDev, 3 * r.FnDev, 1e-9);
    EXPECT_NEAR(r.fabricNormalised.trace(), 1.0, 1e-12);
}

TEST(MicroMacro, CsvColumnsAndRoundTrip) {
    const auto& cols = macroColumns();
    const std::vector<std::string> required = {
        "time", "tau", "volume_fraction", "eps_v", "eps_dev", "sigma_xx", "sigma_yy", "sigma_zz", "sigma_xy",
        "sigma_xz", "sigma_yz", "p", "p_nd", "sigma_dev", "s_dev", "F_xx", "F_yy", "F_zz", "F_v", "F_dev",
        "F_dev_star", "C_r", "C_m", "C_star", "phi_r", "Ek_over_Ep"};
    ASSERT_GE(cols.size(), required.size());
    for (std::size_t k = 0; k < required.size(); ++k) EXPECT_EQ(cols[k], required[k]);
    Star s(axes6(), std::vector<double>(6, 1.0));
    MacroInput in;
    in.volume = 1e-6;
    in.time = 0.5;
    const auto row = macroRow(computeMacro(s.P, s.C, in), in);
    EXPECT_EQ(row.size(), cols.size());
    const std::string path = "micromacro_test.macro.csv";
    std::filesystem::remove(path);
    MacroCsv csv(path);
    csv.append(row);
    auto row2 = row;
    row2[0] = 1.0;
    csv.append(row2);
    const CsvTable t = readCsv(path);
    ASSERT_EQ(t.rows.size(), 2u);
    EXPECT_EQ(t.rows[0], row);
    MacroCsv again(path);
    again.reload();
    EXPECT_EQ(again.rows(), 2u);
    again.truncateAfter(0.75);
    EXPECT_EQ(again.rows(), 1u);
    std::filesystem::remove(path);
}

// The fluctuation kinetic energy removes exactly the homogeneous flow of the moving axes (and a
// drift of the whole packing); what is left is the energy of the added random velocities.
TEST(MicroMacro, FluctuationKineticEnergyRemovesTheAffineFlow) {
    ParticleData P;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> pos(-1.0, 3.0), dv(-0.01, 0.01);
    const Vec3 centre{1, 1, 1}, rate{0.0, 0.0, -52.68};
    const Vec3 drift{0.3, -0.1, 0.2};
    std::vector<Vec3> noise;
    for (int i = 0; i < 200; ++i) {
        const Vec3 x{pos(rng), pos(rng), pos(rng)};
        Vec3 u{dv(rng), dv(rng), dv(rng)};
        noise.push_back(u);
        const Vec3 v = drift + Vec3{0, 0, rate.z * (x.z - centre.z)} + u;
        P.add(x, 0.01 + 0.001 * (i % 5), 2000, 0, v);
    }
    // expected: the noise about its own mass-weighted mean
    double M = 0;
    Vec3 mom{};
    for (std::size_t i = 0; i < P.size(); ++i) { M += P.m[i]; mom = mom + P.m[i] * noise[i]; }
    const Vec3 mean = (1.0 / M) * mom;
    double expected = 0;
    for (std::size_t i = 0; i < P.size(); ++i) expected += 0.5 * P.m[i] * norm2(noise[i] - mean);
    const double got = fluctuationKineticEnergy(P, rate, centre, {false, false, true});
    EXPECT_NEAR(got, expected, 1e-9 * expected);
    // without the flow axis the affine flow counts as kinetic energy (it is far larger)
    EXPECT_GT(fluctuationKineticEnergy(P, rate, centre, {false, false, false}), 100 * expected);
    // the ratio column is filled only when the energy is given
    MacroInput in;
    in.volume = 1.0;
    in.elasticEnergy = 2 * got;
    EXPECT_EQ(computeMacro(P, {}, in).ekFluctOverEp, 0.0);
    in.fluctuationKineticEnergy = got;
    EXPECT_NEAR(computeMacro(P, {}, in).ekFluctOverEp, 0.5, 1e-15);
}
