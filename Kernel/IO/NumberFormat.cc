#include "IO/NumberFormat.h"

#include <charconv>
#include <cmath>
#include <istream>

namespace pdpm {

std::string fmt(double x) {
    char buf[64];
    auto res = std::to_chars(buf, buf + sizeof(buf), x);
    return std::string(buf, res.ptr);
}

std::string fmt(const Vec3& v) { return fmt(v.x) + ' ' + fmt(v.y) + ' ' + fmt(v.z); }

double readDouble(std::istream& is) {
    std::string tok;
    if (!(is >> tok)) return 0.0;
    double x = 0;
    auto res = std::from_chars(tok.data(), tok.data() + tok.size(), x);
    if (res.ec != std::errc() || res.ptr != tok.data() + tok.size()) {
        is.setstate(std::ios::failbit);
        return 0.0;
    }
    return x;
}

Vec3 readVec3(std::istream& is) {
    Vec3 v;
    v.x = readDouble(is);
    v.y = readDouble(is);
    v.z = readDouble(is);
    return v;
}

bool parseDouble(const std::string& text, double& out) {
    if (text.empty()) return false;
    auto res = std::from_chars(text.data(), text.data() + text.size(), out);
    return res.ec == std::errc() && res.ptr == text.data() + text.size() && std::isfinite(out);
}

} // namespace pdpm
