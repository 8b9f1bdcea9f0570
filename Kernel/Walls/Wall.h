// Walls: rigid surfaces that particles touch with the same contact laws as particles (their own
// species-pair parameters). A wall has a prescribed motion and reports the force and torque it receives.
#pragma once
#include <array>
#include <functional>
#include <iosfwd>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "Math/Vec3.h"
#include "Walls/WallMotion.h"

namespace pdpm {

/// Triangles for drawing walls (VTK output).
struct WallMesh {
    std::vector<Vec3> points;
    std::vector<std::vector<int>> polygons;
};

class Wall {
public:
    virtual ~Wall() = default;
    /// Registered type name (restart files).
    virtual std::string type() const = 0;
    /// Signed distance from point x to the wall surface, positive on the particle side, and the unit
    /// normal pointing from the wall towards x. Returns a large value where the wall does not act.
    virtual double distance(const Vec3& x, Vec3& normal) const = 0;
    /// Velocity of the wall surface at point p (translation, plus rotation for a spinning wall).
    virtual Vec3 surfaceVelocity(const Vec3& p) const;
    /// Drawing for the VTK output, clipped to the box [lo, hi].
    virtual void mesh(const Vec3& lo, const Vec3& hi, WallMesh& out) const = 0;
    /// Write/read the geometry (type-specific part). Motion and species are handled by the base.
    virtual void writeGeometry(std::ostream& os) const = 0;
    virtual void readGeometry(std::istream& is) = 0;

    /// Move to the prescribed position for time t.
    void moveTo(double t);
    const Vec3& offset() const { return offset_; }
    const Vec3& velocity() const { return velocity_; }
    void setMotion(const WallMotion& m) { motion_ = m; }
    const WallMotion& motion() const { return motion_; }
    /// Reference point about which the reported torque is taken.
    virtual Vec3 referencePoint() const = 0;

    int species = 0;
    std::string label;   ///< optional name for output ("piston", "floor", ...)
    Vec3 force;          ///< force received from the particles in the last step (N)
    Vec3 torque;         ///< torque about referencePoint() received in the last step (N m)

    void write(std::ostream& os) const;
    static std::unique_ptr<Wall> read(std::istream& is);
    /// Restart-file registry: adding a wall type touches only its own file.
    using Factory = std::function<std::unique_ptr<Wall>()>;
    static void registerType(const std::string& name, Factory f);

protected:
    Vec3 offset_;    ///< current displacement from the initial geometry
    Vec3 velocity_;  ///< current translational velocity
    WallMotion motion_;
};

/// Infinite plane through `point` with unit normal `normal` pointing into the particle region.
class PlaneWall final : public Wall {
public:
    PlaneWall() = default;
    PlaneWall(const Vec3& point, const Vec3& normal, int speciesIndex = 0);
    std::string type() const override { return "plane"; }
    double distance(const Vec3& x, Vec3& n) const override {
        n = normal_;
        return dot(x - point_ - offset_, normal_);
    }
    void mesh(const Vec3& lo, const Vec3& hi, WallMesh& out) const override;
    void writeGeometry(std::ostream& os) const override;
    void readGeometry(std::istream& is) override;
    Vec3 referencePoint() const override { return point_ + offset_; }
    Vec3 point() const { return point_ + offset_; }
    const Vec3& normal() const { return normal_; }

private:
    Vec3 point_, normal_{0, 0, 1};
};

/// Inside surface of a circular cylinder (moulds, outlets): axis through `base` along unit `axis`,
/// radius R, acting for axial coordinates in [0, length] from `base` (length <= 0: infinite).
/// It may spin about its axis with angular velocity `spin` (rad/s).
class CylinderWall final : public Wall {
public:
    CylinderWall() = default;
    CylinderWall(const Vec3& base, const Vec3& axis, double radius, double length = 0, int speciesIndex = 0);
    std::string type() const override { return "cylinder"; }
    double distance(const Vec3& x, Vec3& n) const override;
    Vec3 surfaceVelocity(const Vec3& p) const override;
    void mesh(const Vec3& lo, const Vec3& hi, WallMesh& out) const override;
    void writeGeometry(std::ostream& os) const override;
    void readGeometry(std::istream& is) override;
    Vec3 referencePoint() const override { return base_ + offset_; }
    double radius() const { return radius_; }
    double length() const { return length_; }
    const Vec3& axis() const { return axis_; }
    double spin = 0;

private:
    Vec3 base_, axis_{0, 0, 1};
    double radius_ = 1, length_ = 0;
};

using WallList = std::vector<std::unique_ptr<Wall>>;

/// Planes forming a box [lo, hi] with inward normals; `faces` selects which of the six faces
/// (order: x-, x+, y-, y+, z-, z+) are created. Returns them in that order.
std::vector<std::unique_ptr<Wall>> makeBoxWalls(const Vec3& lo, const Vec3& hi, int speciesIndex,
                                                const std::array<bool, 6>& faces = {true, true, true, true, true, true});

} // namespace pdpm
