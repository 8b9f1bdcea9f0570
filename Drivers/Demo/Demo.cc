// Demo: the main job of scripts/demo.sh.
//
// A polydisperse frictional packing is prepared in a fully periodic box and then compressed
// uniaxially, the element test of thesis chapters 2-3 in miniature:
//   1. a random gas at low volume fraction (random positions, random velocities),
//   2. isotropic compression at a constant true strain rate up to v0 (affine remap of particles),
//   3. relaxation at constant volume,
//   4. uniaxial compression along z by the co-sinusoidal law of Eq. (2.2), x and y fixed.
// Outputs: Demo.ene, Demo_NNNN.vtu + Demo.pvd (ParaView), Demo.restart and Demo.macro.csv with
// volume fraction, stress and coordination at every output.
#include <cmath>
#include <numbers>
#include <sstream>

#include "Core/DPMBase.h"
#include "IO/AtomicFile.h"
#include "IO/NumberFormat.h"
#include "IO/VtkWriter.h"
#include "Particles/Insertion.h"

using namespace pdpm;

class Demo : public DPMBase {
public:
    Demo() : DPMBase("Demo", "Prepare a polydisperse frictional packing, then compress it uniaxially") {
        auto& p = parameters();
        p.add("particles", &n_, 1000L, "-", "number of particles", Range::atLeast(10));
        p.add("mu", &mu_, 0.5, "-", "sliding friction coefficient", Range::nonNegative());
        p.add("vf_start", &vfStart_, 0.3, "-", "volume fraction of the initial random gas", Range::open(0, 0.45));
        p.add("vf0", &vf0_, 0.64, "-", "volume fraction after isotropic compression", Range::open(0, 0.8));
        p.add("rate", &rate_, 20, "1/s", "true strain rate of the isotropic compression", Range::positive());
        p.add("relax_time", &relax_, 0.005, "s", "relaxation at constant volume", Range::nonNegative());
        p.add("strain", &strain_, 0.1, "-", "maximal uniaxial strain along z", Range::open(0, 0.5));
        p.add("period", &period_, 0.04, "s", "period T of the cosine law (loading takes T/2)", Range::positive());
        p.set("save_every", "0.001");
    }

protected:
    void setupInitialConditions() override {
        ContactParameters c;
        c.k = 1e5;           // N/m
        c.gamma = 0.05;      // kg/s
        c.kt = 2.0 / 7.0 * c.k;
        c.muS = c.muD = mu_;
        addSpecies("grain", 2000, c);
        setContactLaw("linear");
        setBackgroundDamping(0.01, 0.0);
        const auto radii = uniformRadii(static_cast<std::size_t>(n_), 0.5e-3, 1.5e-3, random());
        double solid = 0;
        for (double r : radii) solid += 4.0 / 3.0 * std::numbers::pi * r * r * r;
        const double L = std::cbrt(solid / vfStart_);
        setDomain({0, 0, 0}, {L, L, L}, true, true, true);
        insertRandom(*this, radii, {0, 0, 0}, {L, L, L}, 0.1);
        solid_ = solid;
        // phase times: ln(v0/v_start) = 3 rate t1
        t1_ = std::log(vf0_ / vfStart_) / (3 * rate_);
        t2_ = t1_ + relax_;
        setTimeMax(t2_ + 0.5 * period_);
    }
    void actionsOnRestart() override {
        solid_ = 0;
        for (double r : particles().r) solid_ += 4.0 / 3.0 * std::numbers::pi * r * r * r;
        t1_ = std::log(vf0_ / vfStart_) / (3 * rate_);
        t2_ = t1_ + relax_;
    }
    void actionsBeforeTimeStep() override {
        const double t = time(), dt = timeStep();
        if (t < t1_) {  // isotropic compression: L <- L exp(-rate dt)
            const double s = std::exp(-rate_ * std::min(dt, t1_ - t));
            box().scaleAboutCentre({s, s, s}, &particles());
        } else if (t >= t2_) {  // uniaxial, Eq. (2.2): z(t) = zf + (z0 - zf)/2 (1 + cos 2 pi f t)
            if (z0_ == 0) z0_ = box().length().z;
            const double tau = t + dt - t2_;
            const double zf = z0_ * (1 - strain_);
            const double z = zf + 0.5 * (z0_ - zf) * (1 + std::cos(2 * std::numbers::pi * tau / period_));
            const double c = 0.5 * (box().lo().z + box().hi().z);
            box().setAxis(2, c - 0.5 * z, c + 0.5 * z, &particles());
        }
    }
    void saveDriverState(std::vector<std::pair<std::string, std::string>>& kv) const override {
        kv.emplace_back("z0", fmt(z0_));
        kv.emplace_back("macro", std::to_string(macro_.size()));
    }
    void loadDriverState(const std::vector<std::pair<std::string, std::string>>& kv) override {
        for (const auto& [k, v] : kv)
            if (k == "z0") parseDouble(v, z0_);
    }
    void writeOutputFiles() override {
        DPMBase::writeOutputFiles();
        // Stress sigma = (1/V) sum_c f_c (x) l_c (contact part, compression positive) + kinetic part.
        double s[3][3] = {};
        std::vector<int> z(particles().size(), 0);
        for (const auto& c : contacts()) {
            const Vec3 f = c.fn * c.n + c.ft;
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) s[a][b] += f[a] * c.branch[b];
            ++z[c.i];
            if (c.j >= 0) ++z[c.j];
        }
        const ParticleData& P = particles();
        for (std::size_t i = 0; i < P.size(); ++i)
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b) s[a][b] += P.m[i] * P.v[i][a] * P.v[i][b];
        const double V = box().volume();
        long contacts = 0;
        for (int k : z) contacts += k;
        const double epsZ = z0_ > 0 ? 1 - box().length().z / z0_ : 0.0;
        std::ostringstream row;
        row << fmt(time()) << ',' << fmt(solid_ / V) << ',' << fmt(epsZ) << ',' << fmt(s[0][0] / V) << ','
            << fmt(s[1][1] / V) << ',' << fmt(s[2][2] / V) << ',' << fmt((s[0][0] + s[1][1] + s[2][2]) / (3 * V)) << ','
            << fmt(static_cast<double>(contacts) / static_cast<double>(P.size())) << ','
            << fmt(kineticEnergy() / std::max(elasticEnergy(), 1e-300)) << '\n';
        macro_ += row.str();
        writeWholeFile(outputPath(".macro.csv"),
                       "time,volume_fraction,eps_zz,sigma_xx,sigma_yy,sigma_zz,p,coordination,Ek_over_Ep\n" + macro_);
    }

private:
    long n_ = 0;
    double mu_ = 0, vfStart_ = 0, vf0_ = 0, rate_ = 0, relax_ = 0, strain_ = 0, period_ = 0;
    double solid_ = 0, t1_ = 0, t2_ = 0, z0_ = 0;
    std::string macro_;
};

int main(int argc, char** argv) { return Demo().run(argc, argv); }
