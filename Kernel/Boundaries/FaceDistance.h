// Distance of a point from the nearest face of a box along one axis, as a fraction of the box length,
// for points anywhere (a point outside [lo, lo + length) is first wrapped back, as a contact point of
// an image contact may lie outside a periodic box). Used by the layer analyses of the tools
// (Tools/Polar/Layers.h, the face ratio of Tools/MicroMacro).
#pragma once
#include <algorithm>
#include <cmath>

namespace pdpm {

/// d / length in [0, 1/2] for a coordinate x of a box [lo, lo + length) along one axis; length > 0.
inline double faceDistanceFraction(double x, double lo, double length) {
    double s = std::fmod(x - lo, length);
    if (s < 0) s += length;
    return std::min(s, length - s) / length;
}

} // namespace pdpm
