// Helpers that create particle configurations.
#pragma once
#include <random>
#include <vector>

#include "Math/Vec3.h"

namespace pdpm {

class DPMBase;

/// n radii drawn uniformly in [rMin, rMax] (the thesis' polydispersity, Sec. 2.2.2), sorted
/// descending so that insertion places big particles first.
std::vector<double> uniformRadii(std::size_t n, double rMin, double rMax, std::mt19937_64& rng);

/// Insert spheres with the given radii at random non-overlapping positions inside [lo, hi] (periodic
/// axes wrap; along non-periodic axes spheres stay a radius away from the bounds), with random velocities
/// of magnitude up to vMax. Throws InputError if a sphere cannot be placed after many attempts
/// (density too high for random insertion: use a larger box and compress).
void insertRandom(DPMBase& d, const std::vector<double>& radii, const Vec3& lo, const Vec3& hi, double vMax,
                  int species = 0, long maxAttemptsPerParticle = 100000);

/// Insert spheres on a simple-cubic grid of spacing `spacing` starting at lo + spacing/2, filling
/// [lo, hi] row by row until `radii` are used up. Returns the number inserted.
std::size_t insertOnGrid(DPMBase& d, const std::vector<double>& radii, const Vec3& lo, const Vec3& hi, double spacing,
                         int species = 0);

} // namespace pdpm
