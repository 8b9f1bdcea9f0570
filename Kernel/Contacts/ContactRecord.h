// One contact as seen from outside the force loop (output, analysis). Conventions in
// Documentation/file-formats.md: n points from j to i, forces are those on i, j < 0 is wall -1-j.
#pragma once
#include "Math/Vec3.h"

namespace pdpm {

struct ContactRecord {
    int i = 0, j = 0;
    Vec3 point;      ///< contact point
    double overlap = 0;
    Vec3 n;          ///< unit normal from j to i
    double fn = 0;   ///< normal force on i along n
    Vec3 ft;         ///< tangential force on i
    Vec3 branch;     ///< x_i - x_j (minimum image); wall contacts: x_i - contact point
    bool sliding = false;
    double energy = 0;
};

} // namespace pdpm
