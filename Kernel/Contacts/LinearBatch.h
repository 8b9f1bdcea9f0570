// The linear visco-elastic normal force (Eq. 2.1) with, optionally, the linear tangential spring +
// dashpot with Coulomb sliding, evaluated for a batch of contacts at once (structure of arrays).
//
// Why: the scalar pair loop is bound by the latency of the square roots and divisions of one
// contact (unit normal, spring projection, Coulomb cap), a long dependent chain. Evaluated lane by
// lane over a batch, the same arithmetic runs in SIMD registers and the latency overlaps. The
// formulas are those of NormalLinear and TangentialCoulomb (NormalLaws.h, TangentialLaws.h), with
// their branches written as selects; Testing/Unit/ContactBatchTest.cc checks the two against each
// other for random contacts, including sliding, sticking, zero springs and separating contacts.
//
// Determinism: every contact of a run goes through this same vector loop (the batch is padded with
// harmless dummy lanes to a multiple of kPad, so no scalar remainder loop runs), hence a contact's
// result never depends on its position in the batch, on the chunking or on the thread count.
// Last-bit differences to the scalar law are possible (the compiler may fuse multiply-adds
// differently), which is why the scalar law is not used for any pair of a law that has this path.
#pragma once
#include <cmath>
#include <cstddef>

#include "Contacts/ContactParameters.h"

namespace pdpm {

struct LinearBatch {
    static constexpr std::size_t kChunk = 64;  ///< contacts per batch
    static constexpr std::size_t kPad = 8;     ///< batch length is padded to a multiple of this
    static_assert(kChunk % kPad == 0, "a padded batch must fit into the lanes");
    static constexpr std::size_t kMax = kChunk;  ///< lanes per array (sizeof(LinearBatch) = 22.5 kB)

    // ---- input per contact
    alignas(64) double dx[kMax], dy[kMax], dz[kMax], d2[kMax];  ///< x_i - x_j (minimum image), |.|^2
    alignas(64) double ri[kMax], rj[kMax];                      ///< radii
    alignas(64) double vx[kMax], vy[kMax], vz[kMax];            ///< v_i - v_j (+ the box's flow terms)
    alignas(64) double wix[kMax], wiy[kMax], wiz[kMax];         ///< angular velocities
    alignas(64) double wjx[kMax], wjy[kMax], wjz[kMax];
    alignas(64) double h0[kMax], h1[kMax], h2[kMax], h3[kMax];  ///< spring, sliding flag (in/out; h3 unused without the flag)
    alignas(64) double k[kMax], gamma[kMax];                    ///< normal parameters
    alignas(64) double kt[kMax], gammaT[kMax], muS[kMax], muD[kMax]; ///< tangential parameters
    // ---- output per contact
    alignas(64) double nx[kMax], ny[kMax], nz[kMax], overlap[kMax];
    alignas(64) double fn[kMax], ftx[kMax], fty[kMax], ftz[kMax];  ///< normal force, tangential force on i
    alignas(64) double Fx[kMax], Fy[kMax], Fz[kMax];             ///< total force on i (on j: -F)
    alignas(64) double tix[kMax], tiy[kMax], tiz[kMax];          ///< torque on i from ft
    alignas(64) double tjx[kMax], tjy[kMax], tjz[kMax];          ///< torque on j from ft
    alignas(64) double energy[kMax], sliding[kMax];

    /// The law's parameters of lane q.
    template <bool kFriction>
    void setParameters(std::size_t q, const ContactParameters& p) {
        k[q] = p.k;
        gamma[q] = p.gamma;
        if constexpr (kFriction) {
            kt[q] = p.kt;
            gammaT[q] = p.gammaT;
            muS[q] = p.muS;
            muD[q] = p.muD;
        }
    }

    /// Fill lanes [n, padded(n)) with a harmless contact (unit overlap, zero velocities and history;
    /// parameters too if `params`, else those in place are kept) and return padded(n).
    std::size_t pad(std::size_t n, bool friction, bool params) {
        const std::size_t m = (n + kPad - 1) / kPad * kPad;
        for (std::size_t q = n; q < m; ++q) {
            dx[q] = 1.0; dy[q] = 0.0; dz[q] = 0.0; d2[q] = 1.0;
            ri[q] = 1.0; rj[q] = 1.0;
            vx[q] = vy[q] = vz[q] = 0.0;
            if (params) { k[q] = 1.0; gamma[q] = 0.0; }
            if (friction) {
                wix[q] = wiy[q] = wiz[q] = wjx[q] = wjy[q] = wjz[q] = 0.0;
                h0[q] = h1[q] = h2[q] = h3[q] = 0.0;
                if (params) { kt[q] = 1.0; gammaT[q] = 0.0; muS[q] = 1.0; muD[q] = 1.0; }
            }
        }
        return m;
    }

    /// Evaluate lanes [0, m), m a multiple of kPad (see pad()). kFlag = false: no sliding flag (h3 is
    /// neither read nor written; the pairs have mu_s = mu_d, TangentialCoulombOneMu).
    template <bool kFriction, bool kFlag = true>
    [[gnu::noinline]] void evaluate(std::size_t m, double dt) {
#pragma omp simd
        for (std::size_t q = 0; q < m; ++q) {
            const double dist = std::sqrt(d2[q]);
            const double inv = 1.0 / dist;
            const double ex = dx[q] * inv, ey = dy[q] * inv, ez = dz[q] * inv;
            const double ov = (ri[q] + rj[q]) - dist;
            const double rate = -(vx[q] * ex + vy[q] * ey + vz[q] * ez);
            const double f = k[q] * ov + gamma[q] * rate;  // Eq. 2.1, not clipped
            double e = 0.5 * k[q] * ov * ov;
            nx[q] = ex; ny[q] = ey; nz[q] = ez;
            overlap[q] = ov;
            fn[q] = f;
            if constexpr (kFriction) {
                const double load = f > 0 ? f : 0.0;
                const double a = ri[q] - 0.5 * ov, b = rj[q] - 0.5 * ov;
                // relative velocity at the contact point, tangential part
                const double sx = a * wix[q] + b * wjx[q], sy = a * wiy[q] + b * wjy[q], sz = a * wiz[q] + b * wjz[q];
                const double cx = vx[q] - (sy * ez - sz * ey);
                const double cy = vy[q] - (sz * ex - sx * ez);
                const double cz = vz[q] - (sx * ey - sy * ex);
                const double cn = cx * ex + cy * ey + cz * ez;
                const double tx = cx - cn * ex, ty = cy - cn * ey, tz = cz - cn * ez;
                // spring rotated into the current tangent plane, keeping its length
                const double len2 = h0[q] * h0[q] + h1[q] * h1[q] + h2[q] * h2[q];
                const double hn = h0[q] * ex + h1[q] * ey + h2[q] * ez;
                double px = h0[q] - hn * ex, py = h1[q] - hn * ey, pz = h2[q] - hn * ez;
                const double p2 = px * px + py * py + pz * pz;
                // (every operation runs unconditionally and only the results are selected, so the
                // loop has no control flow; the safe denominators keep the unused lanes finite)
                const double rootScale = std::sqrt(len2 / (p2 > 0 ? p2 : 1.0));
                const double scale = p2 > 0 ? rootScale : 1.0;
                px = px * scale + tx * dt;
                py = py * scale + ty * dt;
                pz = pz * scale + tz * dt;
                // trial force and Coulomb cap (static limit while sticking, dynamic while sliding)
                double fx = -kt[q] * px - gammaT[q] * tx;
                double fy = -kt[q] * py - gammaT[q] * ty;
                double fz = -kt[q] * pz - gammaT[q] * tz;
                const double md = muD[q], ms = muS[q];
                double limit = ms * load;
                if constexpr (kFlag) limit = (h3[q] != 0 ? md : ms) * load;
                const double f2 = fx * fx + fy * fy + fz * fz;
                const bool capped = f2 > limit * limit;
                const double fm = std::sqrt(f2 > 0 ? f2 : 1.0);
                const double capRatio = muD[q] * load / fm;
                const double capScale = capped ? capRatio : 1.0;
                fx *= capScale; fy *= capScale; fz *= capScale;
                const bool respring = capped && kt[q] > 0;
                const double ktSafe = kt[q] > 0 ? kt[q] : 1.0;
                const double qx = -(fx + gammaT[q] * tx) / ktSafe;
                const double qy = -(fy + gammaT[q] * ty) / ktSafe;
                const double qz = -(fz + gammaT[q] * tz) / ktSafe;
                px = respring ? qx : px;
                py = respring ? qy : py;
                pz = respring ? qz : pz;
                h0[q] = px; h1[q] = py; h2[q] = pz;
                if constexpr (kFlag) h3[q] = capped ? 1.0 : 0.0;
                sliding[q] = capped ? 1.0 : 0.0;
                e += 0.5 * kt[q] * (px * px + py * py + pz * pz);
                ftx[q] = fx; fty[q] = fy; ftz[q] = fz;
                Fx[q] = f * ex + fx; Fy[q] = f * ey + fy; Fz[q] = f * ez + fz;
                // lever-arm torques: on i -a n x ft, on j -b n x ft
                const double mx = ey * fz - ez * fy, my = ez * fx - ex * fz, mz = ex * fy - ey * fx;
                tix[q] = -(a * mx); tiy[q] = -(a * my); tiz[q] = -(a * mz);
                tjx[q] = -(b * mx); tjy[q] = -(b * my); tjz[q] = -(b * mz);
            } else {
                Fx[q] = f * ex; Fy[q] = f * ey; Fz[q] = f * ez;
            }
            energy[q] = e;
        }
    }
};

} // namespace pdpm
