// The simulation domain: an axis-aligned box [lo, hi], periodic along any subset of x, y, z.
// The box may deform every step (element tests drive it); the neighbour list is told how much
// each periodic length changed since its last build, so images stay correct.
#pragma once
#include <array>
#include <iosfwd>

#include "Math/Vec3.h"

namespace pdpm {

struct ParticleData;

class PeriodicBox {
public:
    void set(const Vec3& lo, const Vec3& hi, bool px, bool py, bool pz);
    const Vec3& lo() const { return lo_; }
    const Vec3& hi() const { return hi_; }
    Vec3 length() const { return hi_ - lo_; }
    bool periodic(int axis) const { return periodic_[axis]; }
    bool anyPeriodic() const { return periodic_[0] || periodic_[1] || periodic_[2]; }
    double volume() const { const Vec3 l = length(); return l.x * l.y * l.z; }

    /// Move the bounds of one axis to [newLo, newHi]. With `remap`, particle positions along that
    /// axis are mapped affinely from the old to the new interval (velocities are not changed).
    void setAxis(int axis, double newLo, double newHi, ParticleData* remap = nullptr);
    /// Scale every axis about the box centre by factors s (affine remap of particles if given).
    void scaleAboutCentre(const Vec3& s, ParticleData* remap = nullptr);
    /// setAxis for every axis with set[a], in one (parallel) pass over the particles; positions are
    /// remapped along the axes with remapAxis[a] when `remap` is given. Per component the same
    /// arithmetic as setAxis, so the result does not depend on the number of threads.
    void setAxes(const Vec3& newLo, const Vec3& newHi, const std::array<bool, 3>& set,
                 const std::array<bool, 3>& remapAxis, ParticleData* remap);

    /// Replace a separation vector by its minimum image along periodic axes. Valid for separations
    /// shorter than 1.5 box lengths (particles are wrapped at every neighbour-list build).
    inline void minimumImage(Vec3& d) const {
        for (int a = 0; a < 3; ++a) {
            if (!periodic_[a]) continue;
            double& c = d[a];
            if (c > half_[a]) c -= len_[a];
            else if (c < -half_[a]) c += len_[a];
        }
    }
    /// Wrap a position into [lo, hi) along periodic axes.
    void wrap(Vec3& x) const;
    /// wrap(x), and the change of velocity that goes with it: a particle moved by -k L along a
    /// flowing axis becomes the image whose velocity is v - k L' (see setFlowRate).
    Vec3 wrapWithVelocityShift(Vec3& x) const;

    /// dL/dt of a periodic axis whose length changes without remapping the particle positions (a
    /// wall-driven deformation): the image of a particle shifted by k box lengths then moves with
    /// v + k L'. The contact loops add this to the velocity of an image partner, and wrapping shifts
    /// the velocity of a particle that crosses the boundary. Zero on axes whose particles are
    /// remapped (their velocities are relative to the affine flow already). Set every step by the
    /// driver of the deformation (BoxController); not part of the restart record.
    void setFlowRate(int axis, double rate);
    double flowRate(int axis) const { return flow_[axis]; }
    /// True if some periodic axis has a non-zero flow rate.
    bool flowing() const { return (periodic_[0] && flow_[0] != 0) || (periodic_[1] && flow_[1] != 0) ||
                                  (periodic_[2] && flow_[2] != 0); }
    /// d ln L/dt of an axis whose particle positions are remapped affinely with the box (strain-rate,
    /// stress and affine cosine control): the particles move with v + rate (x - c) along it, v being
    /// the velocity relative to that affine field. The contact loops add rate * (x_i - x_j) to the
    /// relative velocity of every pair, so that dashpots and tangential springs see the deformation
    /// too, as they do with wall-driven axes. Set every step by BoxController; not in the restart record.
    void setAffineRate(int axis, double rate);
    double affineRate(int axis) const { return affine_[axis]; }
    bool affine() const { return affine_[0] != 0 || affine_[1] != 0 || affine_[2] != 0; }

    /// Sum of |change| of each periodic length since the last call of resetChange().
    double lengthChange(int axis) const { return change_[axis]; }
    void resetChange() { change_ = {0, 0, 0}; }
    void write(std::ostream& os) const;
    void read(std::istream& is);

private:
    void updateCache();
    Vec3 lo_{0, 0, 0}, hi_{1, 1, 1};
    std::array<bool, 3> periodic_{false, false, false};
    std::array<double, 3> len_{1, 1, 1}, half_{0.5, 0.5, 0.5};
    std::array<double, 3> change_{0, 0, 0};
    std::array<double, 3> flow_{0, 0, 0}, affine_{0, 0, 0};
};

} // namespace pdpm
