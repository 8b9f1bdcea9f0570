// Exact text round-trip of doubles (shortest representation that reads back bit-identically),
// used by restart files so that a restarted run is bitwise identical to an uninterrupted one.
#pragma once
#include <iosfwd>
#include <string>

#include "Math/Vec3.h"

namespace pdpm {

/// Shortest decimal text that parses back to exactly x (std::to_chars); "nan"/"inf" for non-finite.
std::string fmt(double x);
/// Three numbers separated by spaces.
std::string fmt(const Vec3& v);
/// Read one double written by fmt(); sets failbit on malformed text.
double readDouble(std::istream& is);
Vec3 readVec3(std::istream& is);
/// Parse a whole string as a finite double; false if it is not one.
bool parseDouble(const std::string& text, double& out);

} // namespace pdpm
