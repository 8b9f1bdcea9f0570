// Data model of the post-processing tools (PowderDPMTools). The tools never reach into kernel
// internals: a driver hook (in-situ) or the readers in SnapshotIO.h fill these plain structs.
#pragma once
#include "Math/Vec3.h"

#include <cstdint>
#include <string>
#include <vector>

namespace pdpm::tools {

/// Particles at one instant. Arrays are indexed by particle number 0…N-1 (the `id` of the VTU
/// files); x, v, r, m are required, the others may be empty.
struct ParticleSnapshot {
    double time = 0;
    long step = -1;                 ///< -1: unknown
    Vec3 boxLo, boxHi;              ///< the simulation domain (walls clip the CG kernel here)
    bool periodic[3] = {false, false, false};
    std::vector<Vec3> x;            ///< centres (m), wrapped into the box in periodic directions
    std::vector<Vec3> v;            ///< velocities (m/s)
    std::vector<double> r;          ///< radii (m)
    std::vector<double> m;          ///< masses (kg)
    std::vector<int> coordination;  ///< contacts per particle (optional)
    std::vector<int> species;       ///< optional
    std::vector<int> fixed;         ///< optional
    std::vector<Vec3> force;        ///< total contact force (optional)
    std::vector<Vec3> omega;        ///< angular velocity (optional)

    std::size_t size() const { return x.size(); }
    Vec3 boxLength() const { return boxHi - boxLo; }
};

/// One contact as in RUN.fstat (see Documentation/file-formats.md): n points from j to i (from the
/// wall into the particle for wall contacts, j = -1 - wall), fn is the normal force on i along n,
/// ft the tangential force on i, branch = x_i - x_j (minimum image) or x_i - contactPoint for walls.
struct ContactRecord {
    int i = 0, j = 0;
    Vec3 contactPoint, normal, ft, branch;
    double overlap = 0, fn = 0;
    bool sliding = false;

    bool isWallContact() const { return j < 0; }
    /// Total force on particle i.
    Vec3 force() const { return fn * normal + ft; }
};

/// All contacts at one instant (one block of RUN.fstat).
struct ContactSnapshot {
    double time = 0;
    long step = -1;
    Vec3 boxLo, boxHi;
    bool periodic[3] = {false, false, false};
    std::vector<ContactRecord> contacts;
};

} // namespace pdpm::tools
