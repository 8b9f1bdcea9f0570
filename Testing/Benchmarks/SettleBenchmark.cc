// Benchmark deck `settle` (../shared/bench/README.md): 50 000 spheres (r in [0.9, 1.1] mm) resting in a
// box with flat walls at x = 0, 0.08 m, y = 0, 0.08 m and a floor at z = 0, gravity -z;
// dt = 3.4e-7 s, 5000 steps: the cost of a static packed bed.
#include <numbers>

#include "BenchmarkCommon.h"
#include "Core/Error.h"
#include "IO/XyzrReader.h"
#include "Particles/Insertion.h"
#include "Particles/PackingPreparation.h"

using namespace pdpm;

class SettleBenchmark : public DPMBase {
public:
    SettleBenchmark() : DPMBase("SettleBenchmark", "Standard deck settle: a static packed bed under gravity") {
        parameters().add("start", &start_, bench::defaultStartFile("settle_packed.xyzr"),
                         "start file (*.xyzr)");
        parameters().add("steps", &steps_, 5000L, "-", "number of time steps", Range::atLeast(1));
        parameters().set("dt", "3.4e-7");
        parameters().set("vtk", "0");
        parameters().set("ene", "0");
        parameters().set("restart_output", "0");
        parameters().set("time_max", "1");  // replaced by steps * dt
        parameters().set("max_initial_overlap", "1");
    }

protected:
    void setupInitialConditions() override {
        ContactParameters p;
        p.k = 1.0e5;
        p.gamma = 0.28;
        p.kt = 2.0 / 7.0 * p.k;
        p.muS = p.muD = 0.5;
        addSpecies("glass", 2000, p);
        setContactLaw("linear");
        XyzrFile f;
        if (start_.empty()) {
            // No deck file: pour and settle an equivalent bed (same size distribution and box).
            std::fprintf(stderr, "settle: no start file, preparing an equivalent bed (this takes a while)\n");
            const Packing pk = prepareSettledBed(uniformRadii(50000, 0.9e-3, 1.1e-3, random()), {0, 0, 0},
                                                 {0.08, 0.08, 0.08}, 2000, 1, quiet());
            f.lo = pk.lo;
            f.hi = pk.hi;
            f.hasBox = true;
            f.x = pk.x;
            f.r = pk.r;
        } else {
            f = readXyzr(start_);
        }
        if (!f.hasBox) inputError("start file " + start_ + " has no '# box' line");
        setDomain(f.lo, f.hi, false, false, false);
        setGravity({0, 0, -9.81});
        particles().reserve(f.x.size());
        for (std::size_t i = 0; i < f.x.size(); ++i) addParticle(f.x[i], f.r[i]);
        for (auto& w : makeBoxWalls(f.lo, f.hi, 0, {true, true, true, true, true, false})) addWall(std::move(w));
        setTimeMax(timeStep() * static_cast<double>(steps_));
        setSaveEvery(timeMax());
        solid_ = 0;
        for (double r : particles().r) solid_ += 4.0 / 3.0 * std::numbers::pi * r * r * r;
    }
    void actionsBeforeTimeLoop() override { timer_.start(); }
    void actionsAfterSolve() override {
        timer_.stop();
        // volume fraction of the bed: solid volume over floor area times the height of the highest particle top
        double top = 0;
        for (std::size_t i = 0; i < particles().size(); ++i) top = std::max(top, particles().x[i].z + particles().r[i]);
        const Vec3 L = box().length();
        bench::printSummary("settle", *this, step(), timer_.seconds(), solid_, L.x * L.y * top);
    }

private:
    std::string start_;
    long steps_ = 0;
    double solid_ = 0;
    bench::LoopTimer timer_;
};

int main(int argc, char** argv) { return SettleBenchmark().run(argc, argv); }
