// Minimum-image separation for the hot loops: the box geometry copied into plain locals (so the
// compiler need not reload it after every store), one rounding instruction per periodic axis
// where SSE4.1 is available, two compares otherwise. Valid for separations under 1.5 box lengths.
#pragma once
#include <cmath>

#include "Boundaries/PeriodicBox.h"

namespace pdpm {

struct MinimumImage {
    bool p[3];
    double len[3], half[3], inv[3];

    explicit MinimumImage(const PeriodicBox& b) {
        for (int a = 0; a < 3; ++a) {
            p[a] = b.periodic(a);
            len[a] = b.length()[a];
            half[a] = 0.5 * len[a];
            inv[a] = 1.0 / len[a];
        }
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
