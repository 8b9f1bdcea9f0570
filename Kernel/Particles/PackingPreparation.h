// Preparation of dense packings by simulation, for drivers and benchmarks that need a start
// configuration and have none on disk. Each helper runs its own small DPMBase simulation.
#pragma once
#include <cstdint>
#include <vector>

#include "Math/Vec3.h"

namespace pdpm {

struct Packing {
    Vec3 lo, hi;            ///< domain
    std::vector<Vec3> x;    ///< centres
    std::vector<double> r;  ///< radii
};

/// Fully periodic packing of the given radii at volume fraction `targetFraction` (<= 0.72): random
/// gas at 0.2, isotropic compression of frictionless soft spheres with strong background damping
/// to the target, then relaxation. The box is a cube centred on `centre`.
Packing preparePeriodicPacking(const std::vector<double>& radii, double targetFraction, const Vec3& centre,
                               double density, uint64_t seed, bool quiet = true);

/// Bed of the given radii poured into the box [lo, hi] (walls on all sides but the top) under
/// gravity g along -z: particles start on a grid filling the box from the floor up (the box may
/// be extended upwards for them) and settle with damping until nearly at rest.
Packing prepareSettledBed(const std::vector<double>& radii, const Vec3& lo, const Vec3& hi, double density,
                          uint64_t seed, bool quiet = true);

} // namespace pdpm
