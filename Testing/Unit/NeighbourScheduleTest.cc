// The thread schedule of the pair loop (NeighbourList::threadSlabs): for any thread count, every slab
// of a phase is handled by exactly one thread, each thread's slabs are one contiguous run, and the
// runs split the phase's pairs evenly up to one slab.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "Boundaries/PeriodicBox.h"
#include "Neighbours/NeighbourList.h"
#include "Particles/ParticleData.h"
#include "Walls/Wall.h"

using namespace pdpm;

namespace {
// A layered bed: dense at the bottom, thinning towards the top (non-uniform slabs along z).
void layeredBed(ParticleData& P, PeriodicBox& box, unsigned seed) {
    const double L = 0.02, H = 0.04, r = 5e-4;
    box.set({0, 0, 0}, {L, L, H}, true, true, true);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    for (int k = 0; k < 4000; ++k) {
        const double z = H * (1 - std::sqrt(u(rng)));  // more particles low down
        P.add({L * u(rng), L * u(rng), z}, r * (0.8 + 0.4 * u(rng)), 2000, 0);
    }
    // memory order follows z, as for a bed poured or inserted layer by layer
    std::vector<std::size_t> idx(P.size());
    for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return P.x[a].z < P.x[b].z; });
    ParticleData Q;
    for (std::size_t i : idx) Q.add(P.x[i], P.r[i], 2000, 0);
    P = Q;
}
} // namespace

TEST(NeighbourSchedule, EverySlabOnceContiguousAndBalancedByPairs) {
    ParticleData P;
    PeriodicBox box;
    layeredBed(P, box, 5);
    NeighbourList nl;
    nl.setSkin(1e-4);
    const WallList walls;
    nl.build(P, box, walls, 0);
    ASSERT_GE(nl.phases.size(), 2u);
    ASSERT_EQ(nl.phasePairs.size(), nl.phases.size());
    for (std::size_t ph = 0; ph < nl.phases.size(); ++ph) {
        const auto& slabs = nl.phases[ph];
        EXPECT_TRUE(std::is_sorted(slabs.begin(), slabs.end()));
        std::size_t total = 0, largest = 0;
        for (int s : slabs) {
            const std::size_t np = nl.slabStart[s + 1] - nl.slabStart[s];
            total += np;
            largest = std::max(largest, np);
        }
        ASSERT_EQ(nl.phasePairs[ph].back(), total);
        for (int threads = 1; threads <= 9; ++threads) {
            std::vector<int> owner(slabs.size(), -1);
            int prevEnd = 0;
            for (int t = 0; t < threads; ++t) {
                const auto [a, b] = nl.threadSlabs(ph, t, threads);
                EXPECT_EQ(a, prevEnd) << "contiguous runs, in thread order";
                ASSERT_LE(a, b);
                std::size_t pairs = 0;
                for (int q = a; q < b; ++q) {
                    EXPECT_EQ(owner[std::size_t(q)], -1) << "slab handled twice";
                    owner[std::size_t(q)] = t;
                    pairs += nl.slabStart[slabs[std::size_t(q)] + 1] - nl.slabStart[slabs[std::size_t(q)]];
                }
                EXPECT_LE(pairs, total / std::size_t(threads) + largest) << "phase " << ph << ", " << threads << " threads";
                prevEnd = b;
            }
            EXPECT_EQ(prevEnd, int(slabs.size()));
            EXPECT_TRUE(std::none_of(owner.begin(), owner.end(), [](int o) { return o < 0; })) << "slab left out";
        }
    }
}

// The boundary between two threads' runs is the slab boundary nearest to the equal share. Phase 1 of
// the pbox deck's first list (six slabs): the first boundary at or above half the pairs would give
// thread 0 four slabs (10233 of 15339 pairs, 67 %) and thread 1 two; the nearest gives 3 and 3.
TEST(NeighbourSchedule, ThreadBoundaryIsTheNearestToAnEqualShare) {
    NeighbourList nl;
    nl.phases = {{1, 3, 5, 7, 9, 11}};
    nl.phasePairs = {{0, 2482, 5110, 7518, 10233, 12660, 15339}};
    EXPECT_EQ(nl.threadSlabs(0, 0, 2), std::make_pair(0, 3));
    EXPECT_EQ(nl.threadSlabs(0, 1, 2), std::make_pair(3, 6));
    // three threads: targets 5113 and 10226 -> boundaries after slabs 2 and 4
    EXPECT_EQ(nl.threadSlabs(0, 0, 3), std::make_pair(0, 2));
    EXPECT_EQ(nl.threadSlabs(0, 1, 3), std::make_pair(2, 4));
    EXPECT_EQ(nl.threadSlabs(0, 2, 3), std::make_pair(4, 6));
    // one heavy slab: the runs stay contiguous, ordered and may be empty
    nl.phasePairs = {{0, 1, 2, 1000, 1001, 1002, 1003}};
    for (int threads = 1; threads <= 8; ++threads) {
        int prevEnd = 0;
        for (int t = 0; t < threads; ++t) {
            const auto [a, b] = nl.threadSlabs(0, t, threads);
            EXPECT_EQ(a, prevEnd);
            EXPECT_LE(a, b);
            prevEnd = b;
        }
        EXPECT_EQ(prevEnd, 6);
    }
}
