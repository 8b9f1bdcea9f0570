// Benchmark deck `pbox` (../shared/bench/README.md): 9261 polydisperse frictional spheres in a fully
// periodic cube, isotropic compression at true strain rate -1/s, dt = 1.4e-7 s, 20 000 steps.
#include <cstdio>

#include "BenchmarkCommon.h"
#include "Particles/Insertion.h"
#include "Particles/PackingPreparation.h"

using namespace pdpm;

class PeriodicBoxBenchmark : public bench::DeckBenchmark {
public:
    PeriodicBoxBenchmark()
        : DeckBenchmark("PeriodicBoxBenchmark", "Standard deck pbox: periodic isotropic compression", "pbox",
                        "pbox_packed.xyzr", 20000, 1.4e-7) {}

protected:
    void setupInitialConditions() override {
        memLine("set-up");
        addDeckSpecies();
        if (!start_.empty()) {
            const XyzrFile f = readXyzr(start_);
            if (!f.hasBox) inputError("start file " + start_ + " has no '# box' line");
            setDomain(f.lo, f.hi, true, true, true);
            addParticles(f.x, f.r);
        } else {
            // No deck file: prepare an equivalent packing (same size distribution, box and volume fraction).
            std::fprintf(stderr, "pbox: no start file, preparing an equivalent packing (takes a while)\n");
            const double c = 0.5 * (0.0521876 + 0.0108124);
            const Packing pk = preparePeriodicPacking(uniformRadii(9261, 0.5e-3, 1.5e-3, random()), 0.690,
                                                      {c, c, c}, 2000, 1, quiet());
            setDomain(pk.lo, pk.hi, true, true, true);
            addParticles(pk.x, pk.r);
        }
    }
    void actionsBeforeTimeStep() override {
        const double s = 1 - timeStep();  // each step L <- L (1 - dt): true strain rate -1/s
        box().scaleAboutCentre({s, s, s}, &particles());
    }
    double measuredVolume() const override { return box().volume(); }
};

int main(int argc, char** argv) { return PeriodicBoxBenchmark().run(argc, argv); }
