// BoxController: deforms a (periodic) PeriodicBox for element tests (thesis Sec. 2.2.2, 2.3, 3.2.2).
//
// Every axis has an explicit control mode (never a sentinel value):
//   Free        the axis length does not change;
//   Cosine      wall-driven strain, L(t) = L_f + (L_0 - L_f)/2 (1 + cos 2 pi (t - t_0)/T)   (Eq. 2.2 / 3.1);
//               by default only the box moves (particles feel it through the periodic images);
//               with `affine` the particle positions are remapped as well (strain-rate driven cosine);
//   StrainRate  homogeneous true strain rate d ln L/dt = rate, applied affinely to the particle
//               positions and the box every step (Sec. 3.2.2); rate < 0 compresses;
//   Stress      virtual wall of mass m_w along the axis, m_w L'' = (sigma_aa - sigma_goal) A - gamma_w L'
//               (Eq. 3.3, compression positive; A = area normal to the axis); affine remap.
// Independently, particles may swell: dr/dt = g_r r (mass follows the radius, Sec. 3.2.2).
//
// Strain bookkeeping is relative to a reference box (setReference): per-axis true strain
// ln(L/L_0) and engineering strain L/L_0 - 1, both tensile positive (the sign of the thesis'
// strain-rate tensors; its Eq. 2.2/3.2 write the compressive epsilon_zz = 1 - z/z_0 instead, and the
// element tests' CSV columns are compression positive), volumetric true strain ln(V/V_0), and the
// deviatoric strain of Eq. (2.4)/(3.11), which does not depend on the sign.
//
// Call step() once per time step from DPMBase::actionsBeforeTimeStep(), with the time at the start
// of the step; the box is set to its state at t + dt.
#pragma once
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "Math/Vec3.h"

namespace pdpm {

class PeriodicBox;
struct ParticleData;

enum class AxisMode { Free, Cosine, StrainRate, Stress };

/// "free", "cosine", "strain_rate", "stress".
std::string axisModeName(AxisMode m);

struct AxisControl {
    AxisMode mode = AxisMode::Free;
    // Cosine
    double lengthStart = 0;  ///< L_0 (m)
    double lengthFinal = 0;  ///< L_f, the length at t_0 + T/2 (m)
    double period = 0;       ///< T (s)
    double timeStart = 0;    ///< t_0 (s)
    bool affine = false;     ///< remap particle positions too (strain-rate driven cosine)
    // StrainRate
    double rate = 0;         ///< d ln L / dt (1/s)
    // Stress
    double stressGoal = 0;   ///< sigma_goal (Pa, compression positive)
    double wallMass = 0;     ///< m_w (kg)
    double wallDamping = 0;  ///< gamma_w (kg/s)
    double wallVelocity = 0; ///< dL/dt of the virtual wall (state)
};

/// Strain state relative to the reference box.
struct StrainState {
    Vec3 trueStrain;         ///< ln(L_a / L_a0), tensile positive
    Vec3 engineeringStrain;  ///< L_a / L_a0 - 1
    Vec3 rate;               ///< d ln L_a / dt over the last step
    double volumetricTrue = 0;         ///< ln(V/V_0) = sum of true strains (thesis' varepsilon_v)
    double volumetricEngineering = 0;  ///< sum of engineering strains (infinitesimal, tr E)
    double deviatoric = 0;             ///< Eq. (2.4)/(3.11) of the true strains
    double deviatoricEngineering = 0;  ///< Eq. (2.4) of the engineering strains
};

/// Eq. (2.4)/(3.11): sqrt(((a-b)^2 + (b-c)^2 + (c-a)^2) / 2) of the diagonal (= eigenvalues) of a strain tensor.
double deviatoricMagnitude(const Vec3& diag);

class BoxController {
public:
    void setFree(int axis);
    /// Cosine law from lengthStart to lengthFinal over half a period, starting at timeStart.
    void setCosine(int axis, double lengthStart, double lengthFinal, double period, double timeStart,
                   bool affine = false);
    void setStrainRate(int axis, double rate);
    void setStress(int axis, double stressGoal, double wallMass, double wallDamping);
    /// Swelling rate g_r (1/s); 0 switches it off.
    void setSwelling(double rate) { swelling_ = rate; }
    double swelling() const { return swelling_; }
    const AxisControl& axis(int a) const { return axes_.at(static_cast<std::size_t>(a)); }
    AxisMode mode(int a) const { return axis(a).mode; }
    bool needsStress() const;

    /// Length of a Cosine axis at time t (held at L_f after half a period only if the caller stops).
    static double cosineLength(const AxisControl& c, double t);
    /// dL/dt of a Cosine axis at time t (0 before its start).
    static double cosineRate(const AxisControl& c, double t);

    /// Advance the box from t to t + dt. `stressDiag`: current diagonal stress (Pa, compression
    /// positive), needed only by Stress axes. `densityOfSpecies`: needed only with swelling.
    void step(PeriodicBox& box, ParticleData& particles, double t, double dt, const Vec3& stressDiag = {},
              const std::vector<double>& densityOfSpecies = {});

    /// Tell the box how its axes move at time t: dL/dt of each axis that moves without remapping the
    /// particles (wall-driven Cosine axes; PeriodicBox::setFlowRate) and d ln L/dt of each axis whose
    /// particles are remapped (StrainRate, Stress, affine Cosine; PeriodicBox::setAffineRate), zero
    /// elsewhere. step() does it for t + dt; call it after a restart has been read, before forces.
    void applyRates(PeriodicBox& box, double t) const;

    void setReference(const PeriodicBox& box);
    const Vec3& referenceLength() const { return ref_; }
    StrainState strain(const PeriodicBox& box) const;

    /// Key/value state for restart files (mode parameters and wall velocities).
    void save(std::vector<std::pair<std::string, std::string>>& kv, const std::string& prefix = "box_") const;
    void load(const std::vector<std::pair<std::string, std::string>>& kv, const std::string& prefix = "box_");

private:
    std::array<AxisControl, 3> axes_{};
    double swelling_ = 0;
    Vec3 ref_{1, 1, 1};
    Vec3 lastRate_{};
};

} // namespace pdpm
