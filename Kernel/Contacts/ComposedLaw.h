// A contact law composed of parts (normal N, tangential T, rolling R, torsion O). The loops over
// particle pairs and wall contacts are instantiated per composition so every part inlines.
#pragma once
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <string>
#include <type_traits>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "Boundaries/MinimumImage.h"
#include "Contacts/ContactLaw.h"
#include "Contacts/LinearBatch.h"
#include "Contacts/TangentialLaws.h"
#include "Particles/ParticleData.h"
#include "Walls/Wall.h"

namespace pdpm {

template <class N, class T, class R, class O>
class ComposedLaw final : public ContactLaw {
public:
    static constexpr int H = N::H + T::H + R::H + O::H;
    static constexpr bool kTangential = T::H > 0 || R::H > 0 || O::H > 0;
    static constexpr bool kNeedsMass = N::kNeedsMass || T::kNeedsMass;
    static constexpr bool kNeedsRadius = N::kNeedsRadius || T::kNeedsRadius || R::H > 0 || O::H > 0;
    /// Laws with a batched (SIMD) pair loop: linear normal force, with or without Coulomb friction.
    static constexpr bool kBatch = std::is_same_v<N, NormalLinear> &&
                                   (std::is_same_v<T, TangentialCoulomb> || std::is_same_v<T, TangentialCoulombOneMu> ||
                                    std::is_same_v<T, NoPart>) &&
                                   std::is_same_v<R, NoPart> && std::is_same_v<O, NoPart>;
    /// Compositions that exist in two forms, with the sliding flag stored in the pairs' histories
    /// (TangentialCoulomb) and without (TangentialCoulombOneMu, when every pair has mu_s = mu_d): the
    /// law `linear`, whose pairs go through the SIMD batch, where the two forms are the same
    /// instructions but for the flag's load and store. (In the scalar loops of the other laws the
    /// compiler vectorises the two forms differently, which fuses multiply-adds differently: results
    /// would differ in the last bits.) Wall contacts keep the flagged form and layout (the same code
    /// as the flagged law, hence the same bits; they are few).
    static constexpr bool kOneMuForm = kBatch && !std::is_same_v<T, NoPart>;
    static constexpr bool kOneMu = std::is_same_v<T, TangentialCoulombOneMu>;
    using Flagged = ComposedLaw<N, std::conditional_t<kOneMu, TangentialCoulomb, T>, R, O>;

    explicit ComposedLaw(std::string name) : name_(std::move(name)) {}
    std::string name() const override { return name_; }
    int historySize() const override { return H; }
    int omittedSlot() const override { return kOneMu ? N::H + 3 : -1; }
    int wallHistorySize() const override { return Flagged::H; }
    std::unique_ptr<ContactLaw> specialised(const SpeciesTable& species) const override {
        if constexpr (kOneMuForm) {
            bool oneMu = true;  // every defined entry, in use or not (a pair used later must fit too)
            for (int a = 0; a < species.size(); ++a)
                for (int b = 0; b < species.size(); ++b)
                    if (species.pair(a, b).defined && species.pair(a, b).muS != species.pair(a, b).muD) oneMu = false;
            constexpr bool flagged = std::is_same_v<T, TangentialCoulomb>;
            if (oneMu && flagged) return std::make_unique<ComposedLaw<N, TangentialCoulombOneMu, R, O>>(name_);
            if (!oneMu && !flagged) return std::make_unique<ComposedLaw<N, TangentialCoulomb, R, O>>(name_);
        }
        (void)species;
        return nullptr;
    }
    void validate(const ContactParameters& p, const std::string& who) const override {
        N::validate(p, who);
        T::validate(p, who);
        R::validate(p, who);
        O::validate(p, who);
    }
    double stiffness(const ContactParameters& p, double rEff) const override {
        return std::max({N::stiffness(p, rEff), T::stiffness(p, rEff), R::stiffness(p, rEff), O::stiffness(p, rEff)});
    }
    double normalDamping(const ContactParameters& p) const override { return N::damping(p); }

    static inline void eval(const ContactParameters& p, const ContactState& s, double* h, ContactOutput& o) {
        N::apply(p, s, h, o);
        T::apply(p, s, h + N::H, o);
        R::apply(p, s, h + N::H + T::H, o);
        O::apply(p, s, h + N::H + T::H + R::H, o);
    }
    void evaluate(const ContactParameters& p, const ContactState& s, double* h, ContactOutput& o) const override {
        eval(p, s, h, o);
    }

    /// Forces of the pairs [k0, k1) of one slab. Restrict-qualified pointers: the arrays never alias.
    /// The pairs are taken in chunks. Where many listed pairs are near misses (a static bed: about as
    /// many as contacts) a chunk is screened first: a branch-free pass computes the separations and
    /// collects the pairs in contact (resetting the history of pairs that just separated), then the
    /// law runs over the collected pairs; this removes the unpredictable contact / near-miss branch.
    /// Where nearly all pairs touch (a compressed packing) the plain single pass is cheaper, and the
    /// loop switches by the hit rate of the previous chunk. Either way each pair's arithmetic and the
    /// order of the force accumulation are the same, so the choice never changes a result.
    /// Laws with a batched path (kBatch: linear, linear-frictionless) go to batchRange instead, which
    /// always screens.
    template <bool kPeriodic>
    [[gnu::flatten]] static void pairRange(std::size_t k0, std::size_t k1, const uint32_t* __restrict pi,
                                           const uint32_t* __restrict pj, const Vec3* __restrict x,
                                           const Vec3* __restrict v, const Vec3* __restrict w,
                                           const double* __restrict r, const double* __restrict invM,
                                           const double* __restrict m, const int32_t* __restrict sp,
                                           Vec3* __restrict f, Vec3* __restrict t, double* __restrict hist,
                                           const MinimumImage img, const SpeciesTable& spt, double dt, double time,
                                           std::vector<ContactRecord>* rec, double& energy) {
        if constexpr (kBatch) {
            batchRange<kPeriodic>(k0, k1, pi, pj, x, v, w, r, sp, f, t, hist, img, spt, dt, rec, energy);
            return;
        }
        constexpr std::size_t kChunk = 256;
        uint32_t hit[kChunk];
        double sdx[kChunk], sdy[kChunk], sdz[kChunk], sd2[kChunk];
        bool screen = true;
        for (std::size_t c0 = k0; c0 < k1; c0 += kChunk) {
            const std::size_t c1 = std::min(k1, c0 + kChunk);
            std::size_t nHit = 0;
            if (screen) {
                nHit = screenChunk<kPeriodic>(c0, c1, pi, pj, x, r, img, hist, hit, sdx, sdy, sdz, sd2);
                for (std::size_t q = 0; q < nHit; ++q) {
                    const std::size_t k = c0 + hit[q];
                    contact<kPeriodic>(k, pi[k], pj[k], sdx[q], sdy[q], sdz[q], sd2[q], x, v, w, r, invM, m,
                                       sp, f, t, hist, img, spt, dt, time, rec, energy);
                }
            } else {
                for (std::size_t k = c0; k < c1; ++k) {
                    const uint32_t i = pi[k], j = pj[k];
                    double dx, dy, dz, d2;
                    if (separation<kPeriodic>(i, j, x, r, img, dx, dy, dz, d2)) {
                        ++nHit;
                        contact<kPeriodic>(k, i, j, dx, dy, dz, d2, x, v, w, r, invM, m, sp, f, t, hist, img,
                                           spt, dt, time, rec, energy);
                    } else if constexpr (H > 0) {
                        if (dirtyHistory(hist + k * H))
                            for (int q = 0; q < H; ++q) hist[k * H + q] = 0.0;
                    }
                }
            }
            screen = 8 * nHit < 7 * (c1 - c0);
        }
    }

    /// pairRange for the laws of LinearBatch: per chunk, a branch-free screening pass collects the
    /// touching pairs (and resets the history of pairs that separated), a gather pass copies their
    /// data into the batch, the batch is evaluated in SIMD lanes, and a scatter pass adds the forces
    /// and torques to the particles in pair order (the same order for any thread count).
    template <bool kPeriodic>
    static void batchRange(std::size_t k0, std::size_t k1, const uint32_t* __restrict pi,
                           const uint32_t* __restrict pj, const Vec3* __restrict x, const Vec3* __restrict v,
                           const Vec3* __restrict w, const double* __restrict r, const int32_t* __restrict sp,
                           Vec3* __restrict f, Vec3* __restrict t, double* __restrict hist, const MinimumImage img,
                           const SpeciesTable& spt, double dt, std::vector<ContactRecord>* rec, double& energy) {
        constexpr bool kFriction = std::is_same_v<T, TangentialCoulomb> || std::is_same_v<T, TangentialCoulombOneMu>;
        constexpr bool kFlag = std::is_same_v<T, TangentialCoulomb>;  // the sliding flag is stored (h[3])
        constexpr std::size_t kChunk = LinearBatch::kChunk;
        LinearBatch b;  // 22.5 kB on the stack (OpenMP threads have MiB stacks); nothing to initialise
        uint32_t hit[kChunk];
        const bool oneSpecies = spt.size() == 1;
        if (oneSpecies)  // the parameters are the same in every lane
            for (std::size_t q = 0; q < LinearBatch::kMax; ++q) b.template setParameters<kFriction>(q, spt.pair(0, 0));
        for (std::size_t c0 = k0; c0 < k1; c0 += kChunk) {
            const std::size_t c1 = std::min(k1, c0 + kChunk);
            const std::size_t n = screenChunk<kPeriodic>(c0, c1, pi, pj, x, r, img, hist, hit, b.dx, b.dy, b.dz, b.d2);
            if (n == 0) continue;
            for (std::size_t q = 0; q < n; ++q) {
                const std::size_t k = c0 + hit[q];
                const uint32_t i = pi[k], j = pj[k];
                b.ri[q] = r[i];
                b.rj[q] = r[j];
                b.vx[q] = v[i].x - v[j].x;
                b.vy[q] = v[i].y - v[j].y;
                b.vz[q] = v[i].z - v[j].z;
                if constexpr (kPeriodic) {
                    if (img.flow) {  // partner seen through a boundary that moves: its image moves with it
                        double ux, uy, uz;
                        img.imageVelocity(x[i].x - x[j].x, x[i].y - x[j].y, x[i].z - x[j].z, ux, uy, uz);
                        b.vx[q] -= ux;
                        b.vy[q] -= uy;
                        b.vz[q] -= uz;
                    }
                }
                if (img.affine) img.addAffine(b.dx[q], b.dy[q], b.dz[q], b.vx[q], b.vy[q], b.vz[q]);
                if constexpr (kFriction) {
                    b.wix[q] = w[i].x;
                    b.wiy[q] = w[i].y;
                    b.wiz[q] = w[i].z;
                    b.wjx[q] = w[j].x;
                    b.wjy[q] = w[j].y;
                    b.wjz[q] = w[j].z;
                    const double* h = hist + k * H;
                    b.h0[q] = h[0];
                    b.h1[q] = h[1];
                    b.h2[q] = h[2];
                    if constexpr (kFlag) b.h3[q] = h[3];
                }
                if (!oneSpecies) b.template setParameters<kFriction>(q, spt.pair(sp[i], sp[j]));
            }
            const std::size_t m = b.pad(n, kFriction, !oneSpecies);
            b.template evaluate<kFriction, kFlag>(m, dt);
            for (std::size_t q = 0; q < n; ++q) {
                const std::size_t k = c0 + hit[q];
                const uint32_t i = pi[k], j = pj[k];
                const Vec3 F{b.Fx[q], b.Fy[q], b.Fz[q]};
                f[i] += F;
                f[j] -= F;
                if constexpr (kFriction) {
                    t[i] += Vec3{b.tix[q], b.tiy[q], b.tiz[q]};
                    t[j] += Vec3{b.tjx[q], b.tjy[q], b.tjz[q]};
                    double* h = hist + k * H;
                    h[0] = b.h0[q];
                    h[1] = b.h1[q];
                    h[2] = b.h2[q];
                    if constexpr (kFlag) h[3] = b.h3[q];
                }
                if (rec) [[unlikely]] {
                    const Vec3 nrm{b.nx[q], b.ny[q], b.nz[q]};
                    Vec3 ft;
                    if constexpr (kFriction) ft = {b.ftx[q], b.fty[q], b.ftz[q]};
                    energy += b.energy[q];
                    ContactRecord cr;
                    cr.i = static_cast<int>(i);
                    cr.j = static_cast<int>(j);
                    const double a = r[i] - 0.5 * b.overlap[q];
                    cr.point = x[i] - a * nrm;
                    cr.overlap = b.overlap[q];
                    cr.n = nrm;
                    cr.fn = b.fn[q];
                    cr.ft = ft;
                    cr.branch = {b.dx[q], b.dy[q], b.dz[q]};
                    cr.sliding = kFriction && b.sliding[q] != 0;
                    cr.energy = b.energy[q];
                    rec->push_back(cr);
                }
            }
        }
    }

    /// Screening pass over the listed pairs c0..c1 (at most one chunk): the offsets (from c0) of the
    /// touching pairs go to hit[0..n), their separations and squared distances to sdx..sd2[0..n); the
    /// history of a pair that no longer touches is reset. Branch-free except for the rare reset.
    /// Returns n. Used by pairRange (screened chunks) and batchRange (every chunk).
    template <bool kPeriodic>
    [[gnu::always_inline]] static inline std::size_t
    screenChunk(std::size_t c0, std::size_t c1, const uint32_t* __restrict pi, const uint32_t* __restrict pj,
                const Vec3* __restrict x, const double* __restrict r, const MinimumImage& img,
                double* __restrict hist, uint32_t* __restrict hit, double* __restrict sdx, double* __restrict sdy,
                double* __restrict sdz, double* __restrict sd2) {
        std::size_t n = 0;
        for (std::size_t k = c0; k < c1; ++k) {
            double dx, dy, dz, d2;
            const bool touching = separation<kPeriodic>(pi[k], pj[k], x, r, img, dx, dy, dz, d2);
            hit[n] = static_cast<uint32_t>(k - c0);
            sdx[n] = dx;
            sdy[n] = dy;
            sdz[n] = dz;
            sd2[n] = d2;
            n += touching ? 1 : 0;
            if constexpr (H > 0) {
                // One well-predicted branch on the combined flag: the empty asm makes the flag
                // opaque, so the compiler cannot split it into a branch on `dirty` (which would
                // mispredict like the contact test itself).
                unsigned reset = dirtyHistory(hist + k * H) & static_cast<unsigned>(!touching);
                asm("" : "+r"(reset));
                if (reset != 0) [[unlikely]]
                    for (int q = 0; q < H; ++q) hist[k * H + q] = 0.0;
            }
        }
        return n;
    }

    /// Separation x_i - x_j of a pair (minimum image if periodic) and its squared length; true if
    /// the spheres overlap.
    template <bool kPeriodic>
    [[gnu::always_inline]] static inline bool separation(uint32_t i, uint32_t j, const Vec3* __restrict x,
                                                         const double* __restrict r, const MinimumImage& img,
                                                         double& dx, double& dy, double& dz, double& d2) {
        dx = x[i].x - x[j].x;
        dy = x[i].y - x[j].y;
        dz = x[i].z - x[j].z;
        if constexpr (kPeriodic) img.apply(dx, dy, dz);
        const double rs = r[i] + r[j];
        d2 = dx * dx + dy * dy + dz * dz;
        return d2 < rs * rs;
    }

    /// 1 if some history entry is != 0.0 (as the floating-point test: +-0 clean, NaN dirty), on the
    /// bits. The history of a pair that is not touching is reset only if dirty, so that the cache
    /// lines of near-miss pairs stay clean.
    static inline unsigned dirtyHistory(const double* h) {
        uint64_t bits = 0;
        for (int q = 0; q < H; ++q) bits |= std::bit_cast<uint64_t>(h[q]);
        return (bits << 1) != 0 ? 1u : 0u;
    }

    /// The law for one pair in contact (separation dx, dy, dz, squared distance d2). Records are a
    /// run-time branch on purpose: a separate no-record instantiation would let the compiler fuse
    /// multiply-adds differently (the energy shares products with the force), so forces would
    /// depend on whether the step writes output.
    template <bool kPeriodic>
    [[gnu::always_inline]] static inline void contact(std::size_t k, uint32_t i, uint32_t j, double dx, double dy, double dz, double d2,
                               const Vec3* __restrict x, const Vec3* __restrict v, const Vec3* __restrict w,
                               const double* __restrict r, const double* __restrict invM,
                               const double* __restrict m, const int32_t* __restrict sp, Vec3* __restrict f,
                               Vec3* __restrict t, double* __restrict hist, const MinimumImage& img,
                               const SpeciesTable& spt, double dt, double time, std::vector<ContactRecord>* rec,
                               double& energy) {
        (void)m;
        (void)invM;
        const double rs = r[i] + r[j];
        double* h = hist + k * H;
        const double dist = std::sqrt(d2);
        const double inv = 1.0 / dist;
        ContactState st;
        st.n = {dx * inv, dy * inv, dz * inv};
        st.overlap = rs - dist;
        Vec3 vrel = v[i] - v[j];
        if constexpr (kPeriodic) {
            if (img.flow) {  // partner seen through a boundary that moves: its image moves with it
                Vec3 u;
                img.imageVelocity(x[i].x - x[j].x, x[i].y - x[j].y, x[i].z - x[j].z, u.x, u.y, u.z);
                vrel -= u;
            }
        }
        if (img.affine) img.addAffine(dx, dy, dz, vrel.x, vrel.y, vrel.z);  // remapped axes: the affine flow
        st.overlapRate = -dot(vrel, st.n);
        st.dt = dt;
        st.time = time;
        const double ai = r[i] - 0.5 * st.overlap, aj = r[j] - 0.5 * st.overlap;
        if constexpr (kNeedsMass) {
            const double sumInv = invM[i] + invM[j];
            st.mEff = sumInv > 0 ? 1.0 / sumInv : reducedMass(m[i], m[j]);
        }
        if constexpr (kNeedsRadius) st.rEff = r[i] * r[j] / rs;
        if constexpr (kTangential) {
            const Vec3 vc = vrel - cross(ai * w[i] + aj * w[j], st.n);
            st.vt = vc - dot(vc, st.n) * st.n;
            st.wRel = w[i] - w[j];
        }
        const ContactParameters& p = spt.size() == 1 ? spt.pair(0, 0) : spt.pair(sp[i], sp[j]);
        ContactOutput o;
        eval(p, st, h, o);
        const Vec3 F = o.fn * st.n + o.ft;
        f[i] += F;
        f[j] -= F;
        if constexpr (kTangential) {
            const Vec3 nxft = cross(st.n, o.ft);
            t[i] += o.torqueRT - ai * nxft;
            t[j] -= o.torqueRT + aj * nxft;
        }
        if (rec) {
            energy += o.energy;
            ContactRecord cr;
            cr.i = static_cast<int>(i);
            cr.j = static_cast<int>(j);
            cr.point = x[i] - ai * st.n;
            cr.overlap = st.overlap;
            cr.n = st.n;
            cr.fn = o.fn;
            cr.ft = o.ft;
            cr.branch = {dx, dy, dz};
            cr.sliding = o.sliding;
            cr.energy = o.energy;
            rec->push_back(cr);
        }
    }

    void computePairForces(ForceContext& c) const override {
        ParticleData& P = c.particles;
        NeighbourList& nl = c.neighbours;
        const MinimumImage img(c.box);
        const bool periodic = img.p[0] || img.p[1] || img.p[2];
        for (std::size_t ph = 0; ph < nl.phases.size(); ++ph) {
            const std::vector<int>& phase = nl.phases[ph];
#pragma omp parallel
            {
#ifdef _OPENMP
            const auto [qa, qb] = nl.threadSlabs(ph, omp_get_thread_num(), omp_get_num_threads());
#else
            const auto [qa, qb] = nl.threadSlabs(ph, 0, 1);
#endif
            for (int q = qa; q < qb; ++q) {
                const int s = phase[q];
                double energy = 0;
                std::vector<ContactRecord>* rec = c.record ? &(*c.records)[s] : nullptr;
                if (rec) rec->clear();
                (periodic ? pairRange<true> : pairRange<false>)(
                    nl.slabStart[s], nl.slabStart[s + 1], nl.pairI.data(), nl.pairJ.data(), P.x.data(), c.velocity,
                    c.angularVelocity, P.r.data(), P.invM.data(), P.m.data(), P.species.data(), P.f.data(), P.t.data(),
                    nl.history.data(), img, c.species, c.dt, c.time, rec, energy);
                if (rec) (*c.energy)[s] = energy;
            }
            }
        }
    }

    void computeWallForces(ForceContext& c) const override {
        if constexpr (kOneMu) Flagged::wallForces(c);  // walls keep the flagged form (see kOneMuForm)
        else wallForces(c);
    }

    /// Forces of the wall contacts (scalar law, wall histories of H doubles).
    static void wallForces(ForceContext& c) {
        ParticleData& P = c.particles;
        NeighbourList& nl = c.neighbours;
        const std::size_t nw = c.walls.size();
        std::vector<ContactRecord>* rec = c.record ? &c.records->back() : nullptr;
        if (rec) rec->clear();
        double energyTotal = 0;
        for (std::size_t wi = 0; wi < nw; ++wi) {
            const Wall& wall = *c.walls[wi];
            const std::size_t b = nl.wallStart[wi], e = nl.wallStart[wi + 1];
            const long cnt = static_cast<long>(e - b);
            Vec3* wf = c.wallForce->data();
            Vec3* wt = c.wallTorque->data();
            const Vec3 ref = wall.referencePoint();
#pragma omp parallel for schedule(static) if (cnt > 512)
            for (long q = 0; q < cnt; ++q) {
                const std::size_t k = b + q;
                const uint32_t i = nl.wallParticle[k];
                double* h = nl.wallHistory.data() + k * H;
                ContactState st;
                const double dist = wall.distance(P.x[i], st.n);
                st.overlap = P.r[i] - dist;
                if (!(st.overlap > 0)) {
                    if constexpr (H > 0) std::fill_n(h, H, 0.0);
                    wf[k] = {};
                    wt[k] = {};
                    continue;
                }
                const double ai = P.r[i] - 0.5 * st.overlap;
                const Vec3 cp = P.x[i] - ai * st.n;
                const Vec3 vrel = c.velocity[i] - wall.surfaceVelocity(cp);
                st.overlapRate = -dot(vrel, st.n);
                st.dt = c.dt;
                st.time = c.time;
                st.mEff = P.m[i];
                st.rEff = P.r[i];
                if constexpr (kTangential) {
                    const Vec3 vc = vrel - ai * cross(c.angularVelocity[i], st.n);
                    st.vt = vc - dot(vc, st.n) * st.n;
                    st.wRel = c.angularVelocity[i];
                }
                ContactOutput o;
                eval(c.species.pair(P.species[i], wall.species), st, h, o);
                const Vec3 F = o.fn * st.n + o.ft;
                P.f[i] += F;
                if constexpr (kTangential) P.t[i] += o.torqueRT - ai * cross(st.n, o.ft);
                wf[k] = -F;
                wt[k] = cross(cp - ref, -F) - o.torqueRT;
                if (c.record) {
                    (*c.wallEnergy)[k] = o.energy;
                    (*c.wallSliding)[k] = o.sliding ? 1 : 0;
                }
            }
            // Wall reactions and records, in list order (deterministic).
            Vec3 fsum, tsum;
            for (std::size_t k = b; k < e; ++k) {
                fsum += wf[k];
                tsum += wt[k];
            }
            c.walls[wi]->force = fsum;
            c.walls[wi]->torque = tsum;
            if (rec) {
                for (std::size_t k = b; k < e; ++k) {
                    if (wf[k] == Vec3{}) continue;
                    const uint32_t i = nl.wallParticle[k];
                    ContactRecord cr;
                    Vec3 n;
                    const double dist = wall.distance(P.x[i], n);
                    cr.i = static_cast<int>(i);
                    cr.j = -1 - static_cast<int>(wi);
                    cr.overlap = P.r[i] - dist;
                    cr.n = n;
                    cr.point = P.x[i] - (P.r[i] - 0.5 * cr.overlap) * n;
                    const Vec3 F = -wf[k];
                    cr.fn = dot(F, n);
                    cr.ft = F - cr.fn * n;
                    cr.branch = P.x[i] - cr.point;
                    cr.sliding = (*c.wallSliding)[k] != 0;
                    cr.energy = (*c.wallEnergy)[k];
                    energyTotal += cr.energy;
                    rec->push_back(cr);
                }
            }
        }
        if (c.record) c.energy->back() = energyTotal;
    }

private:
    std::string name_;
};

} // namespace pdpm
