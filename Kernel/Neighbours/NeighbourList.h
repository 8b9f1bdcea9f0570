// Verlet neighbour list built with linked cells: O(N) per build, rebuilt only when some particle
// moved more than half the skin (or the periodic box / a wall moved enough).
//
// Pairs are stored canonically (i < j) together with the contact history of the law, and grouped
// into slabs along one axis. A pair belongs to the slab of the particle in the lower slab, so the
// pairs of slab s touch only particles of slabs s and s+1. Slabs of the same phase (even / odd)
// therefore touch disjoint particles and are processed in parallel; every particle receives its
// contributions in an order that does not depend on the number of threads -> bitwise-identical
// results for any thread count, without atomics or per-pair force buffers.
#pragma once
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <utility>
#include <vector>

#include "Math/Vec3.h"

namespace pdpm {

struct ParticleData;
class PeriodicBox;
class Wall;
using WallList = std::vector<std::unique_ptr<Wall>>;

class NeighbourList {
public:
    void setSkin(double skin) { skin_ = skin; }
    double skin() const { return skinUsed_ > 0 ? skinUsed_ : skin_; }

    /// True if the list must be rebuilt before the next force evaluation. `maxDisplacement` is the
    /// largest distance of a particle from its referencePositions() (computed by the caller, fused
    /// with the integration).
    bool needsRebuild(double maxDisplacement, const ParticleData& p, const PeriodicBox& box, const WallList& walls) const;
    /// Particle positions at the last build.
    const Vec3* referencePositions() const { return x0_.data(); }
    std::size_t referenceCount() const { return valid_ ? x0_.size() : 0; }
    /// Wrap particles into the periodic box and rebuild pairs and wall lists, carrying contact
    /// histories over. `historySize` = doubles of history per pair, `wallHistorySize` per wall
    /// contact (from the contact law; -1: the same as per pair).
    void build(ParticleData& p, PeriodicBox& box, const WallList& walls, int historySize, int wallHistorySize = -1);
    /// Forget everything (e.g. after particles were added or the law changed).
    void invalidate() { valid_ = false; }
    /// Forgets every contact history (pairs and walls), so that the next build starts all contacts
    /// afresh: for a state whose histories belong to another contact law.
    void dropHistories() {
        history.clear();
        wallHistory.clear();
        historySize = wallHistorySize = 0;
        runStart_.clear();
        valid_ = false;
    }
    bool isValid() const { return valid_; }
    /// Change the pairs' history layout in place: drop slot `slot` of every pair's history, or insert
    /// a 0 there (a contact law switching form, ContactLaw::specialised). Wall histories keep theirs.
    void removeHistorySlot(int slot);
    void insertHistorySlot(int slot);

    // ---- pair data (read by the contact loops) --------------------------------------------------
    std::vector<uint32_t> pairI, pairJ;  ///< canonical i < j
    std::vector<double> history;         ///< historySize doubles per pair
    std::vector<std::size_t> slabStart;  ///< pairs of slab s: [slabStart[s], slabStart[s+1])
    std::vector<std::vector<int>> phases;///< slabs processed together (ascending); phases run one after another
    /// Pairs of the slabs of phase p before its q-th slab: phasePairs[p][q] (size phases[p].size() + 1).
    std::vector<std::vector<std::size_t>> phasePairs;
    /// Slabs [first, last) of phase p that thread `thread` of `threads` handles: a contiguous run of
    /// slabs with about 1/threads of the phase's pairs. Contiguous slabs hold contiguous particle
    /// ranges (the cell numbering follows memory order), so each thread keeps working on the
    /// particles that the statically scheduled integration passes give it (cache affinity).
    std::pair<int, int> threadSlabs(std::size_t p, int thread, int threads) const;
    int historySize = 0;
    int wallHistorySize = 0;  ///< doubles per wall contact (a law's one-coefficient form: one more than per pair)

    // ---- wall data: particles near wall w are wallParticle[wallStart[w] .. wallStart[w+1]) ------
    std::vector<uint32_t> wallParticle;
    std::vector<double> wallHistory;      ///< wallHistorySize doubles per entry
    std::vector<std::size_t> wallStart;

    long builds() const { return builds_; }
    std::size_t pairCount() const { return pairI.size(); }
    int slabCount() const { return static_cast<int>(slabStart.size()) - 1; }
    std::size_t bytes() const;

    /// Exact state for restart files (pairs in order, histories, slabs, reference positions), so a
    /// restarted run continues bitwise-identically without rebuilding.
    /// Restart section. omittedSlot >= 0: the pairs' histories are written in the law's canonical
    /// layout, one double more per pair with 0 at that slot (ContactLaw::omittedSlot); the wall
    /// histories are stored in it already.
    void write(std::ostream& os, int omittedSlot = -1) const;
    /// Reads the section written by write(); historySize must equal lawHistorySize, the doubles per
    /// contact of the law line of the same file (the pair loops index the histories with the law's H).
    void read(std::istream& is, std::size_t nParticles, std::size_t nWalls, int lawHistorySize);

private:
    void countPhasePairs();
    double skin_ = 0;
    double skinUsed_ = 0;
    bool valid_ = false;
    long builds_ = 0;
    std::vector<Vec3> x0_;            ///< positions at the last build
    std::vector<uint32_t> runStart_;  ///< per particle: its first pair found from it at the last build (~0u: none)
    std::vector<Vec3> wallOffset0_;   ///< wall offsets at the last build
    /// ParticleData::radiusGrowth at the last build. Not in restart files: a list read from one does
    /// not know how much its skin the radii used before, so it is rebuilt as soon as radii grow
    /// (growthUnknown_); runs without swelling are not affected.
    double radiusGrowth0_ = 0;
    bool growthUnknown_ = false;
    // build scratch (released after each build)
    std::vector<uint32_t> cellStart_, cellList_;
    std::vector<std::vector<uint32_t>> slabI_, slabJ_, slabK_;  ///< per slab: pairs per visited particle, partner, old pair
    std::vector<uint32_t> oldWallParticle_;
    std::vector<double> oldWallHistory_;
    std::vector<std::size_t> oldWallStart_;

    template <class Src>
    void moveHistoryInPlace(Src& src, std::size_t nOld, uint32_t none);
};

} // namespace pdpm
