// UniaxialCyclic (thesis Sec. 2.3.2 and 3.2.3): from a prepared configuration (--start FILE, or the
// preparation of ElementTest when none is given), uniaxial compression along z by the cosine law of
// Eq. (2.2) from the start volume fraction v_i to v_max and back to v_i over one period T; the x and y
// lengths are fixed. --drive wall moves only the periodic boundary (thesis default); --drive
// strain_rate remaps the particle positions affinely as well (Sec. 3.2.2).
#pragma once
#include "ElementTest.h"

class UniaxialCyclic : public pdpm::ElementTest {
public:
    UniaxialCyclic()
        : ElementTest("UniaxialCyclic", "Uniaxial (oedometric) loading to v_max and unloading along z (thesis Sec. 2.3.2)") {
        addDriveParameter();
    }

protected:
    void addTestStages() override {
        addStage({"load", 0.5 * period_,
                  [this] {
                      const double v = startFractionBelowVMax();
                      const double L = box().length().z;
                      ctrl().setFree(0);
                      ctrl().setFree(1);
                      ctrl().setCosine(2, L, L * v / vMax_, period_, time(), affineDrive());
                  },
                  Branch::Loading, true});
        addStage({"unload", 0.5 * period_, nullptr, Branch::Unloading, true});
    }

private:
};
