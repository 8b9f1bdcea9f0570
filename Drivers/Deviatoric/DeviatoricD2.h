// DeviatoricD2 (thesis Sec. 2.3.3, Table 2.1): volume-conserving pure shear of a prepared packing with
// the diagonal strain-rate tensor eps_rate (1, 0, -1) (--mode D2) or eps_rate (1/2, 1/2, -1) (--mode D3),
// applied homogeneously (affine remap of the particles, Sec. 3.2.2), up to the deviatoric strain
// --eps_dev_max. --mode triaxial: constant lateral stress on x and y through virtual walls (Eq. 3.3)
// and axial compression at the true strain rate --rate along z up to the axial strain --eps_dev_max.
#pragma once
#include <cmath>

#include "ElementTest.h"

class DeviatoricD2 : public pdpm::ElementTest {
public:
    DeviatoricD2()
        : ElementTest("DeviatoricD2", "Deviatoric (D2, D3) or triaxial element test (thesis Sec. 2.3.3, Table 2.1)") {
        auto& p = parameters();
        p.add("mode", &mode_, "D2", "D2: rates (1, 0, -1); D3: (1/2, 1/2, -1); triaxial: lateral stress, axial strain",
              {"D2", "D3", "triaxial"});
        p.add("rate", &rate_, 5.0, "1/s", "strain-rate amplitude eps_rate of the z axis (compression)", pdpm::Range::positive());
        p.add("eps_dev_max", &epsMax_, 0.3, "-", "deviatoric strain (D2, D3) or axial true strain (triaxial) to reach",
              pdpm::Range::open(0, 2));
        p.add("lateral_from_start", &lateralFromStart_, true,
              "triaxial: keep the lateral stress at the mean lateral stress at the start of the test");
        p.add("lateral_stress", &lateral_, 1e4, "Pa", "triaxial: lateral stress when --lateral_from_start 0",
              pdpm::Range::positive());
        p.add("wall_mass", &wallMass_, 1.0, "-", "triaxial: virtual wall mass in units of the total particle mass",
              pdpm::Range::positive());
        p.setDefault("v_i", "0.70");
    }

protected:
    void addTestStages() override {
        const double factor = mode_ == "D2" ? std::sqrt(3.0) : (mode_ == "D3" ? 1.5 : 1.0);
        addStage({mode_, epsMax_ / (factor * rate_), [this] { begin(); }, Branch::None, true});
    }

private:
    void begin() {
        if (mode_ == "D2") {
            ctrl().setStrainRate(0, rate_);
            ctrl().setFree(1);
        } else if (mode_ == "D3") {
            ctrl().setStrainRate(0, 0.5 * rate_);
            ctrl().setStrainRate(1, 0.5 * rate_);
        } else {
            double goal = lateral_;
            if (lateralFromStart_) {
                refreshContacts();
                // the stress the controller holds (contact + kinetic), so that it starts at its goal
                const pdpm::Vec3 s = stressDiagonalNow();
                goal = 0.5 * (s.x + s.y);
                if (!(goal > 0)) pdpm::inputError("triaxial: the packing carries no lateral stress at the start (below jamming?)");
            }
            const double m = wallMass_ * totalMass();
            for (int a = 0; a < 2; ++a) ctrl().setStress(a, goal, m, wallDampingFor(a, m));
        }
        ctrl().setStrainRate(2, -rate_);
    }

    std::string mode_;
    double rate_ = 0, epsMax_ = 0, lateral_ = 0, wallMass_ = 0;
    bool lateralFromStart_ = true;
};
