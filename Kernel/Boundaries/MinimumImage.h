// Minimum-image separation for the hot loops: the box geometry copied into plain locals (so the
// compiler need not reload it after every store), one rounding instruction per periodic axis
// where SSE4.1 is available, two compares otherwise. Valid for separations under 1.5 box lengths.
#pragma once
#include <cmath>

#include "Boundaries/PeriodicBox.h"

namespace pdpm {

struct MinimumImage {
    bool p[3];
    bool flow = false;    ///< some periodic axis moves without remapping (PeriodicBox::setFlowRate)
    bool affine = false;  ///< some axis is remapped with the box (PeriodicBox::setAffineRate)
    double len[3], half[3], inv[3], rate[3], strain[3];

    explicit MinimumImage(const PeriodicBox& b) {
        for (int a = 0; a < 3; ++a) {
            p[a] = b.periodic(a);
            len[a] = b.length()[a];
            half[a] = 0.5 * len[a];
            inv[a] = 1.0 / len[a];
            rate[a] = p[a] ? b.flowRate(a) : 0.0;
            strain[a] = b.affineRate(a);
        }
        flow = b.flowing();
        affine = b.affine();
    }
    /// Number of box lengths k that apply() subtracts from a raw separation component along axis a
    /// (d' = d - k L): the partner's image sits at x_j + k L.
    inline double shift(double d, int a) const {
#ifdef __SSE4_1__
        return std::nearbyint(d * inv[a]);
#else
        return d > half[a] ? 1.0 : (d < -half[a] ? -1.0 : 0.0);
#endif
    }
    /// Affine part of the relative velocity of a pair at separation (dx, dy, dz) (after apply()), added
    /// to u; call only where `affine`.
    inline void addAffine(double dx, double dy, double dz, double& ux, double& uy, double& uz) const {
        ux += strain[0] * dx;
        uy += strain[1] * dy;
        uz += strain[2] * dz;
    }
    /// Velocity of the image of j relative to j itself, k L' per flowing axis, for the raw separation
    /// x_i - x_j (dx, dy, dz); call only where `flow`.
    inline void imageVelocity(double dx, double dy, double dz, double& ux, double& uy, double& uz) const {
        ux = p[0] ? shift(dx, 0) * rate[0] : 0.0;
        uy = p[1] ? shift(dy, 1) * rate[1] : 0.0;
        uz = p[2] ? shift(dz, 2) * rate[2] : 0.0;
    }
    inline void apply(double& dx, double& dy, double& dz) const {
#ifdef __SSE4_1__
        if (p[0]) dx -= len[0] * std::nearbyint(dx * inv[0]);
        if (p[1]) dy -= len[1] * std::nearbyint(dy * inv[1]);
        if (p[2]) dz -= len[2] * std::nearbyint(dz * inv[2]);
#else
        if (p[0]) { if (dx > half[0]) dx -= len[0]; else if (dx < -half[0]) dx += len[0]; }
        if (p[1]) { if (dy > half[1]) dy -= len[1]; else if (dy < -half[1]) dy += len[1]; }
        if (p[2]) { if (dz > half[2]) dz -= len[2]; else if (dz < -half[2]) dz += len[2]; }
#endif
    }
};

} // namespace pdpm
