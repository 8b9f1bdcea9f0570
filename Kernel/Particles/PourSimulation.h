// Pouring simulation for filling a container (mould, canister, bed): the caller adds particles,
// species, walls, gravity and the time step, then calls solve(). Particles fall with a drag
// proportional to their mass, F = -m v / dragTime, so every size falls at the same terminal speed
// g * dragTime (a background damping force -gamma v would let fines fall (r_max/r_min)^3 times more
// slowly than coarse particles and segregate the bed). Once every particle has landed (all speeds
// below landedFraction * terminal speed) the drag time drops to quenchTime, which damps the elastic
// vibration of the formed packing, and the run ends when the kinetic energy is below
// ekRatio * N * m_mean * |g| * d_mean, or at timeLimit. Call pour() (not solve()).
#pragma once
#include "Core/DPMBase.h"

namespace pdpm {

class PourSimulation : public DPMBase {
public:
    explicit PourSimulation(const std::string& name = "Pour");

    double dragTime = 0.1;        ///< s: drag time while falling (terminal speed g * dragTime, about 1 m/s)
    double quenchTime = 0;        ///< s: drag time after landing (0: 20 x the shortest collision time)
    double landedFraction = 0.1;  ///< landed when every speed is below this fraction of the terminal speed
    double ekRatio = 1e-3;        ///< rest: E_k below ekRatio * N m_mean |g| d_mean
    double timeLimit = 10;        ///< s: the pour ends here in any case

    /// Runs the pour to rest (or timeLimit).
    void pour();

    bool landed() const { return landed_; }
    /// Simulated time at which every particle had landed (-1 if never).
    double landingTime() const { return landingTime_; }

protected:
    void actionsBeforeTimeLoop() override;
    void computeAdditionalForces() override;
    void actionsAfterTimeStep() override;
    bool continueSolve() const override;
    /// Progress: 90 % for the fall (time against the fall time of the highest particle at the
    /// terminal speed), 10 % for the quench (log of E_k from landing down to the rest energy).
    double progressFraction() const override;

private:
    double maxSpeed() const;
    bool landed_ = false;
    double landingTime_ = -1, restEnergy_ = 0, quench_ = 0, fallTime_ = 0, landingEnergy_ = 0;
};

} // namespace pdpm
