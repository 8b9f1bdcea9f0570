#include "Walls/WallMotion.h"

#include <cmath>
#include <istream>
#include <numbers>
#include <ostream>

#include "Core/Error.h"
#include "IO/NumberFormat.h"

namespace pdpm {

WallMotion WallMotion::constantVelocity(const Vec3& v, double tStart) {
    WallMotion m;
    m.kind = Kind::ConstantVelocity;
    m.velocity = v;
    m.t0 = tStart;
    return m;
}

WallMotion WallMotion::cosine(const Vec3& amplitude, double frequency, double tStart) {
    if (!(frequency > 0)) inputError("wall motion: cosine frequency must be > 0");
    WallMotion m;
    m.kind = Kind::Cosine;
    m.amplitude = amplitude;
    m.frequency = frequency;
    m.t0 = tStart;
    return m;
}

WallMotion WallMotion::custom(std::function<Vec3(double)> offset, std::function<Vec3(double)> vel) {
    WallMotion m;
    m.kind = Kind::Custom;
    m.customOffset = std::move(offset);
    m.customVelocity = std::move(vel);
    return m;
}

Vec3 WallMotion::offset(double t) const {
    const double s = t - t0;
    switch (kind) {
    case Kind::Static: return {};
    case Kind::ConstantVelocity: return s > 0 ? velocity * s : Vec3{};
    case Kind::Cosine: {
        if (s <= 0) return {};
        return amplitude * (0.5 * (1 - std::cos(2 * std::numbers::pi * frequency * s)));
    }
    case Kind::Custom: return customOffset ? customOffset(t) : Vec3{};
    case Kind::Hold: return holdOffset;
    }
    return {};
}

Vec3 WallMotion::velocityAt(double t) const {
    const double s = t - t0;
    switch (kind) {
    case Kind::Static: return {};
    case Kind::ConstantVelocity: return s >= 0 ? velocity : Vec3{};
    case Kind::Cosine: {
        if (s <= 0) return {};
        const double w = 2 * std::numbers::pi * frequency;
        return amplitude * (0.5 * w * std::sin(w * s));
    }
    case Kind::Custom: return customVelocity ? customVelocity(t) : Vec3{};
    case Kind::Hold: return {};
    }
    return {};
}

void WallMotion::write(std::ostream& os, const Vec3& currentOffset) const {
    // Custom motions cannot be written: they become Hold at the current offset, and the driver
    // re-attaches them in actionsOnRestart().
    const bool custom = kind == Kind::Custom;
    const int k = static_cast<int>(custom ? Kind::Hold : kind);
    os << k << ' ' << fmt(velocity) << ' ' << fmt(amplitude) << ' ' << fmt(frequency) << ' ' << fmt(t0) << ' '
       << fmt(custom ? currentOffset : holdOffset);
}

WallMotion WallMotion::read(std::istream& is) {
    WallMotion m;
    int k = 0;
    is >> k;
    m.velocity = readVec3(is);
    m.amplitude = readVec3(is);
    m.frequency = readDouble(is);
    m.t0 = readDouble(is);
    m.holdOffset = readVec3(is);
    if (!is || k < 0 || k > 4 || k == 3) inputError("restart: malformed wall motion");
    // every field, used by this kind of motion or not, as the writer writes it: finite
    if (!isFinite(m.velocity) || !isFinite(m.amplitude) || !std::isfinite(m.frequency) || !std::isfinite(m.t0) || !isFinite(m.holdOffset))
        inputError("restart: wall motion with a value that is not a finite number");
    m.kind = static_cast<Kind>(k);
    return m;
}

} // namespace pdpm
