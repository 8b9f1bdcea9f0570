// Self-test: an elastic frictionless gas (linear law, gamma = 0, no background damping, no gravity) of
// 1000 spheres in a fully periodic box at volume fraction 0.2, dt = t_c/50, 1e5 steps.
// Checks: total energy (kinetic + elastic) conserved to 1e-4 relative (at 100 sample points), linear
// momentum conserved to round-off (1e-12 relative to sum m|v|). Exit 0 on success, 1 on failure.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "Contacts/ContactParameters.h"
#include "Core/DPMBase.h"
#include "Particles/Insertion.h"

using namespace pdpm;

namespace {
class ElasticGas : public DPMBase {
public:
    ElasticGas() : DPMBase("EnergyConservationSelfTest") {
        parameters().set("vtk", "0");
        parameters().set("ene", "0");
        parameters().set("restart_output", "0");
        setQuiet(true);
    }
    void setUp() {
        const double r = 1e-3, density = 2000, phi = 0.2;
        const std::size_t n = 1000;
        ContactParameters p;
        p.k = 1e3;
        p.gamma = 0;
        setContactLaw("linear-frictionless");
        addSpecies("gas", density, p);
        const std::vector<double> radii = uniformRadii(n, 0.9 * r, 1.1 * r, random());
        double vs = 0;
        for (double a : radii) vs += 4.0 / 3.0 * std::numbers::pi * a * a * a;
        const double L = std::cbrt(vs / phi);
        setDomain({0, 0, 0}, {L, L, L}, true, true, true);
        // speeds up to 0.25 m/s: max overlap ~ 0.25 sqrt(m*/k) = 1.6 % of r
        insertRandom(*this, radii, {0, 0, 0}, {L, L, L}, 0.25);
        setTimeStep(suggestedTimeStep());
        setTimeMax(1e5 * timeStep());
        setSaveEvery(timeMax());
    }
    Vec3 momentum() const {
        Vec3 s;
        for (std::size_t i = 0; i < particles().size(); ++i) s += particles().m[i] * particles().v[i];
        return s;
    }
    double worstEnergy = 0, worstMomentum = 0, e0_ = 0, scale_ = 0;
    Vec3 p0_;
    long collisions = 0;

protected:
    void actionsBeforeTimeLoop() override {
        // (refreshContacts() needs the neighbour list, which solve() builds first)
        refreshContacts();
        e0_ = kineticEnergy() + elasticEnergy();
        p0_ = momentum();
        scale_ = 0;
        for (std::size_t i = 0; i < particles().size(); ++i) scale_ += particles().m[i] * norm(particles().v[i]);
    }
    void actionsAfterTimeStep() override {
        if (step() % 1000 != 0) return;
        refreshContacts();
        const double e = kineticEnergy() + elasticEnergy();
        worstEnergy = std::max(worstEnergy, std::fabs(e - e0_) / e0_);
        worstMomentum = std::max(worstMomentum, norm(momentum() - p0_) / scale_);
        collisions += static_cast<long>(contacts().size());
    }
};
} // namespace

int main() {
    ElasticGas g;
    g.setUp();
    g.solve();
    std::printf("EnergyConservationSelfTest: %zu spheres, %ld steps, contacts seen at samples %ld\n",
                g.particles().size(), g.step(), g.collisions);
    std::printf("  max |E - E0| / E0 = %.3e (limit 1e-4), max |P - P0| / sum m|v| = %.3e (limit 1e-12)\n",
                g.worstEnergy, g.worstMomentum);
    const bool ok = g.step() == 100000 && g.collisions > 100 && g.worstEnergy < 1e-4 && g.worstMomentum < 1e-12;
    std::printf("%s\n", ok ? "PASS" : "FAIL");
    return ok ? 0 : 1;
}
