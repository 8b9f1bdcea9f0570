#include "Boundaries/PeriodicBox.h"

#include <cmath>
#include <istream>
#include <ostream>

#include "IO/NumberFormat.h"

#include "Core/Error.h"
#include "Particles/ParticleData.h"

namespace pdpm {

void PeriodicBox::set(const Vec3& lo, const Vec3& hi, bool px, bool py, bool pz) {
    for (int a = 0; a < 3; ++a)
        if (!(hi[a] > lo[a]) || !std::isfinite(lo[a]) || !std::isfinite(hi[a]))
            inputError("domain: upper bound must exceed lower bound on every axis");
    lo_ = lo;
    hi_ = hi;
    periodic_ = {px, py, pz};
    updateCache();
}

void PeriodicBox::updateCache() {
    for (int a = 0; a < 3; ++a) {
        len_[a] = hi_[a] - lo_[a];
        half_[a] = 0.5 * len_[a];
    }
}

void PeriodicBox::setAxis(int axis, double newLo, double newHi, ParticleData* remap) {
    if (!(newHi > newLo)) inputError("box: axis length became non-positive");
    const double oldLo = lo_[axis], oldLen = hi_[axis] - lo_[axis];
    const double newLen = newHi - newLo;
    if (remap) {
        const double s = newLen / oldLen;
        for (auto& x : remap->x) x[axis] = newLo + (x[axis] - oldLo) * s;
    }
    if (periodic_[axis]) change_[axis] += std::fabs(newLen - oldLen) + std::fabs(newLo - oldLo);
    lo_[axis] = newLo;
    hi_[axis] = newHi;
    updateCache();
}

void PeriodicBox::scaleAboutCentre(const Vec3& s, ParticleData* remap) {
    for (int a = 0; a < 3; ++a) {
        const double c = 0.5 * (lo_[a] + hi_[a]);
        const double half = 0.5 * (hi_[a] - lo_[a]) * s[a];
        setAxis(a, c - half, c + half, remap);
    }
}

void PeriodicBox::wrap(Vec3& x) const {
    for (int a = 0; a < 3; ++a) {
        if (!periodic_[a]) continue;
        double& c = x[a];
        if (c < lo_[a] || c >= hi_[a]) {
            c -= len_[a] * std::floor((c - lo_[a]) / len_[a]);
            if (c >= hi_[a]) c -= len_[a];  // guard against round-off
            if (c < lo_[a]) c = lo_[a];
        }
    }
}

void PeriodicBox::write(std::ostream& os) const {
    os << "box " << fmt(lo_) << ' ' << fmt(hi_) << ' ' << periodic_[0] << ' ' << periodic_[1] << ' ' << periodic_[2]
       << ' ' << fmt(change_[0]) << ' ' << fmt(change_[1]) << ' ' << fmt(change_[2]) << '\n';
}

void PeriodicBox::read(std::istream& is) {
    std::string tag;
    is >> tag;
    const Vec3 lo = readVec3(is), hi = readVec3(is);
    bool p[3];
    is >> p[0] >> p[1] >> p[2];
    const double c0 = readDouble(is), c1 = readDouble(is), c2 = readDouble(is);
    if (!is || tag != "box") inputError("restart: malformed box record");
    set(lo, hi, p[0], p[1], p[2]);
    change_ = {c0, c1, c2};
}

} // namespace pdpm
