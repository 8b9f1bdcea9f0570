// The batched (SIMD) linear law of Contacts/LinearBatch.h against the scalar parts it replaces in
// the pair loop (NormalLinear + TangentialCoulomb, NormalLinear alone): random contacts covering
// sticking, sliding (static and dynamic limit), springs that must be rotated, zero springs, zero
// tangential stiffness and separating (attractive dashpot) contacts. The two may differ in the last
// bits (fused multiply-adds), so the comparison is relative, 1e-12 of the force scale.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "Contacts/ComposedLaw.h"
#include "Contacts/LinearBatch.h"
#include "Contacts/NormalLaws.h"
#include "Contacts/TangentialLaws.h"

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
            b.k[q] = c.p.k; b.gamma[q] = c.p.gamma;
            b.kt[q] = c.p.kt; b.gammaT[q] = c.p.gammaT; b.muS[q] = c.p.muS; b.muD[q] = c.p.muD;
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
            EXPECT_LT(relDiff(b.energy[q], o.energy, std::max(1e-300, o.energy)), 1e-10);
            if constexpr (kFriction) {
                const Vec3 nxft = cross(st.n, o.ft);
                const double ts = std::max(1e-300, ai * norm(o.ft));
                EXPECT_LT(relDiff(b.tix[q], -(ai * nxft).x, ts), 1e-12);
                EXPECT_LT(relDiff(b.tiy[q], -(ai * nxft).y, ts), 1e-12);
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
