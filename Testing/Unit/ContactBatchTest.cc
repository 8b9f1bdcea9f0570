// The batched (SIMD) linear law of Contacts/LinearBatch.h against the scalar parts it replaces in
// the pair loop (NormalLinear + TangentialCoulomb, NormalLinear alone): random contacts covering
// sticking, sliding (static and dynamic limit), springs that must be rotated, zero springs, zero
// tangential stiffness and separating (attractive dashpot) contacts. The two may differ in the last
// bits (fused multiply-adds), so the comparison is relative: forces and torques 1e-12 of the force
// scale, springs and energies 1e-10. The whole batched pair loop (screening, gather with per-pair
// parameters of several species, padding, ordered scatter, history reset of separated pairs,
// contact records) is compared with the scalar per-pair loop as well.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "Contacts/ComposedLaw.h"
#include "Contacts/LinearBatch.h"
#include "Contacts/NormalLaws.h"
#include "Contacts/SpeciesTable.h"
#include "Contacts/TangentialLaws.h"
#include "Boundaries/PeriodicBox.h"

using namespace pdpm;

namespace {

struct Case {
    Vec3 d;           // x_i - x_j
    double ri, rj;
    Vec3 vrel, wi, wj;
    double h[4];
    ContactParameters p;
};

Case randomCase(std::mt19937_64& rng, int k) {
    std::uniform_real_distribution<double> u(-1.0, 1.0), pos(0.0, 1.0);
    Case c;
    c.ri = 1e-3 * (0.5 + pos(rng));
    c.rj = 1e-3 * (0.5 + pos(rng));
    Vec3 dir{u(rng), u(rng), u(rng)};
    dir *= 1.0 / norm(dir);
    const double overlap = (c.ri + c.rj) * 0.05 * pos(rng);
    c.d = (c.ri + c.rj - overlap) * dir;
    c.vrel = {u(rng), u(rng), u(rng)};
    c.wi = {100 * u(rng), 100 * u(rng), 100 * u(rng)};
    c.wj = {100 * u(rng), 100 * u(rng), 100 * u(rng)};
    c.p.k = 1e5 * (0.5 + pos(rng));
    c.p.gamma = 0.3 * pos(rng);
    c.p.kt = (k % 7 == 0) ? 0.0 : 2.0 / 7.0 * c.p.k;
    c.p.gammaT = (k % 3 == 0) ? 0.0 : 0.1 * pos(rng);
    c.p.muS = (k % 5 == 0) ? 0.0 : 0.6 * pos(rng);
    c.p.muD = c.p.muS * (0.5 + 0.5 * pos(rng));
    // a spring from an earlier step: zero, small (sticking) or large (will slide), tilted out of plane
    const double scale = (k % 4 == 0) ? 0.0 : (k % 4 == 1 ? 1e-7 : 1e-4);
    c.h[0] = scale * u(rng);
    c.h[1] = scale * u(rng);
    c.h[2] = scale * u(rng);
    c.h[3] = (k % 2 == 0) ? 1.0 : 0.0;
    return c;
}

double relDiff(double a, double b, double scale) { return std::fabs(a - b) / scale; }

template <bool kFriction>
void compare(int count, unsigned seed) {
    using Law = std::conditional_t<kFriction, ComposedLaw<NormalLinear, TangentialCoulomb, NoPart, NoPart>,
                                   ComposedLaw<NormalLinear, NoPart, NoPart, NoPart>>;
    std::mt19937_64 rng(seed);
    std::vector<Case> cases;
    for (int k = 0; k < count; ++k) cases.push_back(randomCase(rng, k));
    LinearBatch b;
    const double dt = 1e-7;
    int slid = 0, stuck = 0;
    for (std::size_t c0 = 0; c0 < cases.size(); c0 += LinearBatch::kChunk) {
        const std::size_t n = std::min(LinearBatch::kChunk, cases.size() - c0);
        for (std::size_t q = 0; q < n; ++q) {
            const Case& c = cases[c0 + q];
            b.dx[q] = c.d.x; b.dy[q] = c.d.y; b.dz[q] = c.d.z; b.d2[q] = norm2(c.d);
            b.ri[q] = c.ri; b.rj[q] = c.rj;
            b.vx[q] = c.vrel.x; b.vy[q] = c.vrel.y; b.vz[q] = c.vrel.z;
            b.wix[q] = c.wi.x; b.wiy[q] = c.wi.y; b.wiz[q] = c.wi.z;
            b.wjx[q] = c.wj.x; b.wjy[q] = c.wj.y; b.wjz[q] = c.wj.z;
            b.h0[q] = c.h[0]; b.h1[q] = c.h[1]; b.h2[q] = c.h[2]; b.h3[q] = c.h[3];
            b.setParameters<true>(q, c.p);
        }
        const std::size_t m = b.pad(n, kFriction, true);
        ASSERT_EQ(m % LinearBatch::kPad, 0u);
        b.template evaluate<kFriction>(m, dt);
        for (std::size_t q = 0; q < n; ++q) {
            const Case& c = cases[c0 + q];
            // the scalar law, with the state the pair loop computes for it
            const double dist = norm(c.d);
            ContactState st;
            st.n = (1.0 / dist) * c.d;
            st.overlap = c.ri + c.rj - dist;
            st.overlapRate = -dot(c.vrel, st.n);
            st.dt = dt;
            const double ai = c.ri - 0.5 * st.overlap, aj = c.rj - 0.5 * st.overlap;
            const Vec3 vc = c.vrel - cross(ai * c.wi + aj * c.wj, st.n);
            st.vt = vc - dot(vc, st.n) * st.n;
            double h[4] = {c.h[0], c.h[1], c.h[2], c.h[3]};
            ContactOutput o;
            Law::eval(c.p, st, h, o);
            const Vec3 F = o.fn * st.n + o.ft;
            const double fs = std::max(1e-300, std::fabs(o.fn) + norm(o.ft));
            SCOPED_TRACE("contact " + std::to_string(c0 + q));
            EXPECT_LT(relDiff(b.fn[q], o.fn, fs), 1e-12);
            EXPECT_LT(relDiff(b.Fx[q], F.x, fs), 1e-12);
            EXPECT_LT(relDiff(b.Fy[q], F.y, fs), 1e-12);
            EXPECT_LT(relDiff(b.Fz[q], F.z, fs), 1e-12);
            EXPECT_LT(relDiff(b.overlap[q], st.overlap, st.overlap), 1e-12);
            EXPECT_LT(relDiff(b.nx[q], st.n.x, 1.0), 1e-14);
            EXPECT_LT(relDiff(b.ny[q], st.n.y, 1.0), 1e-14);
            EXPECT_LT(relDiff(b.nz[q], st.n.z, 1.0), 1e-14);
            EXPECT_LT(relDiff(b.energy[q], o.energy, std::max(1e-300, o.energy)), 1e-10);
            if constexpr (kFriction) {
                const Vec3 nxft = cross(st.n, o.ft);
                const double ts = std::max(1e-300, ai * norm(o.ft));
                EXPECT_LT(relDiff(b.tix[q], -(ai * nxft).x, ts), 1e-12);
                EXPECT_LT(relDiff(b.tiy[q], -(ai * nxft).y, ts), 1e-12);
                EXPECT_LT(relDiff(b.tiz[q], -(ai * nxft).z, ts), 1e-12);
                EXPECT_LT(relDiff(b.tjx[q], -(aj * nxft).x, ts), 1e-12);
                EXPECT_LT(relDiff(b.tjy[q], -(aj * nxft).y, ts), 1e-12);
                EXPECT_LT(relDiff(b.tjz[q], -(aj * nxft).z, ts), 1e-12);
                const double hs = std::max({1e-300, std::fabs(h[0]) + std::fabs(h[1]) + std::fabs(h[2])});
                EXPECT_LT(relDiff(b.h0[q], h[0], hs), 1e-10);
                EXPECT_LT(relDiff(b.h1[q], h[1], hs), 1e-10);
                EXPECT_LT(relDiff(b.h2[q], h[2], hs), 1e-10);
                EXPECT_EQ(b.h3[q], h[3]);
                EXPECT_EQ(b.sliding[q] != 0, o.sliding);
                (o.sliding ? slid : stuck)++;
            }
        }
    }
    if constexpr (kFriction) {
        // both regimes were exercised
        EXPECT_GT(slid, count / 10);
        EXPECT_GT(stuck, count / 10);
    }
}

} // namespace

TEST(ContactBatch, LinearCoulombMatchesScalarLaw) { compare<true>(2000, 7); }

TEST(ContactBatch, LinearFrictionlessMatchesScalarLaw) { compare<false>(500, 11); }

TEST(ContactBatch, PaddingIsHarmless) {
    LinearBatch b;
    // one real contact, the rest of the batch padding: results of padding lanes are finite
    b.dx[0] = 1.9e-3; b.dy[0] = 0; b.dz[0] = 0; b.d2[0] = 1.9e-3 * 1.9e-3;
    b.ri[0] = b.rj[0] = 1e-3;
    b.vx[0] = b.vy[0] = b.vz[0] = 0;
    b.k[0] = 1e5; b.gamma[0] = 0;
    const std::size_t m = b.pad(1, false, true);
    EXPECT_EQ(m, LinearBatch::kPad);
    b.evaluate<false>(m, 1e-7);
    EXPECT_NEAR(b.fn[0], 1e5 * 0.1e-3, 1e-9);
    for (std::size_t q = 0; q < m; ++q) EXPECT_TRUE(std::isfinite(b.Fx[q]));
}

namespace {

/// The batched pairRange against the scalar contact() of the same law, pair by pair, on random
/// pairs of random particles (60 % placed touching, about 20 % still touching at the end), split into two slab calls so that chunks start
/// away from 0 and end part-filled. Histories of separated pairs are dirty on purpose.
template <class Law, bool kPeriodic>
void comparePairLoops(int nSpecies, unsigned seed, bool record, bool zeroFriction) {
    static_assert(Law::kBatch);
    constexpr int H = Law::H;
    std::mt19937_64 g(seed);
    std::uniform_real_distribution<double> u(-1, 1), pu(0, 1);
    const int n = 120;
    const std::size_t nPairs = 437;
    const double L = 3e-3;
    std::vector<Vec3> x(n), v(n), w(n);
    std::vector<double> r(n), invM(n, 1.0), m(n, 1.0);
    std::vector<int32_t> sp(n);
    for (int i = 0; i < n; ++i) {
        x[i] = {L * pu(g), L * pu(g), L * pu(g)};
        v[i] = {u(g), u(g), u(g)};
        w[i] = {100 * u(g), 100 * u(g), 100 * u(g)};
        r[i] = 1e-3 * (0.5 + pu(g));
        sp[i] = static_cast<int32_t>(pu(g) * nSpecies) % nSpecies;
    }
    SpeciesTable spt;
    auto params = [&](bool zero) {
        ContactParameters p;
        p.k = 1e5 * (0.5 + pu(g));
        p.gamma = 0.3 * pu(g);
        p.kt = zero ? 0.0 : 0.3 * p.k;
        p.gammaT = 0.1 * pu(g);
        p.muS = zero ? 0.0 : 0.6 * pu(g);
        p.muD = p.muS * (0.5 + 0.5 * pu(g));
        return p;
    };
    ASSERT_LE(nSpecies, 3);
    const char* const names[] = {"s0", "s1", "s2"};
    for (int s = 0; s < nSpecies; ++s) spt.add(names[s], 1000, params(zeroFriction && s == 0));
    for (int a = 0; a < nSpecies; ++a)
        for (int b = a + 1; b < nSpecies; ++b) spt.setPair(a, b, params(false));
    std::vector<uint32_t> pi(nPairs), pj(nPairs);
    for (std::size_t k = 0; k < nPairs; ++k) {
        const int i = static_cast<int>(pu(g) * n) % n;
        int j;
        do j = static_cast<int>(pu(g) * n) % n; while (j == i);
        pi[k] = static_cast<uint32_t>(i);
        pj[k] = static_cast<uint32_t>(j);
        if (pu(g) < 0.6) {  // place j touching i
            Vec3 d{u(g), u(g), u(g)};
            d *= 1.0 / norm(d);
            x[j] = x[i] - (r[i] + r[j]) * (1 - 0.03 * pu(g)) * d;
        }
    }
    std::vector<double> hist(nPairs * H + 1);
    for (auto& h : hist) h = pu(g) < 0.5 ? 0.0 : 1e-5 * u(g);
    if constexpr (H > 0)
        for (std::size_t k = 0; k < nPairs; ++k) hist[k * H + 3] = pu(g) < 0.5 ? 1.0 : 0.0;
    PeriodicBox box;
    if (kPeriodic) {
        box.set({0, 0, 0}, {L, L, L}, true, true, true);
        // two walls that move without remapping: image partners carry k L' (both loops must add it)
        box.setFlowRate(0, 0.7);
        box.setFlowRate(2, -1.3);
    }
    box.setAffineRate(1, 40.0);  // remapped axes: the affine flow enters both loops
    box.setAffineRate(2, -25.0);
    const MinimumImage img(box);
    const double dt = 1e-7;
    std::vector<Vec3> fA(n), tA(n), fB(n), tB(n);
    std::vector<double> hA = hist, hB = hist;
    std::vector<ContactRecord> rA, rB;
    double eA = 0, eB = 0;
    for (auto [k0, k1] : {std::pair<std::size_t, std::size_t>{0, 100}, {100, nPairs}})
        Law::template pairRange<kPeriodic>(k0, k1, pi.data(), pj.data(), x.data(), v.data(), w.data(), r.data(),
                                           invM.data(), m.data(), sp.data(), fA.data(), tA.data(), hA.data(), img,
                                           spt, dt, 0.0, record ? &rA : nullptr, eA);
    std::size_t touching = 0;
    for (std::size_t k = 0; k < nPairs; ++k) {
        double dx, dy, dz, d2;
        if (Law::template separation<kPeriodic>(pi[k], pj[k], x.data(), r.data(), img, dx, dy, dz, d2)) {
            ++touching;
            Law::template contact<kPeriodic>(k, pi[k], pj[k], dx, dy, dz, d2, x.data(), v.data(), w.data(), r.data(),
                                             invM.data(), m.data(), sp.data(), fB.data(), tB.data(), hB.data(), img,
                                             spt, dt, 0.0, record ? &rB : nullptr, eB);
        } else if constexpr (H > 0) {
            for (int q = 0; q < H; ++q) hB[k * H + q] = 0.0;
        }
    }
    ASSERT_GT(touching, nPairs / 10);  // about 95 of 437 (later placements break earlier contacts)
    ASSERT_LT(touching, nPairs);
    double fs = 0, ts = 1e-300;
    for (int i = 0; i < n; ++i) {
        fs = std::max(fs, norm(fB[i]));
        ts = std::max(ts, norm(tB[i]));
    }
    for (int i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            EXPECT_LT(relDiff(fA[i][a], fB[i][a], fs), 1e-12) << "force on " << i;
            EXPECT_LT(relDiff(tA[i][a], tB[i][a], ts), 1e-12) << "torque on " << i;
        }
    for (std::size_t q = 0; q < nPairs * H; ++q) {
        if (q % H == 3) EXPECT_EQ(hA[q], hB[q]) << "sliding flag of pair " << q / H;
        else EXPECT_LT(relDiff(hA[q], hB[q], 1e-5), 1e-10) << "spring of pair " << q / H;
    }
    if (!record) return;
    ASSERT_EQ(rA.size(), rB.size());
    for (std::size_t q = 0; q < rA.size(); ++q) {
        const ContactRecord &a = rA[q], &b = rB[q];
        EXPECT_EQ(a.i, b.i);
        EXPECT_EQ(a.j, b.j);
        EXPECT_EQ(a.sliding, b.sliding);
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(a.branch[c], b.branch[c]);
            EXPECT_LT(relDiff(a.point[c], b.point[c], 1e-3), 1e-12);
            EXPECT_LT(relDiff(a.n[c], b.n[c], 1.0), 1e-12);
            EXPECT_LT(relDiff(a.ft[c], b.ft[c], fs), 1e-12);
        }
        EXPECT_LT(relDiff(a.fn, b.fn, fs), 1e-12);
        EXPECT_LT(relDiff(a.overlap, b.overlap, 1e-3), 1e-12);
        EXPECT_LT(relDiff(a.energy, b.energy, std::max(1e-300, std::fabs(b.energy))), 1e-10);
    }
    EXPECT_LT(relDiff(eA, eB, eB), 1e-10);
}

using LinearCoulomb = ComposedLaw<NormalLinear, TangentialCoulomb, NoPart, NoPart>;
using LinearOnly = ComposedLaw<NormalLinear, NoPart, NoPart, NoPart>;

} // namespace

TEST(ContactBatch, PairLoopMatchesScalarLoopOneSpecies) {
    for (unsigned seed = 1; seed <= 3; ++seed) {
        comparePairLoops<LinearCoulomb, false>(1, seed, true, false);
        comparePairLoops<LinearCoulomb, true>(1, seed, false, false);
        comparePairLoops<LinearOnly, true>(1, seed, true, false);
    }
}

TEST(ContactBatch, PairLoopMatchesScalarLoopSeveralSpecies) {
    for (unsigned seed = 1; seed <= 3; ++seed) {
        comparePairLoops<LinearCoulomb, true>(3, seed, true, true);  // species 0: k_t = 0, mu = 0
        comparePairLoops<LinearCoulomb, false>(2, seed, false, false);
        comparePairLoops<LinearOnly, false>(3, seed, true, false);
    }
}

TEST(ContactBatch, FrictionPaddingKeepsSingleSpeciesParameters) {
    // one species with k_t = 0 and mu = 0 in every lane, one real contact, padding without
    // parameters: the padding lanes stay finite and lane 0 keeps its parameters
    LinearBatch b;
    for (std::size_t q = 0; q < LinearBatch::kMax; ++q) {
        b.k[q] = 1e5; b.gamma[q] = 0.1; b.kt[q] = 0; b.gammaT[q] = 0; b.muS[q] = 0; b.muD[q] = 0;
    }
    b.dx[0] = 1.9e-3; b.dy[0] = 0; b.dz[0] = 0; b.d2[0] = 1.9e-3 * 1.9e-3;
    b.ri[0] = b.rj[0] = 1e-3;
    b.vx[0] = 0; b.vy[0] = 0.5; b.vz[0] = 0;
    b.wix[0] = b.wiy[0] = b.wiz[0] = b.wjx[0] = b.wjy[0] = b.wjz[0] = 0;
    b.h0[0] = b.h1[0] = b.h2[0] = b.h3[0] = 0;
    const std::size_t m = b.pad(1, true, false);
    EXPECT_EQ(b.kt[m - 1], 0.0);
    EXPECT_EQ(b.k[m - 1], 1e5);
    b.evaluate<true>(m, 1e-7);
    EXPECT_NEAR(b.fn[0], 1e5 * 0.1e-3, 1e-9);
    EXPECT_EQ(b.ftx[0], 0.0);
    EXPECT_EQ(b.fty[0], 0.0);  // mu = 0: no tangential force
    for (std::size_t q = 0; q < m; ++q) {
        EXPECT_TRUE(std::isfinite(b.Fx[q]) && std::isfinite(b.Fy[q]) && std::isfinite(b.tiz[q]));
        EXPECT_TRUE(std::isfinite(b.h0[q]) && std::isfinite(b.h1[q]));
    }
}

namespace {
struct FlowCase {
    bool across = false;    ///< a just below the top, b just above the bottom: a touches b's image
    bool tell = true;       ///< the box knows how it moves (false: the contact loop is not told)
    bool remapped = false;  ///< the motion as a remapped axis: zero own velocities, affine rate L'/L
    bool swapped = false;   ///< the pair listed as (b, a): image index -1 instead of +1
    bool oblique = false;   ///< b half a radius to the side: tilted normal, tangential spring loaded
};
/// Two spheres touching along z in a box whose z length grows at L' = 0.5 m/s without remapping,
/// both moving with the affine flow about the centre, v = L'/L (z - z_c); either in the middle of the
/// box or across the upper boundary, at the same separation. Two steps (the second sees the spring
/// of the first). Returns the force on a; its torque in *torque.
template <class Law>
Vec3 forceInFlow(const FlowCase& c, Vec3* torque = nullptr) {
    const double L = 1e-2, rad = 1e-3, overlap = 1e-5, rate = 0.5;
    PeriodicBox box;
    box.set({0, 0, 0}, {L, L, L}, true, true, true);
    if (c.tell && !c.remapped) box.setFlowRate(2, rate);
    if (c.tell && c.remapped) box.setAffineRate(2, rate / L);
    const double zc = 0.5 * L, side = c.oblique ? 0.5 * rad : 0.0;
    const double gap = std::sqrt((2 * rad - overlap) * (2 * rad - overlap) - side * side);  // z distance
    const double za = c.across ? L - 0.5 * gap : zc - 0.5 * gap;
    const double zb = c.across ? 0.5 * gap : zc + 0.5 * gap;  // b (or its image b + L) above a
    std::vector<Vec3> x{{0.004, 0.005, za}, {0.004 + side, 0.005, zb}};
    std::vector<Vec3> v{{0, 0, rate / L * (za - zc)}, {0, 0, rate / L * (zb - zc)}}, w(2);
    if (c.remapped) v = {Vec3{}, Vec3{}};
    std::vector<double> r{rad, rad}, invM(2, 1e5), m(2, 1e-5);
    std::vector<int32_t> sp{0, 0};
    SpeciesTable spt;
    ContactParameters p;
    p.k = 1e4;
    p.gamma = 0.2;
    p.kt = 2e3;
    p.gammaT = 0.05;
    p.muS = p.muD = 0.5;
    p.youngEff = 1e8;
    p.shearEff = 4e7;
    p.restitution = 0.5;
    spt.add("s", 1000, p);
    std::vector<uint32_t> pi{c.swapped ? 1u : 0u}, pj{c.swapped ? 0u : 1u};
    std::vector<double> hist(Law::H + 1, 0.0);
    std::vector<Vec3> f(2), t(2);
    double e = 0;
    for (int step = 0; step < 2; ++step) {
        f.assign(2, Vec3{});
        t.assign(2, Vec3{});
        Law::template pairRange<true>(0, 1, pi.data(), pj.data(), x.data(), v.data(), w.data(), r.data(),
                                      invM.data(), m.data(), sp.data(), f.data(), t.data(), hist.data(),
                                      MinimumImage(box), spt, 1e-7, 0.0, nullptr, e);
    }
    for (int a = 0; a < 3; ++a) EXPECT_DOUBLE_EQ(f[0][a], -f[1][a]);
    if (torque) *torque = t[0];
    return f[0];
}
void expectSame(const Vec3& a, const Vec3& b, double scale, const std::string& what) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-9 * scale) << what << ", component " << k;
}
} // namespace

// A periodic axis driven by its walls (no remap): the image of a partner k boxes away moves with
// v + k L', so a pair sees through the boundary what it sees inside the box; and a remapped axis with
// the same rate gives the same force (the affine flow is added to the relative velocity). Batched
// (linear) and scalar (Hertz-Mindlin) loops, image index +1 and -1, a head-on and an oblique contact.
// Without the shift the dashpot sees L' as a closing velocity.
TEST(ContactBatch, ImagePartnerMovesWithTheFlowingBoundary) {
    using HertzMindlin = ComposedLaw<NormalHertz, TangentialMindlin, NoPart, NoPart>;
    const double L = 1e-2, rad = 1e-3, overlap = 1e-5, k = 1e4, gamma = 0.2, rate = 0.5;
    const double gap = 2 * rad - overlap;
    // head-on: the affine flow stretches the contact, overlap rate -L' gap / L; the spring pushes a down
    const double expected = -(k * overlap - gamma * rate * gap / L);
    for (bool across : {false, true})
        for (bool remapped : {false, true})
            for (bool swapped : {false, true}) {
                const FlowCase c{across, true, remapped, swapped, false};
                EXPECT_NEAR(forceInFlow<LinearCoulomb>(c).z, expected, 1e-9 * k * overlap);
                EXPECT_NEAR(forceInFlow<LinearOnly>(c).z, expected, 1e-9 * k * overlap);
            }
    // remapped but the loop not told: the pair moves as a rigid body, no dashpot
    EXPECT_NEAR(forceInFlow<LinearOnly>({false, false, true, false, false}).z, -k * overlap, 1e-9 * k * overlap);
    // not told, across the boundary: v_a - v_b = L' (L - gap) / L closes the contact
    EXPECT_NEAR(forceInFlow<LinearOnly>({true, false, false, false, false}).z,
                -(k * overlap + gamma * rate * (L - gap) / L), 1e-9 * k * overlap);
    const Vec3 hIn = forceInFlow<HertzMindlin>({false, true, false, false, false});
    EXPECT_LT(std::fabs(hIn.x), 1e-15);
    for (bool remapped : {false, true})
        for (bool swapped : {false, true})
            expectSame(forceInFlow<HertzMindlin>({true, true, remapped, swapped, false}), hIn, std::fabs(hIn.z),
                       "Hertz head-on");
    EXPECT_GT(std::fabs(forceInFlow<HertzMindlin>({true, false, false, false, false}).z - hIn.z), 1e-3 * std::fabs(hIn.z));
    // oblique: the flow shears the contact, so the tangential spring and the torque take part
    for (int law = 0; law < 2; ++law) {
        Vec3 tIn, t;
        const FlowCase in{false, true, false, false, true};
        const Vec3 fIn = law == 0 ? forceInFlow<LinearCoulomb>(in, &tIn) : forceInFlow<HertzMindlin>(in, &tIn);
        EXPECT_GT(std::fabs(tIn.y), 0.0);
        EXPECT_GT(std::fabs(fIn.x), 1e-6 * std::fabs(fIn.z));
        for (bool across : {false, true})
            for (bool remapped : {false, true})
                for (bool swapped : {false, true}) {
                    const FlowCase c{across, true, remapped, swapped, true};
                    const Vec3 f = law == 0 ? forceInFlow<LinearCoulomb>(c, &t) : forceInFlow<HertzMindlin>(c, &t);
                    const std::string what = std::string(law == 0 ? "linear" : "Hertz") + " oblique, across " +
                                             std::to_string(across) + " remapped " + std::to_string(remapped) +
                                             " swapped " + std::to_string(swapped);
                    expectSame(f, fIn, norm(fIn), what);
                    expectSame(t, tIn, norm(tIn), what + " (torque)");
                }
    }
}
