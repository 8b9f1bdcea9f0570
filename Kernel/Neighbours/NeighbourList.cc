#include "Neighbours/NeighbourList.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <istream>
#include <ostream>
#include <string>
#include <type_traits>

#include "IO/NumberFormat.h"

#include "Boundaries/MinimumImage.h"
#include "Core/Error.h"
#include "Particles/ParticleData.h"
#include "Walls/Wall.h"

namespace pdpm {

std::size_t NeighbourList::bytes() const {
    return (pairI.capacity() + pairJ.capacity() + wallParticle.capacity() + cellStart_.capacity() +
            cellList_.capacity() + runStart_.capacity()) * sizeof(uint32_t) +
           (history.capacity() + wallHistory.capacity()) * sizeof(double) + x0_.capacity() * sizeof(Vec3) +
           slabStart.capacity() * sizeof(std::size_t) + [&] {
               std::size_t b = 0;
               for (const auto& v : phasePairs) b += v.capacity() * sizeof(std::size_t);
               for (const auto& v : phases) b += v.capacity() * sizeof(int);
               return b;
           }();
}

bool NeighbourList::needsRebuild(double maxD, const ParticleData& p, const PeriodicBox& box, const WallList& walls) const {
    if (!valid_ || x0_.size() != p.size() || wallOffset0_.size() != walls.size()) return true;
    const double boxChange = box.lengthChange(0) + box.lengthChange(1) + box.lengthChange(2);
    const double s = skin();
    // radii grown since the build (swelling) close a gap like a displacement: r_i + r_j by twice the bound
    if (growthUnknown_ && p.radiusGrowth > radiusGrowth0_) return true;
    const double grown = std::max(0.0, p.radiusGrowth - radiusGrowth0_);
    if (2 * maxD + 2 * grown + boxChange >= s) return true;
    for (std::size_t w = 0; w < walls.size(); ++w)
        if (maxD + grown + norm(walls[w]->offset() - wallOffset0_[w]) >= s) return true;
    return false;
}

namespace {
template <class T>
void writeVec(std::ostream& os, const char* name, const std::vector<T>& v) {
    os << name << ' ' << v.size() << '\n';
    for (std::size_t k = 0; k < v.size(); ++k) {
        if constexpr (std::is_same_v<T, double>) os << fmt(v[k]);
        else if constexpr (std::is_same_v<T, Vec3>) os << fmt(v[k]);
        else os << v[k];
        os << ((k + 1) % 16 == 0 || k + 1 == v.size() ? '\n' : ' ');
    }
}
// A history array of H doubles per contact written in the canonical layout of H + 1 doubles, with a
// 0 at slot `omitted` (omitted < 0: as stored); the same text as writeVec of the expanded array.
void writeHistory(std::ostream& os, const char* name, const std::vector<double>& v, int H, int omitted) {
    if (omitted < 0 || H <= 0) return writeVec(os, name, v);
    const std::size_t h = static_cast<std::size_t>(H), hc = h + 1, slot = static_cast<std::size_t>(omitted);
    const std::size_t n = v.size() / h * hc;
    os << name << ' ' << n << '\n';
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t c = k / hc, q = k % hc;
        os << fmt(q == slot ? 0.0 : v[c * h + (q < slot ? q : q - 1)]);
        os << ((k + 1) % 16 == 0 || k + 1 == n ? '\n' : ' ');
    }
}
template <class T>
void readVec(std::istream& is, const char* name, std::vector<T>& v, std::size_t maxSize) {
    std::string tag;
    std::size_t n = 0;
    is >> tag >> n;
    if (!is || tag != name || n > maxSize) inputError(std::string("restart: malformed neighbour section '") + name + "'");
    v.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        if constexpr (std::is_same_v<T, double>) v[k] = readDouble(is);
        else if constexpr (std::is_same_v<T, Vec3>) v[k] = readVec3(is);
        else is >> v[k];
    }
    if (!is) inputError(std::string("restart: truncated neighbour section '") + name + "'");
}
} // namespace

void NeighbourList::write(std::ostream& os, int omittedSlot) const {
    const int written = historySize > 0 && omittedSlot >= 0 ? historySize + 1 : historySize;
    os << "neighbours " << fmt(skin_) << ' ' << fmt(skinUsed_) << ' ' << written << ' ' << builds_ << ' '
       << phases.size() << '\n';
    for (const auto& ph : phases) {
        os << ph.size();
        for (int s : ph) os << ' ' << s;
        os << '\n';
    }
    writeVec(os, "slabStart", slabStart);
    writeVec(os, "pairI", pairI);
    writeVec(os, "pairJ", pairJ);
    writeHistory(os, "history", history, historySize, omittedSlot);
    writeVec(os, "wallStart", wallStart);
    writeVec(os, "wallParticle", wallParticle);
    writeVec(os, "wallHistory", wallHistory);
    writeVec(os, "x0", x0_);
    writeVec(os, "wallOffset0", wallOffset0_);
}

void NeighbourList::read(std::istream& is, std::size_t nParticles, std::size_t nWalls, int lawHistorySize) {
    std::string tag;
    std::size_t nPhases = 0;
    is >> tag;
    skin_ = readDouble(is);
    skinUsed_ = readDouble(is);
    is >> historySize >> builds_ >> nPhases;
    wallHistorySize = historySize;  // files hold the canonical layout, pairs and walls alike
    runStart_.clear();              // not in the file: the next build indexes the old pairs instead
    if (!is || tag != "neighbours" || nPhases > 3 || builds_ < 0) inputError("restart: malformed neighbour header");
    // A file edited consistently (H and every history array rewritten, checksum resealed) would pass the
    // size checks below, and the pair loops, which step through the histories by the law's H, would
    // read past them.
    if (historySize != lawHistorySize)
        inputError("restart: neighbour-list history size " + std::to_string(historySize) + " differs from the contact law's " +
                   std::to_string(lawHistorySize) + " doubles per contact");
    phases.assign(nPhases, {});
    for (auto& ph : phases) {
        std::size_t k = 0;
        is >> k;
        if (!is || k > (1u << 24)) inputError("restart: malformed neighbour phases");
        ph.resize(k);
        for (auto& s : ph) is >> s;
    }
    const std::size_t big = std::size_t(1) << 40;
    readVec(is, "slabStart", slabStart, big);
    readVec(is, "pairI", pairI, big);
    readVec(is, "pairJ", pairJ, big);
    readVec(is, "history", history, big);
    readVec(is, "wallStart", wallStart, nWalls + 1);
    readVec(is, "wallParticle", wallParticle, big);
    readVec(is, "wallHistory", wallHistory, big);
    readVec(is, "x0", x0_, nParticles);
    readVec(is, "wallOffset0", wallOffset0_, nWalls);
    const std::size_t np = pairI.size();
    bool ok = pairJ.size() == np && history.size() == np * historySize && !slabStart.empty() &&
              slabStart.back() == np && x0_.size() == nParticles && wallStart.size() == nWalls + 1 &&
              wallHistory.size() == wallParticle.size() * historySize && wallStart.back() == wallParticle.size();
    // slab starts from 0 up to the pair count, never decreasing (a slab's pairs are slabStart[s] ..
    // slabStart[s + 1]; the threads' shares and the rebuild's history moves rely on it)
    ok = ok && slabStart.front() == 0;
    for (std::size_t s = 1; ok && s < slabStart.size(); ++s) ok = slabStart[s - 1] <= slabStart[s];
    for (std::size_t w = 1; ok && w < wallStart.size(); ++w) ok = wallStart[w - 1] <= wallStart[w];
    ok = ok && wallStart.front() == 0;
    for (std::size_t k = 0; ok && k < np; ++k) ok = pairI[k] < pairJ[k] && pairJ[k] < nParticles;  // the builder writes (min, max)
    for (std::size_t k = 0; ok && k < wallParticle.size(); ++k) ok = wallParticle[k] < nParticles;
    for (const auto& ph : phases)
        for (int s : ph) ok = ok && s >= 0 && s + 1 < static_cast<int>(slabStart.size());
    // an edited file (checksum resealed) must not bring NaN into the skin test or the contact springs
    ok = ok && std::isfinite(skin_) && skin_ >= 0 && std::isfinite(skinUsed_) && skinUsed_ >= 0;
    for (double h : history) ok = ok && std::isfinite(h);
    for (double h : wallHistory) ok = ok && std::isfinite(h);
    for (const Vec3& x : x0_) ok = ok && isFinite(x);
    for (const Vec3& x : wallOffset0_) ok = ok && isFinite(x);
    if (!ok) inputError("restart: inconsistent neighbour-list section");
    for (auto& ph : phases) std::sort(ph.begin(), ph.end());  // older files: largest slab first
    countPhasePairs();
    radiusGrowth0_ = 0;
    growthUnknown_ = true;
    valid_ = true;
}

namespace {
// H doubles per contact -> H - 1 (slot removed), in place
void removeSlot(std::vector<double>& v, std::size_t H, std::size_t slot) {
    const std::size_t n = v.size() / H;
    std::size_t o = 0;
    for (std::size_t c = 0; c < n; ++c)
        for (std::size_t q = 0; q < H; ++q)
            if (q != slot) v[o++] = v[c * H + q];
    v.resize(o);
}
// H doubles per contact -> H + 1 (a 0 at slot)
void insertSlot(std::vector<double>& v, std::size_t H, std::size_t slot) {
    const std::size_t n = v.size() / H;
    std::vector<double> w;
    w.reserve(n * (H + 1) + (v.capacity() - v.size()) / H * (H + 1));
    for (std::size_t c = 0; c < n; ++c)
        for (std::size_t q = 0; q <= H; ++q) w.push_back(q == slot ? 0.0 : v[c * H + (q < slot ? q : q - 1)]);
    v.swap(w);
}
} // namespace

void NeighbourList::removeHistorySlot(int slot) {
    if (historySize <= 0 || slot < 0 || slot >= historySize) return;
    removeSlot(history, static_cast<std::size_t>(historySize), static_cast<std::size_t>(slot));
    --historySize;
}

void NeighbourList::insertHistorySlot(int slot) {
    if (historySize <= 0 || slot < 0 || slot > historySize) return;
    insertSlot(history, static_cast<std::size_t>(historySize), static_cast<std::size_t>(slot));
    ++historySize;
}

void NeighbourList::countPhasePairs() {
    phasePairs.resize(phases.size());
    for (std::size_t p = 0; p < phases.size(); ++p) {
        phasePairs[p].assign(phases[p].size() + 1, 0);
        for (std::size_t q = 0; q < phases[p].size(); ++q)
            phasePairs[p][q + 1] = phasePairs[p][q] + (slabStart[phases[p][q] + 1] - slabStart[phases[p][q]]);
    }
}

std::pair<int, int> NeighbourList::threadSlabs(std::size_t p, int thread, int threads) const {
    const std::vector<std::size_t>& pre = phasePairs[p];
    const int n = static_cast<int>(pre.size()) - 1;
    // Thread t starts at the slab boundary whose count of pairs before it is nearest to t/threads of
    // the phase's pairs (a slab is not split: slabs of one phase touch disjoint particles, a slab's
    // pairs do not). "Nearest" rather than "the first at or above": with a few slabs per thread the
    // latter hands the lower threads up to a whole slab too many (pbox, 6 slabs per phase: 4 to 2).
    // Nearest is monotone in t (pre is non-decreasing), so the runs stay contiguous and ordered.
    auto start = [&](int t) {
        if (t <= 0) return 0;
        if (t >= threads) return n;
        const std::size_t target = pre[n] * static_cast<std::size_t>(t) / static_cast<std::size_t>(threads);
        const int up = static_cast<int>(std::lower_bound(pre.begin(), pre.begin() + n + 1, target) - pre.begin());
        if (up > 0 && target - pre[up - 1] < pre[up] - target) return up - 1;
        return up;
    };
    return {start(thread), start(thread + 1)};
}

// history[k] <- old history[src[k]] (none: zeros) for k < src.size(), in place; src is injective
// and is used up (entries are marked done). Writing position k destroys the old entry k, which only
// its (unique) reader may still need; so entries are moved along chains that start at a position
// nobody reads (each move frees the source for the next), and the positions left over form cycles,
// closed with one saved entry.
namespace {
// The old pair of every new pair, kept in the per-slab lists of the search (slabK_) rather than
// copied into one array (4 B per pair less at the build's peak): entry k of the whole list is entry
// k - start[s] of slab s (the last slab that starts at or before k; empty slabs share a start).
struct SlabIndex {
    std::vector<std::vector<uint32_t>>& seg;
    const std::vector<std::size_t>& start;
    std::size_t size() const { return start.back(); }
    uint32_t& operator[](std::size_t k) {
        const std::size_t s = static_cast<std::size_t>(std::upper_bound(start.begin(), start.end(), k) - start.begin()) - 1;
        return seg[s][k - start[s]];
    }
};
} // namespace

template <class Src>
void NeighbourList::moveHistoryInPlace(Src& src, std::size_t nOld, uint32_t none) {
    const std::size_t nNew = src.size(), H = static_cast<std::size_t>(historySize);
    const std::size_t nPos = std::max(nNew, nOld);
    const uint32_t done = none - 1;  // src values are old pair indices < nOld < done
    history.resize(nPos * H);        // within capacity (checked by the caller)
    std::vector<uint64_t> needed((nPos + 63) / 64, 0);
    for (std::size_t k = 0; k < nNew; ++k)
        if (src[k] != none) needed[src[k] >> 6] |= uint64_t(1) << (src[k] & 63);
    auto isNeeded = [&](std::size_t k) { return (needed[k >> 6] >> (k & 63)) & 1u; };
    double* h = history.data();
    for (std::size_t q = 0; q < nNew; ++q) {
        if (src[q] == done || isNeeded(q)) continue;
        std::size_t pos = q;
        while (true) {
            const uint32_t from = src[pos];
            src[pos] = done;
            if (from == none) {
                std::fill_n(h + pos * H, H, 0.0);
                break;
            }
            std::copy_n(h + std::size_t(from) * H, H, h + pos * H);
            if (from >= nNew) break;
            pos = from;  // its old entry has been read: it is free now
        }
    }
    std::vector<double> saved(H);
    for (std::size_t q = 0; q < nNew; ++q) {
        if (src[q] == done) continue;
        std::copy_n(h + q * H, H, saved.data());
        std::size_t pos = q;
        while (true) {
            const uint32_t from = src[pos];
            src[pos] = done;
            if (from == q) {
                std::copy_n(saved.data(), H, h + pos * H);
                break;
            }
            std::copy_n(h + std::size_t(from) * H, H, h + pos * H);
            pos = from;
        }
    }
    history.resize(nNew * H);
}

void NeighbourList::build(ParticleData& p, PeriodicBox& box, const WallList& walls, int hsize, int wsize) {
    if (wsize < 0) wsize = hsize;
    const std::size_t n = p.size();
    if (n >= 0xffffffffu) inputError("too many particles for 32-bit neighbour indices");
    const bool carry = historySize == hsize && hsize > 0;
    const bool carryWallHistory = wallHistorySize == wsize && wsize > 0;

    // The old pair lists stay where they are until the new pairs have been found (each new pair
    // notes the old pair it continues); then the new pairs overwrite them and the histories are
    // moved in place, so a rebuild never holds two full lists (memory per particle matters).
    // The wall lists are short: the old ones are kept aside for their history transfer.
    oldWallParticle_.swap(wallParticle);
    oldWallHistory_.swap(wallHistory);
    oldWallStart_.swap(wallStart);
    historySize = hsize;
    wallHistorySize = wsize;

    for (auto& xi : p.x) box.wrap(xi);

    // ---- cell grid --------------------------------------------------------------------------------
    const double rmax = p.maxRadius();
    double skin = skin_ > 0 ? skin_ : 0.1 * (n ? p.minRadius() : 0);
    const Vec3 L = box.length();
    for (int a = 0; a < 3; ++a) {
        if (!box.periodic(a)) continue;
        // A particle may touch only the nearest image of another: L >= 2 (2 rmax + skin).
        const double maxSkin = 0.5 * L[a] - 2 * rmax;
        if (maxSkin <= 0)
            inputError("periodic box length " + std::to_string(L[a]) + " m along axis " + std::to_string(a) +
                       " is smaller than twice the largest particle diameter");
        skin = std::min(skin, maxSkin * 0.999);
    }
    skinUsed_ = skin;
    const double cutoff = 2 * rmax + skin;

    Vec3 origin, extent;
    int nc[3];
    for (int a = 0; a < 3; ++a) {
        if (box.periodic(a)) {
            origin[a] = box.lo()[a];
            extent[a] = L[a];
        } else {
            double lo = 1e300, hi = -1e300;
            for (const auto& xi : p.x) { lo = std::min(lo, xi[a]); hi = std::max(hi, xi[a]); }
            if (n == 0) { lo = 0; hi = 1; }
            origin[a] = lo;
            extent[a] = std::max(hi - lo, cutoff);
        }
        nc[a] = std::max(1, static_cast<int>(std::floor(extent[a] / cutoff)));
        if (box.periodic(a) && nc[a] < 3) nc[a] = 1;
    }
    // Bound the number of cells for sparse systems.
    while (static_cast<double>(nc[0]) * nc[1] * nc[2] > 8.0 * static_cast<double>(n) + 64) {
        int a = 0;
        for (int k = 1; k < 3; ++k) if (nc[k] > nc[a]) a = k;
        nc[a] = std::max(1, nc[a] / 2);
        if (box.periodic(a) && nc[a] < 3) nc[a] = 1;
    }
    Vec3 invCell;
    for (int a = 0; a < 3; ++a) invCell[a] = nc[a] / extent[a];

    // Axis order of the cell numbering (slab axis outermost). Cells are traversed in this order, so
    // it should follow the order of the particles in memory: an axis along which the particle index
    // rarely steps backwards is "outer". This keeps the force loop streaming through memory for
    // layered configurations (packings generated or inserted layer by layer).
    long descents[3] = {0, 0, 0};
    for (std::size_t i = 1; i < n; ++i)
        for (int a = 0; a < 3; ++a)
            if (p.x[i][a] < p.x[i - 1][a] - cutoff) ++descents[a];
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int a, int b) {
        if (descents[a] != descents[b]) return descents[a] < descents[b];
        return nc[a] > nc[b];
    });
    // The slab axis needs several cells for the parallel phases; otherwise take the longest axis.
    if (nc[order[0]] < 4) {
        int best = 0;
        for (int k = 1; k < 3; ++k) if (nc[order[k]] > nc[order[best]]) best = k;
        std::rotate(order, order + best, order + best + 1);
    }
    const int sa = order[0], sb = order[1], sc = order[2];
    // An even number of slabs along a periodic slab axis gives two balanced phases (an odd number
    // needs a third phase with a single slab, which runs on one thread).
    if (box.periodic(sa) && nc[sa] % 2 == 1 && nc[sa] >= 5) {
        --nc[sa];
        invCell[sa] = nc[sa] / extent[sa];
    }
    const int nSlab = nc[sa];
    const std::size_t nCells = static_cast<std::size_t>(nc[0]) * nc[1] * nc[2];
    auto cellCoord = [&](const Vec3& xi, int a) {
        int c = static_cast<int>((xi[a] - origin[a]) * invCell[a]);
        return std::clamp(c, 0, nc[a] - 1);
    };
    auto cellIndex = [&](int ca, int cb, int cc) {
        return (static_cast<std::size_t>(ca) * nc[sb] + cb) * nc[sc] + cc;
    };

    // Counting sort of the particles into cells (filled backwards from the cell ends, so no fill
    // array is needed; particles stay in increasing index order within a cell).
    auto cellOfParticle = [&](std::size_t i) {
        return cellIndex(cellCoord(p.x[i], sa), cellCoord(p.x[i], sb), cellCoord(p.x[i], sc));
    };
    cellStart_.assign(nCells + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++cellStart_[cellOfParticle(i) + 1];
    for (std::size_t c = 0; c < nCells; ++c) cellStart_[c + 1] += cellStart_[c];
    cellList_.resize(n);
    for (std::size_t i = n; i-- > 0;) {
        const std::size_t c = cellOfParticle(i);
        cellList_[--cellStart_[c + 1]] = static_cast<uint32_t>(i);
    }
    // now cellStart_[c + 1] is the start of cell c: shift back
    for (std::size_t c = 0; c < nCells; ++c) cellStart_[c] = cellStart_[c + 1];
    cellStart_[nCells] = static_cast<uint32_t>(n);
    const bool perSlab = box.periodic(sa);

    // ---- pairs, per slab, in parallel ---------------------------------------------------------------
    // Neither the stencil nor the owner rule may see a cell twice: nc = 2 along a periodic axis is
    // excluded above (nc < 3 -> 1), so +-1 neighbours are distinct cells.
    const MinimumImage img(box);

    // ---- finding the old pair that a new pair continues ----------------------------------------------
    // The last build found the pairs of each particle it visited one after another (runStart_: where
    // that run starts, kNone: none), so the old pair {a, b} lies in the run of a or in that of b:
    // a short scan of each (a run is followed while its pairs contain the particle; any old pair
    // holding both a and b is the one, the pairs being unique). Without runs (the first build after
    // a restart, a changed particle count) an index of the old pairs with a non-zero history
    // (bitwise: -0.0 counts), by their first particle (CSR), is built instead, filled backwards like
    // the cells. Both give the same history to every new pair: a pair found through its run with a
    // zero history moves zeros.
    const std::size_t nOld = pairI.size();
    const bool transfer = carry && nOld > 0 && history.size() == nOld * static_cast<std::size_t>(hsize);
    constexpr uint32_t kNone = 0xffffffffu;
    const bool runs = transfer && runStart_.size() == n;
    std::vector<uint32_t> csrStart, csrIndex;
    if (transfer && !runs) {
        auto carriesHistory = [&](std::size_t k) {
            uint64_t bits = 0;
            for (int q = 0; q < hsize; ++q) bits |= std::bit_cast<uint64_t>(history[k * hsize + q]);
            return bits != 0 && pairI[k] < n && pairJ[k] < n;
        };
        csrStart.assign(n + 1, 0);
        std::size_t nCarry = 0;
        for (std::size_t k = 0; k < nOld; ++k)
            if (carriesHistory(k)) { ++csrStart[pairI[k]]; ++nCarry; }
        for (std::size_t a = 1; a < n; ++a) csrStart[a] += csrStart[a - 1];  // end of a's range
        csrStart[n] = static_cast<uint32_t>(nCarry);
        csrIndex.resize(nCarry);
        for (std::size_t k = nOld; k-- > 0;)
            if (carriesHistory(k)) csrIndex[--csrStart[pairI[k]]] = static_cast<uint32_t>(k);
    }

    slabI_.resize(nSlab);
    slabJ_.resize(nSlab);
    slabK_.resize(nSlab);
    // Expected pairs per slab, from the previous build, so the lists rarely grow while filling.
    const std::size_t expectPerSlab = nOld > 0 ? nOld / nSlab + nOld / (8 * nSlab) + 16 : 0;
    const Vec3* x = p.x.data();
    const double* r = p.r.data();
    const uint32_t* oldI = pairI.data();
    const uint32_t* oldJ = pairJ.data();
    const uint32_t* runOf = runStart_.data();
    // the old pair {a, b} (a < b), or kNone
    auto oldPair = [&](uint32_t a, uint32_t b) -> uint32_t {
        if (runs) {
            for (uint32_t k = runOf[a]; k < nOld && (oldI[k] == a || oldJ[k] == a); ++k)
                if (oldI[k] == b || oldJ[k] == b) return k;
            for (uint32_t k = runOf[b]; k < nOld && (oldI[k] == b || oldJ[k] == b); ++k)
                if (oldI[k] == a || oldJ[k] == a) return k;
            return kNone;
        }
        for (uint32_t e = csrStart[a]; e < csrStart[a + 1]; ++e)
            if (oldJ[csrIndex[e]] == b) return csrIndex[e];
        return kNone;
    };
#pragma omp parallel for schedule(dynamic, 1)
    for (int s = 0; s < nSlab; ++s) {
        // Per slab: the partner j of every pair found, in the order found, and for every particle
        // the slab visits (cells in order, particles in cell order) the number of pairs found from
        // it; the first particle i of each pair is implied by that order, so it is not stored (4 B
        // per pair less at the build's peak). The concatenation walks the same order.
        auto& ln = slabI_[s];
        auto& lj = slabJ_[s];
        auto& lk = slabK_[s];
        ln.clear();
        lj.clear();
        lk.clear();
        lj.reserve(expectPerSlab);
        if (transfer) lk.reserve(expectPerSlab);
        // the slab's cells are contiguous in the cell numbering (slab axis outermost)
        ln.reserve(cellStart_[cellIndex(s, nc[sb] - 1, nc[sc] - 1) + 1] - cellStart_[cellIndex(s, 0, 0)]);
        // Private copies: in the outlined parallel loop, shared variables are reached through
        // pointers, and every push_back would make the compiler reload them.
        const MinimumImage im = img;
        const double sk = skin;
        const uint32_t* __restrict cs = cellStart_.data();
        const uint32_t* __restrict cl = cellList_.data();
        std::size_t stencil[18];
        for (int cb = 0; cb < nc[sb]; ++cb)
            for (int cc = 0; cc < nc[sc]; ++cc) {
                const std::size_t c = cellIndex(s, cb, cc);
                if (cs[c] == cs[c + 1]) continue;
                // Half stencil of this cell, once for all its particles, in the order the particles
                // visit it: this slab layer with the 2D half stencil (own cell: j > i), then the full
                // 3x3 block of the next slab. Every pair is found once, from the particle in the lower
                // slab, so it lands in that slab's list.
                int ns = 0;
                for (int da = 0; da <= 1; ++da) {
                    if (da == 1 && nSlab == 1) break;
                    int ca = s + da;
                    if (ca >= nSlab) { if (!perSlab) break; ca -= nSlab; }
                    for (int db = -1; db <= 1; ++db) {
                        if (nc[sb] == 1 && db != 0) continue;
                        for (int dc = -1; dc <= 1; ++dc) {
                            if (nc[sc] == 1 && dc != 0) continue;
                            // in-layer half stencil: (0,0) own cell, (0,1), (1,-1), (1,0), (1,1)
                            if (da == 0 && (db < 0 || (db == 0 && dc < 0))) continue;
                            int cb2 = cb + db;
                            if (cb2 < 0 || cb2 >= nc[sb]) { if (!box.periodic(sb)) continue; cb2 = (cb2 + nc[sb]) % nc[sb]; }
                            int cc2 = cc + dc;
                            if (cc2 < 0 || cc2 >= nc[sc]) { if (!box.periodic(sc)) continue; cc2 = (cc2 + nc[sc]) % nc[sc]; }
                            stencil[ns++] = cellIndex(ca, cb2, cc2);
                        }
                    }
                }
                for (uint32_t ki = cs[c]; ki < cs[c + 1]; ++ki) {
                    const uint32_t i = cl[ki];
                    const Vec3 xi = x[i];
                    const double ri = r[i];
                    const std::size_t first = lj.size();
                    for (int q = 0; q < ns; ++q) {
                        const std::size_t c2 = stencil[q];
                        const uint32_t kEnd = cs[c2 + 1];
                        for (uint32_t kj = c2 == c ? ki + 1 : cs[c2]; kj < kEnd; ++kj) {
                            const uint32_t j = cl[kj];
                            double dx = xi.x - x[j].x, dy = xi.y - x[j].y, dz = xi.z - x[j].z;
                            im.apply(dx, dy, dz);
                            const double rc = ri + r[j] + sk;  // the same sum as before: same lists
                            if (dx * dx + dy * dy + dz * dz < rc * rc) lj.push_back(j);
                        }
                    }
                    ln.push_back(static_cast<uint32_t>(lj.size() - first));
                    // the old pair that each new pair continues (its history moves along)
                    if (transfer)
                        for (std::size_t q = first; q < lj.size(); ++q)
                            lk.push_back(oldPair(std::min(i, lj[q]), std::max(i, lj[q])));
                }
            }
    }
    std::vector<uint32_t>().swap(csrStart);
    std::vector<uint32_t>().swap(csrIndex);

    // ---- concatenate: the new pairs overwrite the old ones --------------------------------------
    slabStart.assign(nSlab + 1, 0);
    for (int s = 0; s < nSlab; ++s) slabStart[s + 1] = slabStart[s] + slabJ_[s].size();
    const std::size_t nPairs = slabStart[nSlab];
    // A little spare capacity, so that a list that grows slowly (a compressed packing) rarely needs a
    // new block (which, for the history, would briefly hold old and new together).
    const std::size_t spare = nPairs + nPairs / 16 + 64;
    auto resizeDiscarding = [&](auto& v, std::size_t size) {
        if (size > v.capacity()) {
            std::remove_reference_t<decltype(v)>().swap(v);
            v.reserve(size + (size / static_cast<std::size_t>(nPairs ? nPairs : 1)) * (spare - nPairs));
        }
        v.resize(size);
    };
    resizeDiscarding(pairI, nPairs);
    resizeDiscarding(pairJ, nPairs);
    if (nPairs >= kNone) inputError("too many neighbour pairs for 32-bit pair indices");
    runStart_.assign(n, kNone);  // the runs of this build, for the next one
    for (int s = 0; s < nSlab; ++s) {
        // the visiting order of the search: cells of the slab in order, particles in cell order
        const std::vector<uint32_t>& ln = slabI_[s];
        const std::vector<uint32_t>& lj = slabJ_[s];
        std::size_t out = slabStart[s], q = 0, v = 0;
        for (int cb = 0; cb < nc[sb]; ++cb)
            for (int cc = 0; cc < nc[sc]; ++cc) {
                const std::size_t c = cellIndex(s, cb, cc);
                for (uint32_t ki = cellStart_[c]; ki < cellStart_[c + 1]; ++ki) {
                    const uint32_t i = cellList_[ki];
                    if (ln[v] > 0) runStart_[i] = static_cast<uint32_t>(out);
                    for (uint32_t e = ln[v++]; e > 0; --e, ++q, ++out) {
                        pairI[out] = std::min(i, lj[q]);
                        pairJ[out] = std::max(i, lj[q]);
                    }
                }
            }
    }
    auto release = [](auto& v) { std::remove_reference_t<decltype(v)>().swap(v); };
    for (auto& v : slabI_) release(v);
    for (auto& v : slabJ_) release(v);
    // Phases: even slabs, odd slabs (and the last slab alone if periodic and odd in number).
    phases.clear();
    if (nSlab == 1) {
        phases.push_back({0});
    } else {
        std::vector<int> even, odd, last;
        for (int s = 0; s < nSlab; ++s) {
            if (perSlab && (nSlab % 2 == 1) && s == nSlab - 1) last.push_back(s);
            else (s % 2 == 0 ? even : odd).push_back(s);
        }
        phases.push_back(even);
        phases.push_back(odd);
        if (!last.empty()) phases.push_back(last);
    }
    // Within a phase, the slabs touch disjoint particles, so the order in which they are handed to
    // the threads does not change any result. Each thread takes a contiguous run of slabs with an
    // equal share of the pairs (threadSlabs): balanced for non-uniform systems (a settled bed's thin
    // top slabs) and, unlike a dynamic hand-out, the same particles for the same thread every step.
    countPhasePairs();

    // ---- history transfer: new pair k takes the history of old pair src[k] (or zeros) -------------
    SlabIndex src{slabK_, slabStart};
    const std::size_t H = static_cast<std::size_t>(hsize);
    if (!transfer) {
        resizeDiscarding(history, nPairs * H);
        std::fill(history.begin(), history.end(), 0.0);
    } else if (nPairs * H > history.capacity()) {
        // The list outgrew its spare capacity: gather into a new block.
        std::vector<double> fresh;
        fresh.reserve(spare * H);
        fresh.resize(nPairs * H, 0.0);
        for (std::size_t k = 0; k < nPairs; ++k)
            if (src[k] != kNone) std::copy_n(&history[src[k] * H], H, &fresh[k * H]);
        history.swap(fresh);
    } else {
        moveHistoryInPlace(src, nOld, kNone);
    }
    for (auto& v : slabK_) release(v);

    // ---- wall lists -----------------------------------------------------------------------------
    const bool carryWalls = carryWallHistory && oldWallStart_.size() == walls.size() + 1;
    wallStart.assign(walls.size() + 1, 0);
    wallParticle.clear();
    wallHistory.clear();
    for (std::size_t w = 0; w < walls.size(); ++w) {
        std::size_t q = carryWalls ? oldWallStart_[w] : 0;
        const std::size_t qEnd = carryWalls ? oldWallStart_[w + 1] : 0;
        for (std::size_t i = 0; i < n; ++i) {
            Vec3 nrm;
            const double d = walls[w]->distance(p.x[i], nrm);
            if (d < p.r[i] + skin) {
                wallParticle.push_back(static_cast<uint32_t>(i));
                const std::size_t base = wallHistory.size();
                wallHistory.resize(base + wsize, 0.0);
                while (q < qEnd && oldWallParticle_[q] < i) ++q;
                if (q < qEnd && oldWallParticle_[q] == i)
                    std::copy_n(&oldWallHistory_[q * wsize], wsize, &wallHistory[base]);
            }
        }
        wallStart[w + 1] = wallParticle.size();
    }

    x0_ = p.x;
    radiusGrowth0_ = p.radiusGrowth;
    growthUnknown_ = false;
    // Release the build's scratch: memory per particle matters more than the cost of reallocating
    // it at the next build (builds are tens of steps apart).
    release(oldWallParticle_); release(oldWallHistory_); release(oldWallStart_);
    release(cellList_); release(cellStart_);
    wallOffset0_.resize(walls.size());
    for (std::size_t w = 0; w < walls.size(); ++w) wallOffset0_[w] = walls[w]->offset();
    box.resetChange();
    valid_ = true;
    ++builds_;
}

} // namespace pdpm
