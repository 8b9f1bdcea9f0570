// Tutorial: spheres dropped into an open box settle under gravity.
// Documentation/writing-a-driver.md shows this file in full and explains it. Two tests keep it
// working: tutorial_settling_column runs it, install_find_package builds a copy of it against an
// installed PowderDPM.
#include <cmath>
#include <iostream>

#include "Core/DPMBase.h"
#include "IO/VtkWriter.h"  // including this header is what turns on RUN.pvd / RUN_NNNN.vtu output
#include "Particles/Insertion.h"
#include "Walls/Wall.h"

using namespace pdpm;

class SettlingColumn : public DPMBase {
public:
    // Each parameter is registered once. That gives it a flag (--particles 500), a line in --help
    // with its unit and allowed range, range checking, and a place in the restart file.
    SettlingColumn() : DPMBase("SettlingColumn", "Tutorial: spheres settle under gravity in an open box") {
        parameters().add("particles", &n_, 1000L, "-", "number of spheres (at most 1e8)", Range::closed(1, 1e8));
        parameters().add("radius", &r_, 1e-3, "m", "mean radius (radii vary by +-10 %)", Range::positive());
        parameters().add("mu", &mu_, 0.5, "-", "sliding friction coefficient", Range::nonNegative());
        parameters().add("restitution", &e_, 0.5, "-", "restitution coefficient", Range::openClosed(0, 1));
        parameters().setDefault("time_max", "0.3");  // new default of a kernel parameter; --time_max wins
    }

protected:
    // Called on a fresh start only; a run continued with --restart reads all of this from the file.
    void setupInitialConditions() override {
        // One material with the default law "linear" (--contact_law). stiffnessAndDamping turns a
        // collision time and a restitution coefficient for the reduced mass of two average spheres
        // into the stiffness k and dashpot gamma of Eq. (2.1).
        const double density = 2500;
        const StiffnessDamping sd = stiffnessAndDamping(5e-4, e_, 0.5 * sphereMass(r_, density));
        ContactParameters p;
        p.k = sd.k;
        p.gamma = sd.gamma;
        p.kt = 2.0 / 7.0 * p.k;  // tangential spring
        p.muS = p.muD = mu_;     // static = dynamic friction
        const int glass = addSpecies("glass", density, p);  // the walls are made of it too

        // An open box 20 radii wide, tall enough that the spheres fill a quarter of it; five walls.
        const Vec3 lo{0, 0, 0}, hi{20 * r_, 20 * r_, 4 * r_ * std::ceil(n_ / 100.0)};
        setDomain(lo, hi, false, false, false);
        // makeBoxWalls returns the faces in the order x-, x+, y-, y+, z-, z+: the floor is wall 4.
        for (auto& w : makeBoxWalls(lo, hi, glass, {true, true, true, true, true, false})) addWall(std::move(w));
        setGravity({0, 0, -9.81});
        // Radii uniform in [0.9 r, 1.1 r], placed at random without overlaps, random velocities
        // up to 0.05 m/s. Both use the driver's random generator (--seed), so runs are repeatable.
        insertRandom(*this, uniformRadii(n_, 0.9 * r_, 1.1 * r_, random()), lo, hi, 0.05, glass);
        // Time step: not set, so the kernel takes t_c/50 of the fastest pair.
    }

    // After the last step: how much of the weight rests on the floor? (The side walls carry the
    // rest through friction.) wall(k).force is the force the particles exert on wall k.
    void actionsAfterSolve() override {
        const double weight = particles().totalMass() * 9.81;
        if (!quiet())
            std::cout << "SettlingColumn: t = " << time() << " s, kinetic energy " << kineticEnergy()
                      << " J, the floor carries " << -100 * wall(4).force.z / weight << " % of the weight\n";
    }

private:
    long n_ = 0;
    double r_ = 0, mu_ = 0, e_ = 0;
};

int main(int argc, char** argv) { return SettlingColumn().run(argc, argv); }
