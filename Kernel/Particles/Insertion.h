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

/// Start positions for pouring n spheres: a staggered grid of spacing `spacing` (odd layers shifted
/// by spacing/2 along x and y, so that no sphere sits on top of another) in a column rising from
/// z = 0. Over the square [0, lx]^2 (radius = 0) or, with radius > 0, over the disc of that radius
/// about the z axis, keeping `clearance` from its rim. InputError if no point fits in a layer.
std::vector<Vec3> staggeredColumn(std::size_t n, double spacing, double lx, double radius, double clearance);

} // namespace pdpm
