// Prescribed rigid motion of a wall: an offset of its reference point as a function of time.
#pragma once
#include <functional>
#include <iosfwd>
#include <string>

#include "Math/Vec3.h"

namespace pdpm {

struct WallMotion {
    /// Hold: stays at `holdOffset` (a custom motion read back from a restart file keeps the wall
    /// where it was until the driver re-attaches the motion in actionsOnRestart()).
    enum class Kind { Static, ConstantVelocity, Cosine, Custom, Hold };
    Kind kind = Kind::Static;
    Vec3 velocity;      ///< ConstantVelocity: offset = velocity (t - t0)
    Vec3 amplitude;     ///< Cosine: offset = amplitude (1 - cos(2 pi f (t - t0))) / 2, Eq. (2.2)
    double frequency = 0;
    double t0 = 0;      ///< start time of the motion
    Vec3 holdOffset;    ///< Hold: the fixed offset
    /// Custom: offset(t) and its derivative; not stored in restart files (set again in actionsOnRestart).
    std::function<Vec3(double)> customOffset, customVelocity;

    static WallMotion none() { return {}; }
    static WallMotion constantVelocity(const Vec3& v, double tStart = 0);
    /// Co-sinusoidal law of Eq. (2.2): the wall travels `amplitude` in half a period 1/(2f), then back.
    static WallMotion cosine(const Vec3& amplitude, double frequency, double tStart = 0);
    static WallMotion custom(std::function<Vec3(double)> offset, std::function<Vec3(double)> vel);

    Vec3 offset(double t) const;
    Vec3 velocityAt(double t) const;
    /// Writes the motion; a Custom motion is written as Hold at `currentOffset`.
    void write(std::ostream& os, const Vec3& currentOffset) const;
    static WallMotion read(std::istream& is);
};

} // namespace pdpm
