// Benchmark deck `settle` (../shared/bench/README.md): 50 000 spheres (r in [0.9, 1.1] mm) resting in a
// box with flat walls at x = 0, 0.08 m, y = 0, 0.08 m and a floor at z = 0, gravity -z;
// dt = 3.4e-7 s, 5000 steps: the cost of a static packed bed.
#include <algorithm>
#include <cstdio>

#include "BenchmarkCommon.h"
#include "Particles/Insertion.h"
#include "Particles/PackingPreparation.h"

using namespace pdpm;

class SettleBenchmark : public bench::DeckBenchmark {
public:
    SettleBenchmark()
        : DeckBenchmark("SettleBenchmark", "Standard deck settle: a static packed bed under gravity", "settle",
                        "settle_packed.xyzr", 5000, 3.4e-7) {}

protected:
    void setupInitialConditions() override {
        memLine("set-up");
        addDeckSpecies();
        Packing pk;
        if (!start_.empty()) {
            const XyzrFile f = readXyzr(start_);
            if (!f.hasBox) inputError("start file " + start_ + " has no '# box' line");
            pk = {f.lo, f.hi, f.x, f.r};
        } else {
            // No deck file: pour and settle an equivalent bed (same size distribution and box).
            std::fprintf(stderr, "settle: no start file, preparing an equivalent bed (takes a while)\n");
            pk = prepareSettledBed(uniformRadii(50000, 0.9e-3, 1.1e-3, random()), {0, 0, 0}, {0.08, 0.08, 0.08},
                                   2000, 1, quiet());
        }
        setDomain(pk.lo, pk.hi, false, false, false);
        setGravity({0, 0, -9.81});
        addParticles(pk.x, pk.r);
        for (auto& w : makeBoxWalls(pk.lo, pk.hi, 0, {true, true, true, true, true, false})) addWall(std::move(w));
    }
    // The bed: floor area times the height of the highest particle top.
    double measuredVolume() const override {
        double top = 0;
        for (std::size_t i = 0; i < particles().size(); ++i) top = std::max(top, particles().x[i].z + particles().r[i]);
        return box().length().x * box().length().y * top;
    }
};

int main(int argc, char** argv) { return SettleBenchmark().run(argc, argv); }
