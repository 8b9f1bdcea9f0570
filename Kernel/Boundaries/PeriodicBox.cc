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
    Vec3 lo = lo_, hi = hi_;
    lo[axis] = newLo;
    hi[axis] = newHi;
    std::array<bool, 3> set{false, false, false};
    set[axis] = true;
    setAxes(lo, hi, set, set, remap);
}

void PeriodicBox::setAxes(const Vec3& newLo, const Vec3& newHi, const std::array<bool, 3>& set,
                          const std::array<bool, 3>& remapAxis, ParticleData* remap) {
    Vec3 s{1, 1, 1}, oldLo = lo_;
    bool any = false;
    for (int a = 0; a < 3; ++a) {
        if (!set[a]) continue;
        if (!(newHi[a] > newLo[a])) inputError("box: axis length became non-positive");
        s[a] = (newHi[a] - newLo[a]) / (hi_[a] - lo_[a]);
        any = any || (remap && remapAxis[a]);
    }
    if (any) {
        // The affine remap is one pass for all axes (the periodic-box benchmark deforms three axes
        // every step; three serial passes were about 4 % of a two-thread step).
        const bool r0 = set[0] && remapAxis[0], r1 = set[1] && remapAxis[1], r2 = set[2] && remapAxis[2];
        Vec3* x = remap->x.data();
        const long n = static_cast<long>(remap->x.size());
#pragma omp parallel for schedule(static) if (n > 4096)
        for (long i = 0; i < n; ++i) {
            if (r0) x[i][0] = newLo[0] + (x[i][0] - oldLo[0]) * s[0];
            if (r1) x[i][1] = newLo[1] + (x[i][1] - oldLo[1]) * s[1];
            if (r2) x[i][2] = newLo[2] + (x[i][2] - oldLo[2]) * s[2];
        }
    }
    for (int a = 0; a < 3; ++a) {
        if (!set[a]) continue;
        const double oldLen = hi_[a] - lo_[a], newLen = newHi[a] - newLo[a];
        if (periodic_[a]) change_[a] += std::fabs(newLen - oldLen) + std::fabs(newLo[a] - lo_[a]);
        lo_[a] = newLo[a];
        hi_[a] = newHi[a];
    }
    updateCache();
}

void PeriodicBox::scaleAboutCentre(const Vec3& s, ParticleData* remap) {
    Vec3 lo, hi;
    for (int a = 0; a < 3; ++a) {
        const double c = 0.5 * (lo_[a] + hi_[a]);
        const double half = 0.5 * (hi_[a] - lo_[a]) * s[a];
        lo[a] = c - half;
        hi[a] = c + half;
    }
    setAxes(lo, hi, {true, true, true}, {true, true, true}, remap);
}

void PeriodicBox::wrap(Vec3& x) const { (void)wrapWithVelocityShift(x); }

Vec3 PeriodicBox::wrapWithVelocityShift(Vec3& x) const {
    Vec3 dv{};
    for (int a = 0; a < 3; ++a) {
        if (!periodic_[a]) continue;
        double& c = x[a];
        if (c < lo_[a] || c >= hi_[a]) {
            const double k = std::floor((c - lo_[a]) / len_[a]);
            c -= len_[a] * k;
            double shifts = k;
            if (c >= hi_[a]) {  // guard against round-off
                c -= len_[a];
                shifts += 1;
            }
            if (c < lo_[a]) c = lo_[a];
            dv[a] = -shifts * flow_[a];
        }
    }
    return dv;
}

void PeriodicBox::setFlowRate(int axis, double rate) {
    if (axis < 0 || axis > 2 || !std::isfinite(rate)) inputError("box: flow rate needs an axis 0..2 and a finite rate");
    flow_[axis] = rate;
}

void PeriodicBox::setAffineRate(int axis, double rate) {
    if (axis < 0 || axis > 2 || !std::isfinite(rate)) inputError("box: affine rate needs an axis 0..2 and a finite rate");
    affine_[axis] = rate;
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
    if (!is || tag != "box" || !std::isfinite(c0) || !std::isfinite(c1) || !std::isfinite(c2))
        inputError("restart: malformed box record");  // set() checks the bounds
    set(lo, hi, p[0], p[1], p[2]);
    change_ = {c0, c1, c2};
}

} // namespace pdpm
