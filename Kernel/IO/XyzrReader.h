// Reader of the benchmark start-file format (*.xyzr, ../shared/bench/README.md):
//   '#' header lines, among them "# box xlo xhi ylo yhi zlo zhi"; then "id x y z r" per particle (m).
#pragma once
#include <string>
#include <vector>

#include "Math/Vec3.h"

namespace pdpm {

struct XyzrFile {
    Vec3 lo, hi;
    bool hasBox = false;
    double density = 0;  ///< from "# case NAME N n density RHO" if present, else 0
    std::vector<Vec3> x;
    std::vector<double> r;
};

/// Read a start file; InputError with file:line on malformed content.
XyzrFile readXyzr(const std::string& path);

} // namespace pdpm
