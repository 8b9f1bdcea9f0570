#include "Particles/PourSimulation.h"

#include <algorithm>
#include <cmath>

namespace pdpm {

PourSimulation::PourSimulation(const std::string& name) : DPMBase(name) {
    parameters().set("vtk", "0");
    parameters().set("restart_output", "0");
    parameters().set("ene", "0");
    setProgressLabel("pouring: ");
}

void PourSimulation::actionsBeforeTimeLoop() {
    const ParticleData& P = particles();
    double m = 0, d = 0, zLow = 0, zHigh = 0, vDown = 0;
    for (std::size_t i = 0; i < P.size(); ++i) {
        m += P.m[i];
        d += 2 * P.r[i];
        vDown += -P.v[i].z;
        zLow = i == 0 ? P.x[i].z : std::min(zLow, P.x[i].z);
        zHigh = i == 0 ? P.x[i].z : std::max(zHigh, P.x[i].z);
    }
    // fall of the highest particle to the lowest one's height at the terminal speed, plus twice the
    // lag of the acceleration from the mean initial speed: an upper estimate of the landing time,
    // for the progress line only
    const double n = static_cast<double>(std::max<std::size_t>(P.size(), 1));
    const double vTerminal = std::max(norm(gravity()) * dragTime, 1e-12);
    const double lag = std::clamp(1 - vDown / n / vTerminal, 0.0, 1.0) * dragTime;
    fallTime_ = 2 * lag + (zHigh - zLow) / vTerminal;
    restEnergy_ = ekRatio * m * norm(gravity()) * d / n;  // ekRatio * N * m_mean * g * d_mean
    quench_ = quenchTime > 0 ? quenchTime : 20 * minCollisionTime();
}

void PourSimulation::pour() {
    setTimeMax(time() + timeLimit);
    setSaveEvery(timeLimit);
    solve();
}

void PourSimulation::computeAdditionalForces() {
    ParticleData& P = particles();
    const double tau = landed_ ? quench_ : dragTime;
    const long n = static_cast<long>(P.size());
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) P.f[i] -= (P.m[i] / tau) * P.v[i];
}

double PourSimulation::maxSpeed() const {
    const ParticleData& P = particles();
    double v2 = 0;
    for (std::size_t i = 0; i < P.size(); ++i) v2 = std::max(v2, dot(P.v[i], P.v[i]));
    return std::sqrt(v2);
}

void PourSimulation::actionsAfterTimeStep() {
    // a column released from rest is slower than landedFraction * terminal speed until about
    // landedFraction * dragTime: no landing test before twice that
    if (landed_ || step() % 50 != 0 || time() < 2 * landedFraction * dragTime) return;
    if (maxSpeed() < landedFraction * norm(gravity()) * dragTime) {
        landed_ = true;
        landingTime_ = time();
        landingEnergy_ = kineticEnergy();
    }
}

double PourSimulation::progressFraction() const {
    if (!landed_) return fallTime_ > 0 ? 0.9 * std::min(time() / fallTime_, 1.0) : 0.0;
    const double ek = kineticEnergy();
    if (!(landingEnergy_ > restEnergy_) || !(ek > 0)) return 1;
    return 0.9 + 0.1 * std::clamp(std::log(landingEnergy_ / ek) / std::log(landingEnergy_ / restEnergy_), 0.0, 1.0);
}

bool PourSimulation::continueSolve() const {
    return !landed_ || kineticEnergy() > restEnergy_;
}

} // namespace pdpm
