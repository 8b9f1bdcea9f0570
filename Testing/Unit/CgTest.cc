// Verification of the coarse-graining library (Tools/CoarseGraining): mass conservation, uniform
// translation, global stress (Eq. 2.5) in a periodic box, a static column under gravity,
// determinism across thread counts, readers/writers and bad input.
#include "CoarseGraining.h"
#include "Core/Error.h"
#include "SnapshotIO.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

using namespace pdpm;
using namespace pdpm::tools;

namespace {

ParticleSnapshot randomBox(int n, double L, bool periodic, unsigned seed, Vec3 u = {}, bool randomVel = true) {
    ParticleSnapshot s;
    s.boxLo = {0, 0, 0};
    s.boxHi = {L, L, L};
    for (bool& p : s.periodic) p = periodic;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(0, 1);
    for (int k = 0; k < n; ++k) {
        s.x.push_back({L * U(rng), L * U(rng), L * U(rng)});
        s.v.push_back(randomVel ? Vec3{U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5} : u);
        s.r.push_back(0.3 + 0.2 * U(rng));
        s.m.push_back(0.5 + U(rng));
    }
    s.time = 1.5;
    s.step = 100;
    return s;
}

Vec3 minimumImage(Vec3 d, double L) {
    for (int a = 0; a < 3; ++a) d[a] -= L * std::round(d[a] / L);
    return d;
}

/// Contacts between all pairs closer than `range` (minimum image) with random forces.
ContactSnapshot randomContacts(const ParticleSnapshot& s, double L, double range, unsigned seed) {
    ContactSnapshot c;
    c.boxLo = s.boxLo;
    c.boxHi = s.boxHi;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(-1, 1);
    for (std::size_t i = 0; i < s.size(); ++i)
        for (std::size_t j = i + 1; j < s.size(); ++j) {
            const Vec3 l = minimumImage(s.x[i] - s.x[j], L);
            const double d = norm(l);
            if (d > range) continue;
            ContactRecord r;
            r.i = int(i);
            r.j = int(j);
            r.branch = l;
            r.normal = l / d;
            r.fn = 1 + U(rng);
            Vec3 t = cross(r.normal, Vec3{U(rng), U(rng), U(rng)});
            r.ft = 0.3 * t;
            r.contactPoint = s.x[i] - 0.5 * l;
            r.overlap = 0.01;
            c.contacts.push_back(r);
        }
    return c;
}

double cellVolume(const CgResult& r) { return r.geom.spacing[0] * r.geom.spacing[1] * r.geom.spacing[2]; }

} // namespace

TEST(CgTest, MassConservationPeriodicGaussianAndLucy) {
    const double L = 10;
    const ParticleSnapshot s = randomBox(2000, L, true, 1);
    double M = 0;
    for (double m : s.m) M += m;
    for (CgKernel k : {CgKernel::Gaussian, CgKernel::Lucy}) {
        CgConfig cfg;
        cfg.kernel = k;
        cfg.width = 0.8;
        cfg.n[0] = cfg.n[1] = cfg.n[2] = 25;
        const CgResult r = coarseGrain(cfg, s);
        double integral = 0;
        for (double rho : r.rho) integral += rho * cellVolume(r);
        EXPECT_NEAR(integral / M, 1.0, 1e-6);
        EXPECT_NEAR(integral / M, 1.0, 1e-12);  // exact cell integration: round-off only
        std::cout << "mass conservation (" << (k == CgKernel::Gaussian ? "Gaussian" : "Lucy")
                  << "): relative error " << std::abs(integral / M - 1) << "\n";
    }
}

TEST(CgTest, MassConservationWithWallsAndWideKernel) {
    // non-periodic box, kernel wider than the box in one direction: renormalised clipping keeps all mass
    const ParticleSnapshot s = randomBox(300, 4, false, 2);
    double M = 0;
    for (double m : s.m) M += m;
    CgConfig cfg;
    cfg.width = 1.5;
    cfg.n[0] = 10; cfg.n[1] = 7; cfg.n[2] = 0;
    const CgResult r = coarseGrain(cfg, s);
    double integral = 0;
    for (double rho : r.rho) integral += rho * cellVolume(r);
    EXPECT_NEAR(integral / M, 1.0, 1e-12);
}

TEST(CgTest, UniformTranslationGivesExactVelocity) {
    const Vec3 u{0.3, -1.2, 2.5};
    const ParticleSnapshot s = randomBox(1500, 8, false, 3, u, false);
    CgConfig cfg;
    cfg.width = 0.5;
    cfg.n[0] = cfg.n[1] = cfg.n[2] = 20;
    const CgResult r = coarseGrain(cfg, s);
    double worst = 0, worstK = 0;
    int nonEmpty = 0;
    for (std::size_t c = 0; c < r.rho.size(); ++c) {
        if (!(r.rho[c] > 0)) continue;
        ++nonEmpty;
        worst = std::max(worst, norm(r.velocity[c] - u) / norm(u));
        for (double k : r.kineticStress[c]) worstK = std::max(worstK, std::abs(k) / (r.rho[c] * norm2(u)));
    }
    EXPECT_GT(nonEmpty, 7000);
    EXPECT_LT(worst, 1e-13);
    EXPECT_LT(worstK, 1e-12);  // no velocity fluctuation → no kinetic stress
    std::cout << "uniform translation: max |V-u|/|u| = " << worst << "\n";
}

TEST(CgTest, PeriodicVolumeAverageEqualsGlobalStress) {
    const double L = 8;
    const ParticleSnapshot s = randomBox(800, L, true, 4);
    const ContactSnapshot c = randomContacts(s, L, 1.2, 5);
    ASSERT_GT(c.contacts.size(), 500u);
    // global stress, Eq. 2.5 in the convention of the tools: σ = (1/V)(Σ m v v + Σ f ⊗ l), f on i, l = x_i − x_j
    Tensor9 global{};
    double kin[3][3] = {};
    const double V = L * L * L;
    for (const ContactRecord& r : c.contacts) {
        const Vec3 f = r.force();
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) global[3 * a + b] += f[a] * r.branch[b] / V;
    }
    for (std::size_t p = 0; p < s.size(); ++p)
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) kin[a][b] += s.m[p] * s.v[p][a] * s.v[p][b] / V;
    for (CgKernel k : {CgKernel::Gaussian, CgKernel::Lucy}) {
        CgConfig cfg;
        cfg.kernel = k;
        cfg.width = 0.7;
        cfg.n[0] = cfg.n[1] = cfg.n[2] = 16;
        const CgResult r = coarseGrain(cfg, s, &c);
        Tensor9 avg{};
        double mvv[3][3] = {};
        const double dV = cellVolume(r);
        for (std::size_t cell = 0; cell < r.rho.size(); ++cell) {
            for (int q = 0; q < 9; ++q) avg[q] += r.contactStress[cell][q] * dV / V;
            const int m[9] = {0, 1, 2, 1, 3, 4, 2, 4, 5};
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) {
                    const double pp = r.rho[cell] > 0 ? r.momentum[cell][a] * r.momentum[cell][b] / r.rho[cell] : 0;
                    mvv[a][b] += (r.kineticStress[cell][m[3 * a + b]] + pp) * dV / V;
                }
        }
        double scale = 0, err = 0;
        for (int q = 0; q < 9; ++q) scale = std::max(scale, std::abs(global[q]));
        for (int q = 0; q < 9; ++q) err = std::max(err, std::abs(avg[q] - global[q]) / scale);
        EXPECT_LT(err, 1e-6);
        EXPECT_LT(err, 1e-12);
        EXPECT_GT(global[0] + global[4] + global[8], 0);  // repulsive contacts → positive pressure
        double kerr = 0;
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) kerr = std::max(kerr, std::abs(mvv[a][b] - kin[a][b]) / std::abs(kin[0][0]));
        EXPECT_LT(kerr, 1e-12);
        std::cout << "periodic global stress: max relative deviation " << err << "\n";
    }
}

namespace {

struct Column {
    ParticleSnapshot s;
    ContactSnapshot c;
    double area = 0, g = 9.81, d = 1, m = 1;
    int layers = 20;
};

/// Simple-cubic stack of equal spheres in 3x3 vertical columns on a floor, side walls at the box faces.
Column staticColumn() {
    Column col;
    const int nxy = 3;
    const double d = col.d;
    ParticleSnapshot& s = col.s;
    s.boxLo = {0, 0, 0};
    s.boxHi = {nxy * d, nxy * d, 25 * d};
    col.area = nxy * d * nxy * d;
    col.c.boxLo = s.boxLo;
    col.c.boxHi = s.boxHi;
    for (int a = 0; a < nxy; ++a)
        for (int b = 0; b < nxy; ++b)
            for (int k = 0; k < col.layers; ++k) {
                const int id = int(s.size());
                s.x.push_back({(a + 0.5) * d, (b + 0.5) * d, (k + 0.5) * d});
                s.v.push_back({});
                s.r.push_back(0.5 * d);
                s.m.push_back(col.m);
                ContactRecord r;
                r.i = id;
                if (k == 0) {  // floor: wall 0, normal from the wall into the particle
                    r.j = -1;
                    r.normal = {0, 0, 1};
                    r.fn = col.layers * col.m * col.g;
                    r.contactPoint = {s.x.back().x, s.x.back().y, 0};
                    r.branch = s.x.back() - r.contactPoint;
                } else {  // i = this particle, j = the one below: force on i from below is upward
                    r.j = id - 1;
                    r.normal = {0, 0, 1};
                    r.fn = (col.layers - k) * col.m * col.g;
                    r.branch = {0, 0, d};
                    r.contactPoint = s.x.back() - Vec3{0, 0, 0.5 * d};
                }
                col.c.contacts.push_back(r);
            }
    return col;
}

} // namespace

TEST(CgTest, StaticColumnStressEqualsWeightAbove) {
    const Column col = staticColumn();
    for (double w : {0.5, 1.0}) {
        for (CgKernel k : {CgKernel::Gaussian, CgKernel::Lucy}) {
            CgConfig cfg;
            cfg.kernel = k;
            cfg.width = w;
            cfg.n[2] = 125;
            const CgResult r = coarseGrain(cfg, col.s, &col.c);
            const CoarseGrainer probe(cfg);
            const double cut = probe.cutoff();
            double worst = 0;
            int checked = 0;
            for (int kz = 0; kz < r.geom.n[2]; ++kz) {
                const double z = r.geom.centres[2][kz];
                if (z < cut + col.d || z > col.layers * col.d - cut - col.d) continue;
                double above = 0;
                for (std::size_t p = 0; p < col.s.size(); ++p)
                    above += col.s.m[p] * std::clamp((col.s.x[p].z + 0.5 * col.d - z) / col.d, 0.0, 1.0);
                const double ref = above * col.g / col.area;
                const double szz = r.contactStress[kz][8];
                worst = std::max(worst, std::abs(szz - ref) / ref);
                ++checked;
            }
            EXPECT_GT(checked, 40);
            EXPECT_LT(worst, 0.05) << "w = " << w;
            std::cout << "static column (" << (k == CgKernel::Gaussian ? "Gaussian" : "Lucy") << ", w = " << w
                      << " d): max relative deviation of sigma_zz from the weight above " << worst << "\n";
        }
    }
}

TEST(CgTest, StaticColumnMomentumBalanceWithCutKernel) {
    // d σ_zz/dz = −ρ g in the bulk (central differences on the 1D grid)
    const Column col = staticColumn();
    CgConfig cfg;
    cfg.width = 0.7;
    cfg.walls = WallTreatment::Cut;
    cfg.n[2] = 250;
    const CgResult r = coarseGrain(cfg, col.s, &col.c);
    const double h = r.geom.spacing[2];
    double worst = 0;
    for (int kz = 30; kz < 170; ++kz) {  // z in [3, 17]: one cut-off away from floor and surface
        const double dsdz = (r.contactStress[kz + 1][8] - r.contactStress[kz - 1][8]) / (2 * h);
        worst = std::max(worst, std::abs(dsdz + r.rho[kz] * col.g) / (r.rho[kz] * col.g));
    }
    EXPECT_LT(worst, 0.03);  // limited by the Gauss quadrature of the cut-off (discontinuous) kernel
    std::cout << "static column momentum balance: max |dsigma_zz/dz + rho g|/(rho g) = " << worst << "\n";
}

TEST(CgTest, IdenticalResultsForOneAndTwoThreads) {
    const double L = 8;
    const ParticleSnapshot s = randomBox(1000, L, true, 6);
    const ContactSnapshot c = randomContacts(s, L, 1.2, 7);
    CgConfig cfg;
    cfg.width = 0.6;
    cfg.n[0] = 12; cfg.n[1] = 9; cfg.n[2] = 14;
    const int before = omp_get_max_threads();
    omp_set_num_threads(1);
    const CgResult a = coarseGrain(cfg, s, &c);
    omp_set_num_threads(2);
    const CgResult b = coarseGrain(cfg, s, &c);
    omp_set_num_threads(before);
    for (std::size_t k = 0; k < a.rho.size(); ++k) {
        ASSERT_EQ(a.rho[k], b.rho[k]);
        ASSERT_EQ(a.contactStress[k], b.contactStress[k]);
        ASSERT_EQ(a.fabric[k], b.fabric[k]);
    }
}

TEST(CgTest, CylindricalGridConservesMassAndRotatesVelocity) {
    // particles in a cylinder of radius 4 around the z axis, rigid rotation about z
    ParticleSnapshot s;
    s.boxLo = {-5, -5, 0};
    s.boxHi = {5, 5, 6};
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<double> U(0, 1);
    double M = 0;
    const double Omega = 2;
    while (s.size() < 3000) {
        const Vec3 x{-4 + 8 * U(rng), -4 + 8 * U(rng), 6 * U(rng)};
        if (x.x * x.x + x.y * x.y > 16) continue;
        s.x.push_back(x);
        s.v.push_back({-Omega * x.y, Omega * x.x, 0.0});
        s.r.push_back(0.2);
        s.m.push_back(1);
        M += 1;
    }
    CgConfig cfg;
    cfg.cylindrical = true;
    cfg.width = 0.4;
    cfg.rmax = 4;
    cfg.n[0] = 16;
    cfg.n[2] = 12;
    const CgResult r = coarseGrain(cfg, s);
    double integral = 0;
    for (int k = 0; k < r.geom.n[2]; ++k)
        for (int i = 0; i < r.geom.n[0]; ++i) {
            const double ra = i * r.geom.spacing[0], rb = ra + r.geom.spacing[0];
            const std::size_t c = r.geom.index(i, 0, k);
            integral += r.rho[c] * std::numbers::pi * (rb * rb - ra * ra) * r.geom.spacing[2];
            if (r.rho[c] > 0) {
                EXPECT_NEAR(r.velocity[c].x, 0, 1e-9);  // radial
                EXPECT_NEAR(r.velocity[c].z, 0, 1e-12);  // axial
                EXPECT_GT(r.velocity[c].y, 0);  // azimuthal
            }
        }
    EXPECT_NEAR(integral / M, 1, 1e-12);
}

TEST(CgTest, HeightProfileIsDensityRatio) {
    const Column col = staticColumn();
    CgConfig cfg;
    cfg.width = 0.5;
    cfg.n[2] = 25;
    const CgResult a = coarseGrain(cfg, col.s);
    ParticleSnapshot half = col.s;  // remove the upper half of every column
    ParticleSnapshot t = col.s;
    t.x.clear(); t.v.clear(); t.r.clear(); t.m.clear();
    for (std::size_t p = 0; p < half.size(); ++p)
        if (half.x[p].z < 10) {
            t.x.push_back(half.x[p]);
            t.v.push_back({});
            t.r.push_back(0.5);
            t.m.push_back(1);
        }
    const CgResult b = coarseGrain(cfg, t);
    const auto h = heightProfile(b, a, 0.2);
    EXPECT_NEAR(h[2], 0.2, 1e-12);  // z = 2.5: unchanged
    EXPECT_NEAR(h[15], 0.0, 1e-12);  // z = 15.5: emptied
    const auto mpl = massPerLength(a);
    EXPECT_NEAR(mpl[10], 9.0, 1e-9);  // 9 columns of unit mass per unit length in the bulk
}

// ---- files ----------------------------------------------------------------------------------------

namespace {
std::string tmpDir() {
    auto d = std::filesystem::temp_directory_path() / ("pdpm_cg_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d.string();
}
} // namespace

TEST(CgIoTest, VtuAndFstatRoundTrip) {
    if (!haveVtk()) GTEST_SKIP() << "built without VTK";
    const std::string dir = tmpDir();
    ParticleSnapshot s = randomBox(50, 5, true, 9);
    s.periodic[2] = false;
    s.coordination.assign(50, 3);
    const ContactSnapshot c = [&] {
        ContactSnapshot c = randomContacts(s, 5, 1.5, 10);
        c.time = s.time;
        c.step = s.step;
        return c;
    }();
    writeVtu(dir + "/run_0000.vtu", s);
    writeFstat(dir + "/run.fstat", {c});
    {
        std::ofstream pvd(dir + "/run.pvd");
        pvd << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n"
               "<DataSet timestep=\"1.5\" part=\"0\" file=\"run_0000.vtu\"/>\n</Collection>\n</VTKFile>\n";
    }
    const auto frames = loadFrames({dir + "/run.pvd", dir + "/run.fstat"});
    ASSERT_EQ(frames.size(), 1u);
    ASSERT_TRUE(frames[0].hasParticles);
    ASSERT_TRUE(frames[0].hasContacts);
    const ParticleSnapshot& r = frames[0].particles;
    EXPECT_EQ(r.time, s.time);
    EXPECT_EQ(r.step, s.step);
    EXPECT_TRUE(r.periodic[0] && !r.periodic[2]);
    ASSERT_EQ(r.size(), s.size());
    for (std::size_t p = 0; p < s.size(); ++p) {
        EXPECT_EQ(r.x[p], s.x[p]);
        EXPECT_EQ(r.v[p], s.v[p]);
        EXPECT_EQ(r.m[p], s.m[p]);
        EXPECT_EQ(r.coordination[p], 3);
    }
    const auto& rc = frames[0].contacts.contacts;
    ASSERT_EQ(rc.size(), c.contacts.size());
    for (std::size_t k = 0; k < rc.size(); ++k) {
        EXPECT_EQ(rc[k].i, c.contacts[k].i);
        EXPECT_EQ(rc[k].branch, c.contacts[k].branch);
        EXPECT_EQ(rc[k].fn, c.contacts[k].fn);
    }
    std::filesystem::remove_all(dir);
}

TEST(CgIoTest, MalformedVtuThrowsInputError) {
    if (!haveVtk()) GTEST_SKIP() << "built without VTK";
    const std::string dir = tmpDir();
    {
        std::ofstream f(dir + "/bad.vtu");
        f << "this is not xml\n";
    }
    EXPECT_THROW(readVtu(dir + "/bad.vtu"), InputError);
    std::filesystem::remove_all(dir);
}

TEST(CgIoTest, BadInputThrowsInputError) {
    const std::string dir = tmpDir();
    EXPECT_THROW(readFstat(dir + "/missing.fstat"), InputError);
    EXPECT_THROW(loadFrames({dir + "/missing.vtu"}), InputError);
    {
        std::ofstream f(dir + "/bad.fstat");
        f << "# time 0 step 0 contacts 2\n# box 0 1 0 1 0 1 periodic 0 0 0\n0 1 0 0 0 0.1 0 0 1 1 0 0 0 0 0 1\n";
    }
    EXPECT_THROW(readFstat(dir + "/bad.fstat"), InputError);  // 16 values and too few rows
    CgConfig cfg;
    cfg.n[0] = 10;
    cfg.width = 0;
    EXPECT_THROW(CoarseGrainer{cfg}, InputError);
    cfg.width = -1;
    EXPECT_THROW(CoarseGrainer{cfg}, InputError);
    cfg.width = 1;
    cfg.n[0] = 0;
    EXPECT_THROW(CoarseGrainer{cfg}, InputError);  // empty grid
    std::filesystem::remove_all(dir);
}

TEST(CgTest, ContactFieldsAverageOverTheSnapshotsWithContacts) {
    // a window of two snapshots of the same state, one with its contact block and one without: the
    // contact stress and fabric are those of the one with contacts, not half of them
    const double L = 5;
    const ParticleSnapshot s = randomBox(60, L, true, 21);
    const ContactSnapshot c = randomContacts(s, L, 1.5, 22);
    CgConfig cfg;
    cfg.width = 0.8;
    cfg.n[0] = 4;
    cfg.n[1] = 4;
    cfg.n[2] = 4;
    const CgResult one = coarseGrain(cfg, s, &c);
    CoarseGrainer cg(cfg);
    cg.add(s, &c);
    cg.add(s, nullptr);
    const CgResult two = cg.result();
    EXPECT_EQ(two.snapshots, 2);
    EXPECT_EQ(two.contactSnapshots, 1);
    for (std::size_t k = 0; k < one.rho.size(); ++k) {
        EXPECT_NEAR(two.rho[k], one.rho[k], 1e-12 * one.rho[k]);  // sums over two snapshots: round-off
        for (int q = 0; q < 9; ++q) EXPECT_EQ(two.contactStress[k][q], one.contactStress[k][q]);
        for (int q = 0; q < 6; ++q) EXPECT_EQ(two.fabric[k][q], one.fabric[k][q]);
    }
}

TEST(CgTest, CylinderCentreIsGivenInAxisOrder) {
    // axis y: --centre a,b is (x, z). One particle on that axis lies in the innermost radial cell.
    ParticleSnapshot s;
    s.boxLo = {0, 0, 0};
    s.boxHi = {10, 10, 10};
    s.x = {{2, 5, 7}};
    s.v = {{0, 0, 0}};
    s.r = {0.1};
    s.m = {1};
    CgConfig cfg;
    cfg.cylindrical = true;
    cfg.axis = 1;
    cfg.width = 0.1;
    cfg.rmax = 2;
    cfg.n[0] = 20;
    cfg.n[2] = 1;
    cfg.centre[0] = 2;  // x
    cfg.centre[1] = 7;  // z
    cfg.centreSet = true;
    const CgResult r = coarseGrain(cfg, s);
    std::size_t best = 0;
    for (std::size_t i = 0; i < std::size_t(r.geom.n[0]); ++i)
        if (r.rho[r.geom.index(int(i), 0, 0)] > r.rho[r.geom.index(int(best), 0, 0)]) best = i;
    EXPECT_EQ(best, 0u) << "the particle on the axis must be at r = 0";
}

TEST(CgTest, KernelThousandsOfPeriodsWideIsRefused) {
    const ParticleSnapshot s = randomBox(10, 1, true, 3);
    CgConfig cfg;
    cfg.n[2] = 4;
    cfg.width = 1e4;  // 3.24e4 periods of the 1 m box
    EXPECT_THROW(coarseGrain(cfg, s), InputError);
    cfg.width = 10;  // 32 periods: summed
    EXPECT_NO_THROW(coarseGrain(cfg, s));
    // without periods a kernel of any width is fine: its stencil (2c/h cells) once overflowed an int
    const ParticleSnapshot w = randomBox(10, 1, false, 3);
    double m0 = 0;
    for (double m : w.m) m0 += m;
    for (double width : {1e7, 1e9, 1e12}) {  // the stencil size, then the cell indices, overflowed an int
        cfg.width = width;
        CgResult r;
        ASSERT_NO_THROW(r = coarseGrain(cfg, w));
        double mass = 0;
        for (double x : r.rho) mass += x * cellVolume(r);
        EXPECT_NEAR(mass / m0, 1, 1e-9) << "width " << width;
    }
}

TEST(CgIoTest, DuplicatesAndNonPositiveRadiiAreRefused) {
    if (!haveVtk()) GTEST_SKIP() << "built without VTK";
    const std::string dir = tmpDir() + "_dup";
    std::filesystem::create_directories(dir);
    ParticleSnapshot s = randomBox(20, 5, true, 4);
    writeVtu(dir + "/run_0000.vtu", s);
    {
        std::ofstream pvd(dir + "/run.pvd");
        pvd << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n"
               "<DataSet timestep=\"1.5\" part=\"0\" file=\"run_0000.vtu\"/>\n</Collection>\n</VTKFile>\n";
    }
    EXPECT_NO_THROW(loadFrames({dir + "/run.pvd"}));
    EXPECT_THROW(loadFrames({dir + "/run.pvd", dir + "/run_0000.vtu"}), InputError);  // the same snapshot twice
    // another file at the same time and step (a replica, or a start file and its preparation) is not a duplicate
    writeVtu(dir + "/replica_0000.vtu", randomBox(20, 5, true, 44));
    EXPECT_NO_THROW(loadFrames({dir + "/run_0000.vtu", dir + "/replica_0000.vtu"}));
    ContactSnapshot c = randomContacts(s, 5, 1.5, 5);
    c.time = s.time;
    c.step = s.step;
    writeFstat(dir + "/run.fstat", {c});
    EXPECT_THROW(loadFrames({dir + "/run.pvd", dir + "/run.fstat", dir + "/run.fstat"}), InputError);
    s.r[7] = -0.3;
    writeVtu(dir + "/neg.vtu", s);
    try {
        readVtu(dir + "/neg.vtu");
        ADD_FAILURE() << "a negative radius accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("point 7"), std::string::npos) << e.what();
    }
    std::filesystem::remove_all(dir);
}
