// Bad-input probe: a small driver whose set-up uses registered parameters without range checks of its
// own, so that the kernel's validation is what refuses bad values. BadInputProbe.sh runs it with every
// refused case (exit code 2, one-line message naming the parameter). Without arguments it runs a short
// valid simulation (two spheres colliding head-on next to a floor) and exits 0.
//
// Test helper mode:  BadInputProbe --rehash FILE   recomputes the checksum line of an edited restart
// file (IO/RestartSeal.h), so that the version and program checks behind the checksum can be reached.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>

#include "Contacts/ContactParameters.h"
#include "Core/DPMBase.h"
#include "IO/RestartSeal.h"
#include "Walls/Wall.h"

using namespace pdpm;

namespace {

class BadInputProbe : public DPMBase {
public:
    BadInputProbe() : DPMBase("BadInputProbe", "probe of the kernel's input validation") {
        auto& P = parameters();
        P.add("radius", &radius_, 1e-3, "m", "particle radius");
        P.add("density", &density_, 2000.0, "kg/m^3", "particle density");
        P.add("stiffness", &stiffness_, 1e3, "N/m", "normal stiffness k (sets t_c = pi sqrt(m*/k))");
        P.add("restitution", &restitution_, 0.8, "-", "restitution coefficient e");
        P.add("mu", &mu_, 0.5, "-", "sliding friction coefficient");
        P.add("phi_f", &phiF_, 0.05, "-", "plasticity depth (luding)");
        P.add("k1", &k1_, 500.0, "N/m", "loading stiffness (luding)");
        P.add("kc", &kc_, 0.0, "N/m", "adhesive stiffness (luding)");
        P.add("gap", &gap_, 1e-4, "m", "initial surface gap between the two spheres (negative: overlap)");
        P.add("nan_step", &nanStep_, -1L, "-", "make particle 1's velocity NaN after this step (-1: never)");
        P.set("time_max", "0.002");
        P.set("vtk", "0");
    }

protected:
    void setupInitialConditions() override {
        ContactParameters p;
        const double m = 4.0 / 3.0 * std::numbers::pi * radius_ * radius_ * radius_ * density_;
        if (stiffness_ > 0 && m > 0) {
            // the kernel's conversion validates e; k and gamma give t_c = pi sqrt(m*/k_given), restitution e
            const StiffnessDamping sd = stiffnessAndDamping(std::numbers::pi * std::sqrt(0.5 * m / stiffness_),
                                                            restitution_, 0.5 * m);
            p.k = sd.k;
            p.gamma = sd.gamma;
        } else {
            p.k = stiffness_;
        }
        p.kt = 2.0 / 7.0 * p.k;
        p.muS = p.muD = mu_;
        p.k1 = k1_;
        p.kc = kc_;
        p.phiF = phiF_;
        p.youngEff = 1e8;
        p.shearEff = 4e7;
        p.restitution = restitution_;
        addSpecies("grain", density_, p);
        const double r = radius_;
        setDomain({-0.01, -0.01, 0}, {0.01, 0.01, 0.01}, false, false, false);
        addWall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, 0));
        addParticle({-r - 0.5 * gap_, 0, 2 * r}, r, 0, {0.05, 0, 0});
        addParticle({r + 0.5 * gap_, 0, 2 * r}, r, 0, {-0.05, 0, 0});
        setGravity({0, 0, -9.81});
    }
    void actionsAfterTimeStep() override {
        if (step() == nanStep_) particles().v[1].x = std::numeric_limits<double>::quiet_NaN();
    }

private:
    double radius_ = 0, density_ = 0, stiffness_ = 0, restitution_ = 0, mu_ = 0, phiF_ = 0, k1_ = 0, kc_ = 0, gap_ = 0;
    long nanStep_ = -1;
};

int rehash(const char* path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string sealed = pdpm::resealRestartText(ss.str());
    if (!in || sealed.empty()) return 1;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << sealed;
    return out ? 0 : 1;
}

} // namespace

int main(int argc, char** argv) {
    if (argc == 3 && std::strcmp(argv[1], "--rehash") == 0) return rehash(argv[2]);
    return BadInputProbe().run(argc, argv);
}
