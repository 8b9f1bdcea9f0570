// Particle storage: structure-of-arrays, one array per field, indexed 0..N-1.
// The kernel never reorders particles, so an index is a stable particle id for the whole run.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "Math/Vec3.h"

namespace pdpm {

struct ParticleData {
    std::vector<Vec3> x;      ///< position (m)
    std::vector<Vec3> v;      ///< velocity (m/s)
    std::vector<Vec3> w;      ///< angular velocity (rad/s)
    std::vector<Vec3> f;      ///< force accumulated this step (N)
    std::vector<Vec3> t;      ///< torque accumulated this step (N m)
    std::vector<double> r;    ///< radius (m)
    std::vector<double> m;    ///< mass (kg)
    std::vector<double> invM; ///< 1/m, 0 for fixed particles
    std::vector<int32_t> species;
    std::vector<uint8_t> fixed;
    /// Upper bound of the growth of any radius since the start of the run (m), raised by whoever grows
    /// radii during a run (the box controller's swelling); the neighbour list counts the growth since
    /// its last build against its skin, like a displacement. Setting radii up front needs no entry.
    double radiusGrowth = 0;

    std::size_t size() const { return x.size(); }
    bool empty() const { return x.empty(); }

    /// Append one sphere; mass from density. Returns its index.
    std::size_t add(const Vec3& pos, double radius, double density, int speciesIndex,
                    const Vec3& vel = {}, const Vec3& angVel = {}, bool isFixed = false);
    /// 1/I of a free solid sphere, I = 2/5 m r^2 (0 for a fixed particle). Not stored: computed from m and
    /// r where needed (8 B per particle less), with the same expression as before, so the same bits.
    static double inverseInertia(double mass, double radius) { return 1.0 / (0.4 * mass * radius * radius); }
    /// Recompute mass and inverse mass of particle i from radius and density.
    void setRadius(std::size_t i, double radius, double density);
    void setFixed(std::size_t i, bool isFixed);
    void clear();
    void reserve(std::size_t n);
    /// Memory held by the arrays (bytes), for the benchmarks' bytes-per-particle figure.
    std::size_t bytes() const;
    double totalMass() const;
    double minRadius() const;
    double maxRadius() const;
};

/// Mass of a solid sphere.
double sphereMass(double radius, double density);

} // namespace pdpm
