#include "Particles/ParticleData.h"

#include <algorithm>
#include <numbers>

namespace pdpm {

double sphereMass(double radius, double density) {
    return 4.0 / 3.0 * std::numbers::pi * radius * radius * radius * density;
}

std::size_t ParticleData::add(const Vec3& pos, double radius, double density, int speciesIndex,
                              const Vec3& vel, const Vec3& angVel, bool isFixed) {
    x.push_back(pos);
    v.push_back(vel);
    w.push_back(angVel);
    f.push_back({});
    t.push_back({});
    r.push_back(radius);
    m.push_back(0.0);
    invM.push_back(0.0);
    species.push_back(speciesIndex);
    fixed.push_back(isFixed ? 1 : 0);
    const std::size_t i = x.size() - 1;
    setRadius(i, radius, density);
    return i;
}

void ParticleData::setRadius(std::size_t i, double radius, double density) {
    r[i] = radius;
    m[i] = sphereMass(radius, density);
    const bool isFixed = fixed[i] != 0;
    invM[i] = isFixed ? 0.0 : 1.0 / m[i];
}

void ParticleData::setFixed(std::size_t i, bool isFixed) {
    fixed[i] = isFixed ? 1 : 0;
    invM[i] = isFixed ? 0.0 : 1.0 / m[i];
    if (isFixed) { v[i] = {}; w[i] = {}; }
}

void ParticleData::clear() {
    x.clear(); v.clear(); w.clear(); f.clear(); t.clear();
    r.clear(); m.clear(); invM.clear(); species.clear(); fixed.clear();
    radiusGrowth = 0;
}

void ParticleData::reserve(std::size_t n) {
    x.reserve(n); v.reserve(n); w.reserve(n); f.reserve(n); t.reserve(n);
    r.reserve(n); m.reserve(n); invM.reserve(n); species.reserve(n); fixed.reserve(n);
}

std::size_t ParticleData::bytes() const {
    return 5 * x.capacity() * sizeof(Vec3) + 3 * r.capacity() * sizeof(double) +
           species.capacity() * sizeof(int32_t) + fixed.capacity();
}

double ParticleData::totalMass() const {
    double s = 0;
    for (double mi : m) s += mi;
    return s;
}
double ParticleData::minRadius() const { return r.empty() ? 0.0 : *std::min_element(r.begin(), r.end()); }
double ParticleData::maxRadius() const { return r.empty() ? 0.0 : *std::max_element(r.begin(), r.end()); }

} // namespace pdpm
