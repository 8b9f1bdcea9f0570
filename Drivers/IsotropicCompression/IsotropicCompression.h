// IsotropicCompression (thesis Sec. 2.3.1 and 3.2.2, Fig. 2.1 / 3.1): the three-step preparation
// (random gas -> isotropic compression to v0 -> relaxation at constant volume), then isotropic
// loading to v_max and unloading back to v0, every axis following the cosine law of Eq. (2.2) over
// one period T. Restart files are written where the volume fraction crosses each of --save_fractions
// on the loading branch (RUN.load_0.700.restart) and on the unloading branch (RUN.unload_0.700.restart);
// UniaxialCyclic and DeviatoricD2 start from them with --start.
#pragma once
#include <cmath>

#include "ElementTest.h"

class IsotropicCompression : public pdpm::ElementTest {
public:
    IsotropicCompression()
        : ElementTest("IsotropicCompression",
                      "Isotropic element test: preparation, loading to v_max and unloading (thesis Fig. 2.1)") {
        addDriveParameter();
    }

protected:
    void addTestStages() override {
        addStage({"load", 0.5 * period_,
                  [this] {
                      const double v = startFractionBelowVMax();
                      const double s = std::cbrt(v / vMax_);
                      for (int a = 0; a < 3; ++a) {
                          const double L = box().length()[a];
                          ctrl().setCosine(a, L, L * s, period_, time(), affineDrive());
                      }
                  },
                  Branch::Loading, true});
        addStage({"unload", 0.5 * period_, nullptr, Branch::Unloading, true});
    }

private:
};
