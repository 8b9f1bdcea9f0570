#include "Walls/Wall.h"

#include <cmath>
#include <istream>
#include <numbers>
#include <ostream>

#include "Core/Error.h"
#include "IO/NumberFormat.h"

namespace pdpm {

namespace {
std::map<std::string, Wall::Factory>& registry() {
    static std::map<std::string, Wall::Factory> r = {
        {"plane", [] { return std::make_unique<PlaneWall>(); }},
        {"cylinder", [] { return std::make_unique<CylinderWall>(); }},
    };
    return r;
}
Vec3 unit(const Vec3& v, const char* what) {
    const double l = norm(v);
    if (!(l > 0) || !std::isfinite(l)) inputError(std::string(what) + " must be a non-zero finite vector");
    return v / l;
}
} // namespace

void Wall::registerType(const std::string& name, Factory f) { registry()[name] = std::move(f); }

Vec3 Wall::surfaceVelocity(const Vec3&) const { return velocity_; }

void Wall::moveTo(double t) {
    offset_ = motion_.offset(t);
    velocity_ = motion_.velocityAt(t);
}

void Wall::write(std::ostream& os) const {
    os << type() << ' ' << species << ' ' << (label.empty() ? "-" : label) << ' ';
    writeGeometry(os);
    os << ' ' << fmt(offset_) << ' ' << fmt(velocity_) << ' ';
    motion_.write(os, offset_);
    // the reaction of the last step: drivers read it (e.g. a stress servo) before the next force evaluation
    os << ' ' << fmt(force) << ' ' << fmt(torque);
}

std::unique_ptr<Wall> Wall::read(std::istream& is) {
    std::string t, lab;
    int sp = 0;
    is >> t >> sp >> lab;
    auto it = registry().find(t);
    if (!is || it == registry().end()) inputError("restart: unknown wall type '" + t + "'");
    auto w = it->second();
    w->species = sp;
    w->label = lab == "-" ? "" : lab;
    w->readGeometry(is);
    w->offset_ = readVec3(is);
    w->velocity_ = readVec3(is);
    w->motion_ = WallMotion::read(is);
    w->force = readVec3(is);
    w->torque = readVec3(is);
    // the geometry may hold inf (an infinite cylinder); the motion state and the reaction may not
    if (!is || !isFinite(w->offset_) || !isFinite(w->velocity_) || !isFinite(w->force) || !isFinite(w->torque))
        inputError("restart: malformed wall record of type " + t);
    return w;
}

// ---- PlaneWall -----------------------------------------------------------------------------------
PlaneWall::PlaneWall(const Vec3& point, const Vec3& normal, int speciesIndex)
    : point_(point), normal_(unit(normal, "plane wall normal")) {
    species = speciesIndex;
}

void PlaneWall::writeGeometry(std::ostream& os) const { os << fmt(point_) << ' ' << fmt(normal_); }
void PlaneWall::readGeometry(std::istream& is) {
    point_ = readVec3(is);
    normal_ = readVec3(is);
    // written as a unit vector; an edited file may hold anything
    if (is && (!isFinite(point_) || !isFinite(normal_) || !(std::fabs(norm(normal_) - 1) < 1e-9)))
        inputError("restart: invalid plane wall (point must be finite, normal a unit vector)");
}

void PlaneWall::mesh(const Vec3& lo, const Vec3& hi, WallMesh& out) const {
    // Quad of the plane spanning the box: pick the two axes least aligned with the normal.
    const Vec3 p = point();
    int a = 0;
    for (int k = 1; k < 3; ++k)
        if (std::fabs(normal_[k]) > std::fabs(normal_[a])) a = k;
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const int base = static_cast<int>(out.points.size());
    const double cs[4][2] = {{lo[b], lo[c]}, {hi[b], lo[c]}, {hi[b], hi[c]}, {lo[b], hi[c]}};
    for (auto& q : cs) {
        Vec3 x;
        x[b] = q[0];
        x[c] = q[1];
        // solve n.(x - p) = 0 for x[a]
        x[a] = p[a] - (normal_[b] * (x[b] - p[b]) + normal_[c] * (x[c] - p[c])) / normal_[a];
        out.points.push_back(x);
    }
    out.polygons.push_back({base, base + 1, base + 2, base + 3});
}

// ---- CylinderWall --------------------------------------------------------------------------------
CylinderWall::CylinderWall(const Vec3& base, const Vec3& axis, double radius, double length, int speciesIndex)
    : base_(base), axis_(unit(axis, "cylinder axis")), radius_(radius), length_(length) {
    if (!(radius > 0)) inputError("cylinder wall: radius must be > 0");
    species = speciesIndex;
}

double CylinderWall::distance(const Vec3& x, Vec3& n) const {
    const Vec3 d = x - base_ - offset_;
    const double s = dot(d, axis_);
    if (length_ > 0 && (s < 0 || s > length_)) {
        n = {0, 0, 0};
        return 1e300;
    }
    const Vec3 radial = d - s * axis_;
    const double rho = norm(radial);
    if (rho == 0) {
        n = {0, 0, 0};
        return radius_;
    }
    n = radial * (-1.0 / rho);  // towards the axis
    return radius_ - rho;
}

Vec3 CylinderWall::surfaceVelocity(const Vec3& p) const {
    if (spin == 0) return velocity_;
    const Vec3 d = p - base_ - offset_;
    return velocity_ + cross(spin * axis_, d);
}

void CylinderWall::writeGeometry(std::ostream& os) const {
    os << fmt(base_) << ' ' << fmt(axis_) << ' ' << fmt(radius_) << ' ' << fmt(length_) << ' ' << fmt(spin);
}
void CylinderWall::readGeometry(std::istream& is) {
    base_ = readVec3(is);
    axis_ = readVec3(is);
    radius_ = readDouble(is);
    length_ = readDouble(is);
    spin = readDouble(is);
    if (is && (!isFinite(base_) || !isFinite(axis_) || !(std::fabs(norm(axis_) - 1) < 1e-9) || !(radius_ > 0) ||
               !std::isfinite(radius_) || std::isnan(length_) || !std::isfinite(spin)))
        inputError("restart: invalid cylinder wall (base finite, axis a unit vector, radius > 0, spin finite)");
}

void CylinderWall::mesh(const Vec3& lo, const Vec3& hi, WallMesh& out) const {
    // Axial extent: the finite length, or the box extent along the axis.
    double s0 = 0, s1 = length_;
    if (length_ <= 0) {
        s0 = 1e300; s1 = -1e300;
        for (int c = 0; c < 8; ++c) {
            const Vec3 corner{(c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z};
            const double s = dot(corner - base_ - offset_, axis_);
            s0 = std::min(s0, s);
            s1 = std::max(s1, s);
        }
    }
    Vec3 e1 = std::fabs(axis_.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    e1 = e1 - dot(e1, axis_) * axis_;
    e1 /= norm(e1);
    const Vec3 e2 = cross(axis_, e1);
    const int nSeg = 48;
    const int base = static_cast<int>(out.points.size());
    for (int k = 0; k < nSeg; ++k) {
        const double phi = 2 * std::numbers::pi * k / nSeg;
        const Vec3 rad = radius_ * (std::cos(phi) * e1 + std::sin(phi) * e2);
        out.points.push_back(base_ + offset_ + s0 * axis_ + rad);
        out.points.push_back(base_ + offset_ + s1 * axis_ + rad);
    }
    for (int k = 0; k < nSeg; ++k) {
        const int k2 = (k + 1) % nSeg;
        out.polygons.push_back({base + 2 * k, base + 2 * k2, base + 2 * k2 + 1, base + 2 * k + 1});
    }
}

std::vector<std::unique_ptr<Wall>> makeBoxWalls(const Vec3& lo, const Vec3& hi, int speciesIndex,
                                                const std::array<bool, 6>& faces) {
    std::vector<std::unique_ptr<Wall>> walls;
    for (int a = 0; a < 3; ++a) {
        Vec3 n;
        n[a] = 1;
        if (faces[2 * a]) walls.push_back(std::make_unique<PlaneWall>(lo, n, speciesIndex));
        if (faces[2 * a + 1]) walls.push_back(std::make_unique<PlaneWall>(hi, -n, speciesIndex));
    }
    return walls;
}

} // namespace pdpm
