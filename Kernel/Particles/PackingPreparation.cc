#include "Particles/PackingPreparation.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "Core/DPMBase.h"
#include "Particles/Insertion.h"

namespace pdpm {

namespace {
double solidVolume(const std::vector<double>& radii) {
    double v = 0;
    for (double r : radii) v += 4.0 / 3.0 * std::numbers::pi * r * r * r;
    return v;
}

// Soft frictionless contacts; stiffness chosen so that t_c of the smallest pair allows large steps.
ContactParameters softParameters(double rMin, double density) {
    const double m = 4.0 / 3.0 * std::numbers::pi * rMin * rMin * rMin * density;
    ContactParameters p;
    // t_c = 1e-4 s for two smallest particles, e = 0.3
    const auto kg = stiffnessAndDamping(1e-4, 0.3, 0.5 * m);
    p.k = kg.k;
    p.gamma = kg.gamma;
    return p;
}

class PeriodicCompressor : public DPMBase {
public:
    PeriodicCompressor(const std::vector<double>& radii, double target, const Vec3& centre, double density,
                       uint64_t seed)
        : DPMBase("PackingPreparation"), radii_(radii), target_(target), centre_(centre), density_(density) {
        random().seed(seed);
        disableFileOutput();
    }
    void setup() {
        const double rMin = *std::min_element(radii_.begin(), radii_.end());
        addSpecies("soft", density_, softParameters(rMin, density_));
        setContactLaw("linear-frictionless");
        solid_ = solidVolume(radii_);
        const double L = std::cbrt(solid_ / 0.2);
        const Vec3 h{0.5 * L, 0.5 * L, 0.5 * L};
        setDomain(centre_ - h, centre_ + h, true, true, true);
        insertRandom(*this, radii_, centre_ - h, centre_ + h, 0.0);
        // Compression rate: strain 0.1 per 100 collision times; background damping of ~10 t_c.
        const double tc = 1e-4;
        rate_ = 1e-3 / tc;
        const double mMean = density_ * solid_ / static_cast<double>(radii_.size());
        setBackgroundDamping(mMean / (10 * tc), 0.0);
        tCompress_ = std::log(target_ / 0.2) / (3 * rate_);
        setTimeMax(tCompress_ + 200 * tc);
        setSaveEvery(timeMax());
    }
    void actionsBeforeTimeStep() override {
        if (time() >= tCompress_) return;
        const double s = std::exp(-rate_ * std::min(timeStep(), tCompress_ - time()));
        box().scaleAboutCentre({s, s, s}, &particles());
    }

private:
    std::vector<double> radii_;
    double target_;
    Vec3 centre_;
    double density_, solid_ = 0, rate_ = 0, tCompress_ = 0;
};

class BedSettler : public DPMBase {
public:
    BedSettler(const std::vector<double>& radii, const Vec3& lo, const Vec3& hi, double density, uint64_t seed)
        : DPMBase("PackingPreparation"), radii_(radii), lo_(lo), hi_(hi), density_(density) {
        random().seed(seed);
        disableFileOutput();
    }
    void setup() {
        const double rMin = *std::min_element(radii_.begin(), radii_.end());
        const double rMax = *std::max_element(radii_.begin(), radii_.end());
        addSpecies("soft", density_, softParameters(rMin, density_));
        setContactLaw("linear-frictionless");
        const double spacing = 2.05 * rMax;
        const double nx = std::floor((hi_.x - lo_.x) / spacing), ny = std::floor((hi_.y - lo_.y) / spacing);
        const double layers = std::ceil(static_cast<double>(radii_.size()) / (nx * ny));
        Vec3 top = hi_;
        top.z = std::max(hi_.z, lo_.z + (layers + 1) * spacing);
        setDomain(lo_, top, false, false, false);
        setGravity({0, 0, -9.81});
        for (auto& w : makeBoxWalls(lo_, top, 0, {true, true, true, true, true, false})) addWall(std::move(w));
        std::vector<double> shuffled = radii_;
        std::shuffle(shuffled.begin(), shuffled.end(), random());
        insertOnGrid(*this, shuffled, lo_, top, spacing);
        const double tc = 1e-4;
        const double mMean = density_ * solidVolume(radii_) / static_cast<double>(radii_.size());
        setBackgroundDamping(mMean / (20 * tc), 0.0);
        // fall time over the column height plus settling
        setTimeMax(2 * std::sqrt(2 * (top.z - lo_.z) / 9.81) + 2000 * tc);
        setSaveEvery(timeMax());
    }

private:
    std::vector<double> radii_;
    Vec3 lo_, hi_;
    double density_;
};

Packing collect(const DPMBase& d) {
    Packing p;
    p.lo = d.box().lo();
    p.hi = d.box().hi();
    p.x = d.particles().x;
    p.r = d.particles().r;
    for (auto& x : p.x) d.box().wrap(x);
    return p;
}
} // namespace

Packing preparePeriodicPacking(const std::vector<double>& radii, double target, const Vec3& centre, double density,
                               uint64_t seed, bool quiet) {
    PeriodicCompressor c(radii, target, centre, density, seed);
    c.setQuiet(quiet);
    c.setup();
    c.solve();
    return collect(c);
}

Packing prepareSettledBed(const std::vector<double>& radii, const Vec3& lo, const Vec3& hi, double density,
                          uint64_t seed, bool quiet) {
    BedSettler b(radii, lo, hi, density, seed);
    b.setQuiet(quiet);
    b.setup();
    b.solve();
    Packing p = collect(b);
    p.lo = lo;
    p.hi = hi;
    return p;
}

} // namespace pdpm
