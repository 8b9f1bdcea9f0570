// In-situ coarse-graining from a running simulation (no particle files): a small frictional bed
// settles on a floor in a laterally periodic box; the snapshots taken through DPMBase's public
// interface (Tools/Common/InSitu.h) coarse-grain to a density profile that holds the total mass, and
// the floor's reaction equals the bed's weight.
#include <gtest/gtest.h>

#include <cmath>

#include "CoarseGraining.h"
#include "InSitu.h"
#include "Core/DPMBase.h"
#include "Particles/Insertion.h"

using namespace pdpm;

namespace {
class SettlingBed : public DPMBase {
public:
    SettlingBed() : DPMBase("SettlingBed") {
        disableFileOutput();
        setQuiet(true);
        ContactParameters p;
        const auto kg = stiffnessAndDamping(2e-4, 0.3, 0.5 * sphereMass(1e-3, 2000));
        p.k = kg.k;
        p.gamma = kg.gamma;
        p.kt = 2.0 / 7.0 * p.k;
        p.muS = p.muD = 0.5;
        addSpecies("grain", 2000, p);
        setContactLaw("linear");
        setDomain({0, 0, 0}, {0.012, 0.012, 0.03}, true, true, false);
        setGravity({0, 0, -9.81});
        setBackgroundDamping(2e-3, 0);
        addWall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, 0));
        insertOnGrid(*this, uniformRadii(108, 0.9e-3, 1.0e-3, random()), {0, 0, 0}, {0.012, 0.012, 0.03}, 2.2e-3);
        setTimeMax(0.25);
    }
};
} // namespace

TEST(CgInSitu, MassAndFloorLoadFromARunningSimulation) {
    SettlingBed bed;
    bed.solve();
    bed.refreshContacts();
    ASSERT_TRUE(bed.contactsAreCurrent());
    const tools::ParticleSnapshot ps = tools::particleSnapshot(bed);
    const tools::ContactSnapshot cs = tools::contactSnapshot(bed);
    ASSERT_EQ(ps.size(), bed.particles().size());
    ASSERT_FALSE(cs.contacts.empty());

    tools::CgConfig cfg;
    cfg.width = 1e-3;
    cfg.n[2] = 60;  // profile along z, averaged over x and y
    tools::CoarseGrainer cg(cfg);
    cg.add(ps, &cs);
    const tools::CgResult r = cg.result();

    // mass: integral of rho over the column equals the total mass
    const Vec3 L = bed.box().length();
    double mass = 0;
    for (std::size_t k = 0; k < r.rho.size(); ++k) mass += r.rho[k] * L.x * L.y * r.geom.spacing[2];
    EXPECT_NEAR(mass / bed.particles().totalMass(), 1.0, 1e-6);

    // The floor carries the weight: its reaction equals m g (bed at rest, background damping only).
    const double weight = bed.particles().totalMass() * 9.81;
    EXPECT_NEAR(bed.walls()[0]->force.z / -weight, 1.0, 0.02);
}
