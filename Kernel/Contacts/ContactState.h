// The input and output of a contact law evaluation. A contact law is a pure function
//   (parameters, ContactState, history) -> (ContactOutput, new history).
#pragma once
#include "Math/Vec3.h"

namespace pdpm {

/// Geometry and kinematics of one contact, computed by the kernel before the law is called.
struct ContactState {
    Vec3 n;              ///< unit normal, pointing from j (or the wall) to i
    double overlap = 0;  ///< delta > 0
    double overlapRate = 0; ///< d(delta)/dt, positive while approaching
    Vec3 vt;             ///< tangential relative velocity of i w.r.t. j at the contact point
    Vec3 wRel;           ///< relative angular velocity w_i - w_j
    double mEff = 0;     ///< reduced mass
    double rEff = 0;     ///< reduced radius r_i r_j / (r_i + r_j) of the radii, not the lever arms (r_i for a wall)
    double dt = 0;       ///< time step
    double time = 0;     ///< simulation time (for time-dependent laws)
};

/// What a law returns. The force on i is fn*n + ft; the torque on i from rolling and torsion is
/// torqueRT (on j: -torqueRT). The kernel adds the lever-arm torques of ft itself.
struct ContactOutput {
    double fn = 0;         ///< normal force on i along n (positive repulsive)
    double fnFriction = 0; ///< normal load that sets the Coulomb limits (>= 0)
    Vec3 ft;               ///< tangential force on i
    Vec3 torqueRT;         ///< rolling + torsion torque on i
    double energy = 0;     ///< elastic (and adhesive) energy stored in the contact
    bool sliding = false;  ///< tangential force at the Coulomb limit
};

} // namespace pdpm
