// Benchmark deck `pbox` (../shared/bench/README.md): 9261 polydisperse frictional spheres in a fully
// periodic cube, isotropic compression at true strain rate -1/s, dt = 1.4e-7 s, 20 000 steps.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include "BenchmarkCommon.h"
#include "Core/Error.h"
#include "IO/XyzrReader.h"
#include "Particles/Insertion.h"
#include "Particles/PackingPreparation.h"

using namespace pdpm;

class PeriodicBoxBenchmark : public DPMBase {
public:
    PeriodicBoxBenchmark() : DPMBase("PeriodicBoxBenchmark", "Standard deck pbox: periodic isotropic compression") {
        parameters().add("start", &start_, bench::defaultStartFile("pbox_packed.xyzr"),
                         "start file (*.xyzr); empty: prepare an equivalent packing");
        parameters().add("steps", &steps_, 20000L, "-", "number of time steps", Range::atLeast(1));
        parameters().set("dt", "1.4e-7");
        parameters().set("vtk", "0");
        parameters().set("ene", "0");
        parameters().set("restart_output", "0");
        parameters().set("time_max", "1");
        parameters().set("max_initial_overlap", "1");  // the deck is a compressed packing  // replaced by steps * dt
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
        if (!start_.empty()) {
            const XyzrFile f = readXyzr(start_);
            if (!f.hasBox) inputError("start file " + start_ + " has no '# box' line");
            setDomain(f.lo, f.hi, true, true, true);
            particles().reserve(f.x.size());
            for (std::size_t i = 0; i < f.x.size(); ++i) addParticle(f.x[i], f.r[i]);
        } else {
            // No deck file: prepare an equivalent packing (same size distribution and volume fraction).
            std::fprintf(stderr, "pbox: no start file, preparing an equivalent packing (this takes a while)\n");
            const double L = 0.0521876 - 0.0108124, c = 0.5 * (0.0521876 + 0.0108124);
            const Packing pk = preparePeriodicPacking(uniformRadii(9261, 0.5e-3, 1.5e-3, random()),
                                                      0.690, {c, c, c}, 2000, 1, quiet());
            (void)L;
            setDomain(pk.lo, pk.hi, true, true, true);
            particles().reserve(pk.x.size());
            for (std::size_t i = 0; i < pk.x.size(); ++i) addParticle(pk.x[i], pk.r[i]);
        }
        setTimeMax(timeStep() * static_cast<double>(steps_));
        setSaveEvery(timeMax());
        solid_ = 0;
        for (double r : particles().r) solid_ += 4.0 / 3.0 * std::numbers::pi * r * r * r;
    }
    void actionsBeforeTimeLoop() override {
        if (std::getenv("PDPM_MEMTRACE")) std::fprintf(stderr, "peak RSS before loop: %ld\n", bench::peakRssBytes());
        timer_.start();
    }
    void actionsBeforeTimeStep() override {
        const double s = 1 - timeStep();  // true strain rate -1/s
        box().scaleAboutCentre({s, s, s}, &particles());
    }
    void actionsAfterSolve() override {
        timer_.stop();
        bench::printSummary("pbox", *this, step(), timer_.seconds(), solid_, box().volume());
    }

private:
    std::string start_;
    long steps_ = 0;
    double solid_ = 0;
    bench::LoopTimer timer_;
};

int main(int argc, char** argv) { return PeriodicBoxBenchmark().run(argc, argv); }
