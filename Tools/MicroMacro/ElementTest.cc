#include "ElementTest.h"

#include "IO/StateFields.h"

#include "Cli.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>

#include "Core/Error.h"
#include "IO/NumberFormat.h"
#include "Particles/Insertion.h"

namespace pdpm {

namespace {
/// What every element test runs in: a box periodic on all three axes, without walls.
bool fullyPeriodicWithoutWalls(const DPMBase& d) {
    return d.walls().empty() && d.box().periodic(0) && d.box().periodic(1) && d.box().periodic(2);
}
} // namespace

// ---- parameters ------------------------------------------------------------------------------------
ElementTest::ElementTest(const std::string& name, const std::string& description) : DPMBase(name, description) {
    auto& p = parameters();
    p.add("particles", &n_, 1000L, "-", "number of particles N (at most 1e8: 32-bit pair indices)", Range::closed(10, 1e8));
    p.add("r_min", &rMin_, 0.5e-3, "m", "smallest radius (uniform distribution, Sec. 2.2.2)", Range::positive());
    p.add("r_max", &rMax_, 1.5e-3, "m", "largest radius", Range::positive());
    p.add("density", &density_, 2000.0, "kg/m^3", "particle density rho", Range::positive());
    p.add("k", &k_, 1e5, "N/m", "normal spring stiffness k_n (Eq. 2.1)", Range::positive());
    p.add("gamma", &gamma_, 0.0316, "kg/s", "normal contact damping gamma_n", Range::nonNegative());
    p.add("kt", &kt_, 2e4, "N/m", "tangential spring stiffness k_t", Range::nonNegative());
    p.add("gamma_t", &gammaT_, 0.00632, "kg/s", "tangential contact damping gamma_t", Range::nonNegative());
    p.add("mu", &mu_, 0.5, "-", "sliding (= sticking) friction coefficient; 0: frictionless law", Range::nonNegative());
    p.add("gamma_b", &gammaB_, 0.01, "kg/s", "translational background damping gamma_b", Range::nonNegative());
    p.add("gamma_br", &gammaBr_, 1e-8, "kg m^2/s", "rotational background damping (torque -gamma_br w)",
          Range::nonNegative());
    p.add("v_gas", &vGas_, 0.3, "-", "volume fraction of the initial random gas (step i)", Range::open(0, 0.45));
    p.add("gas_speed", &gasSpeed_, 0.5, "m/s", "largest random speed of the initial gas", Range::nonNegative());
    p.add("v0", &v0_, 0.64, "-", "volume fraction after the isotropic preparation (step ii)", Range::open(0, 0.9));
    p.add("prep_rate", &prepRate_, 20.0, "1/s", "true strain rate of the isotropic preparation", Range::positive());
    p.add("relax", &relax_, 0.005, "s", "relaxation at constant volume after the preparation (step iii)",
          Range::nonNegative());
    p.add("v_i", &vi_, 0.64, "-", "start volume fraction of the test for self-prepared runs (>= v0)",
          Range::open(0, 0.9));
    p.add("start", &start_, "", "restart file of an element-test run to start from (empty: prepare)");
    p.add("start_relax", &startRelax_, 0.002, "s", "relaxation after reading --start", Range::nonNegative());
    p.add("v_max", &vMax_, 0.82, "-", "largest volume fraction of a loading cycle", Range::open(0, 0.95));
    p.add("period", &period_, 0.04, "s", "period T of the cosine law (loading T/2, unloading T/2)", Range::positive());
    p.add("save_fractions", &saveFractions_, "0.66,0.68,0.70,0.72,0.75,0.78,0.80",
          "volume fractions v_i at which RUN.load_v.restart / RUN.unload_v.restart are written (comma separated)");
    p.add("outputs", &outputsPerTest_, 200, "-", "outputs (macro rows) over the test stages (unless --save_every)",
          Range::atLeast(1));
    p.addPreset("default", "fast: N = 1000, w = 3, soft k = 1e5 N/m, frictional (mu = --mu), T = 0.04 s", {});
    const std::vector<std::pair<std::string, std::string>> full = {
        {"particles", "9261"}, {"density", "2000"}, {"k", "1e8"},       {"gamma", "1"},
        {"period", "0.005"},   {"v0", "0.64"},      {"v_max", "0.82"},  {"prep_rate", "50"},
        {"relax", "0.0005"},   {"start_relax", "0.0002"}, {"gas_speed", "1"}};
    auto ch2 = full;
    ch2.insert(ch2.end(), {{"r_min", "0.5e-3"}, {"r_max", "1.5e-3"}, {"kt", "0"}, {"gamma_t", "0"}, {"mu", "0"},
                           {"gamma_b", "0.1"}, {"gamma_br", "0"}});
    p.addPreset("thesis-ch2", "thesis chapter 2: frictionless, N = 9261, r in [0.5, 1.5] mm, k = 1e8 N/m, gamma = 1 kg/s, "
                              "gamma_b = 0.1 kg/s, T = 5000 us",
                ch2);
    auto ch3 = full;
    ch3.insert(ch3.end(), {{"r_min", "0.8e-3"}, {"r_max", "1.2e-3"}, {"kt", "2e7"}, {"gamma_t", "0.2"},
                           {"gamma_b", "0.1"}, {"gamma_br", "2e-8"}});
    p.addPreset("thesis-ch3", "thesis chapter 3 (Table 3.1 in SI): N = 9261, w = 1.5, k_n = 1e8, k_t = 2e7 N/m, "
                              "gamma_n = 1, gamma_t = 0.2 kg/s, mu = --mu",
                ch3);
}

std::string ElementTest::stageName() const { return stage_ < stages_.size() && begun_ ? stages_[stage_].name : ""; }

// ---- helpers ---------------------------------------------------------------------------------------
void ElementTest::isotropicRate(double rate) {
    for (int a = 0; a < 3; ++a) ctrl_.setStrainRate(a, rate);
}
void ElementTest::freeAll() {
    for (int a = 0; a < 3; ++a) ctrl_.setFree(a);
}
double ElementTest::volumeFraction() const { return solid_ / box().volume(); }
double ElementTest::lengthForFraction(int axis, double v) const {
    const Vec3 L = box().length();
    return solid_ / (v * L[(axis + 1) % 3] * L[(axis + 2) % 3]);
}
double ElementTest::totalMass() const {
    double m = 0;
    for (double x : particles().m) m += x;
    return m;
}
double ElementTest::wallDampingFor(int axis, double wallMass) const {
    double rs = 0;
    for (double r : particles().r) rs += r;
    const double rMean = rs / static_cast<double>(particles().size());
    const double kEff = k_ * box().length()[axis] / (2 * rMean);
    return 2 * std::sqrt(wallMass * kEff);
}

void ElementTest::setMaterial() {
    if (rMax_ < rMin_) inputError("--r_max must not be smaller than --r_min");
    ContactParameters c;
    c.k = k_;
    c.gamma = gamma_;
    c.kt = kt_;
    c.gammaT = gammaT_;
    c.muS = c.muD = mu_;
    addSpecies("grain", density_, c);
    if (!parameters().wasSetOnCommandLine("contact_law")) setContactLaw(mu_ > 0 ? "linear" : "linear-frictionless");
    setBackgroundDamping(gammaB_, gammaBr_);
}

// ---- set-up ----------------------------------------------------------------------------------------
void ElementTest::setupInitialConditions() {
    setMaterial();
    if (!start_.empty()) {
        // The other run's configuration with its contact histories (tangential, rolling and torsion
        // springs, Luding's delta_max), so the packing does not lose its frictional memory at the
        // start; then this run's material, law and damping (its flags), one species, masses from
        // --density. The clock starts at zero.
        readRestart(start_, true);
        species().clear();
        setMaterial();
        ParticleData& P = particles();
        for (std::size_t i = 0; i < P.size(); ++i) {
            P.species[i] = 0;
            P.setRadius(i, P.r[i], density_);
        }
        setGravity({0, 0, 0});
        if (!fullyPeriodicWithoutWalls(*this))
            inputError("--start: " + start_ + " is not a fully periodic configuration without walls");
        // overlaps of a simulated packing are physical: the insertion check does not apply
        if (!parameters().wasSetOnCommandLine("max_initial_overlap")) parameters().set("max_initial_overlap", "1");
    } else {
        if (vi_ < v0_) inputError("--v_i (" + formatDoubleShort(vi_) + ") must not be below --v0 (" +
                                  formatDoubleShort(v0_) + ")");
        if (vGas_ >= v0_) inputError("--v_gas must be below --v0");
        const auto radii = uniformRadii(static_cast<std::size_t>(n_), rMin_, rMax_, random());
        double solid = 0;
        for (double r : radii) solid += 4.0 / 3.0 * std::numbers::pi * r * r * r;
        const double L = std::cbrt(solid / vGas_);
        setDomain({0, 0, 0}, {L, L, L}, true, true, true);
        insertRandom(*this, radii, {0, 0, 0}, {L, L, L}, gasSpeed_);
    }
    solid_ = 0;
    for (double r : particles().r) solid_ += 4.0 / 3.0 * std::numbers::pi * r * r * r;
    ctrl_.setReference(box());
    lastFraction_ = volumeFraction();
    buildStages();
    double total = 0;
    for (const auto& s : stages_) total += s.duration;
    setTimeMax(time() + total);
    if (!parameters().wasSetOnCommandLine("save_every")) setSaveEvery(testDuration() / outputsPerTest_);
    macro_.setPath(outputPath(".macro.csv"));
}

void ElementTest::buildStages() {
    stages_.clear();
    fractions_.clear();
    // the tools' list parser: comma-separated, no empty entries ("0.7," is a typo, not a shorter list)
    for (double f : tools::parseNumberList("--save_fractions", saveFractions_)) {
        if (!(f > 0 && f < 1)) inputError("--save_fractions: '" + fmt(f) + "' is not a volume fraction in (0, 1)");
        fractions_.push_back(f);
    }
    if (start_.empty()) {
        addStage({"compress", std::log(v0_ / vGas_) / (3 * prepRate_), [this] { isotropicRate(-prepRate_); }});
        addStage({"relax", relax_, [this] { freeAll(); }});
        if (vi_ > v0_) {
            addStage({"compress_vi", std::log(vi_ / v0_) / (3 * prepRate_), [this] { isotropicRate(-prepRate_); }});
            addStage({"relax_vi", relax_, [this] { freeAll(); }});
        }
    } else if (startRelax_ > 0) {
        addStage({"relax_start", startRelax_, [this] { freeAll(); }});
    }
    addTestStages();
    stages_.erase(std::remove_if(stages_.begin(), stages_.end(), [](const Stage& s) { return !(s.duration > 0); }),
                  stages_.end());
    if (stages_.empty()) inputError("nothing to do: every stage has zero duration");
}

double ElementTest::testStart() const {
    double t = 0;
    for (const auto& s : stages_) {
        if (s.test) return t;
        t += s.duration;
    }
    return t;
}
double ElementTest::testDuration() const {
    double d = 0;
    for (const auto& s : stages_)
        if (s.test) d += s.duration;
    if (d > 0) return d;
    for (const auto& s : stages_) d += s.duration;
    return d;
}

void ElementTest::actionsOnRestart() {
    // every element test runs in a fully periodic box without walls (as a --start file must be)
    if (!fullyPeriodicWithoutWalls(*this))
        inputError("restart file: not a fully periodic box without walls, which every element test runs in");
    solid_ = 0;
    for (double r : particles().r) solid_ += 4.0 / 3.0 * std::numbers::pi * r * r * r;
    const std::size_t savedStage = stage_;
    const bool savedBegun = begun_;
    const double savedStart = stageStart_;
    // stage durations are fixed by the parameters; the first stage's start is time 0
    const double t = time();
    setTime(0);
    buildStages();
    setTime(t);
    // (the stage index never passes the last stage: a finished run stays in it)
    if (savedStage >= stages_.size())
        inputError("restart file: stage " + std::to_string(savedStage) + " but this run has " + std::to_string(stages_.size()) +
                   " stages (0 to " + std::to_string(stages_.size() - 1) + ")");
    // a stage began at a step of the run: not before time 0, not after the restart time (within a step)
    if (savedBegun && !(savedStart >= 0 && savedStart <= t + timeStep()))
        inputError("restart file: stage_start " + fmt(savedStart) + " s outside the run so far (0 to " + fmt(t) + " s)");
    stage_ = savedStage;
    begun_ = savedBegun;
    stageStart_ = savedStart;
    macro_.setPath(outputPath(".macro.csv"));
    macro_.reload();
    macro_.truncateAfter(time());
    lastFraction_ = volumeFraction();
}

void ElementTest::actionsBeforeTimeLoop() {
    ctrl_.applyRates(box(), time());  // after a restart: the box's motion before the first step
    // whether the step before the loop was stress-controlled (after a restart: the stored controller's
    // state); a stage that enters stress control re-evaluates its records (actionsBeforeTimeStep)
    stressLastStep_ = ctrl_.needsStress();
    if (stressLastStep_) {
        // the first step uses the stored (restart) or the current contact sum; every later step uses the
        // records of the step before it, so the first step records too (as actionsAfterTimeStep asks)
        if (!haveRestoredContactSum_) refreshContacts();
        requestContacts();
    }
}

void ElementTest::enterStage(std::size_t k) {
    stage_ = k;
    begun_ = true;
    stageStart_ = time();
    const bool firstTest = stages_[k].test && (k == 0 || !stages_[k - 1].test);
    if (firstTest) {
        ctrl_.setReference(box());
        refLength_ = box().length();
    }
    if (stages_[k].begin) stages_[k].begin();
    if (!quiet()) std::fprintf(stderr, "%s: t = %.6g s: stage '%s' (v = %.4f)\n", runName().c_str(), time(),
                               stages_[k].name.c_str(), volumeFraction());
}

Vec3 ElementTest::contactStressSum() const {
    Vec3 s;
    for (const auto& c : contacts()) {
        const Vec3 f = c.fn * c.n + c.ft;
        for (int a = 0; a < 3; ++a) s[a] += f[a] * c.branch[a];
    }
    return s;
}

Vec3 ElementTest::currentStressDiagonal() {
    return stressDiagonalFrom(haveRestoredContactSum_ ? restoredContactSum_ : contactStressSum());
}

Vec3 ElementTest::stressDiagonalFrom(Vec3 s) const {
    const ParticleData& P = particles();
    for (std::size_t i = 0; i < P.size(); ++i)
        for (int a = 0; a < 3; ++a) s[a] += P.m[i] * P.v[i][a] * P.v[i][a];
    return s / box().volume();
}

void ElementTest::actionsBeforeTimeStep() {
    const double t = time(), dt = timeStep();
    // stage boundaries: cumulative durations from t = 0 (or from the stage in progress)
    if (!begun_) enterStage(stage_);
    while (stage_ + 1 < stages_.size() && t >= stageStart_ + stages_[stage_].duration - 0.5 * dt)
        enterStage(stage_ + 1);
    std::vector<double> dens;
    if (ctrl_.swelling() != 0)
        for (int s = 0; s < species().size(); ++s) dens.push_back(species()[s].density);
    // The stress of a stress-controlled step comes from the last step's records. At the first step of
    // stress control they may be an output's, or none; a straight and a restarted run then both
    // re-evaluate them here, from the same state. The stored sum of a restart serves its first step only.
    const bool stress = ctrl_.needsStress();
    Vec3 sigma{};
    if (stress) {
        if (!stressLastStep_) {
            refreshContacts();
            haveRestoredContactSum_ = false;
        }
        sigma = currentStressDiagonal();
    }
    haveRestoredContactSum_ = false;
    stressLastStep_ = stress;
    ctrl_.step(box(), particles(), t, dt, sigma, dens);
    if (ctrl_.swelling() != 0) {
        solid_ = 0;
        for (double r : particles().r) solid_ += 4.0 / 3.0 * std::numbers::pi * r * r * r;
    }
}

void ElementTest::actionsAfterTimeStep() {
    if (ctrl_.needsStress()) requestContacts();
    const double v = volumeFraction();
    if (begun_ && stage_ < stages_.size() && stages_[stage_].branch != Branch::None && !fractions_.empty()) {
        const bool loading = stages_[stage_].branch == Branch::Loading;
        for (double f : fractions_) {
            const bool crossed = loading ? (lastFraction_ < f && v >= f) : (lastFraction_ > f && v <= f);
            if (!crossed) continue;
            char tag[32];
            std::snprintf(tag, sizeof tag, ".%s_%.3f.restart", loading ? "load" : "unload", f);
            writeRestart(outputPath(tag));
        }
    }
    lastFraction_ = v;
}

void ElementTest::writeOutputFiles() {
    DPMBase::writeOutputFiles();
    const auto& p = parameters();
    auto on = [&](const char* n) { const std::string v = p.get(n); return v == "1" || v == "true"; };
    // records for the macro row where the kernel made none (no ene, vtk or fstat output): a refresh,
    // unless the step made its own (stress control asks for them every step; replacing them would make
    // the next step's stress depend on the output flags)
    if (!(on("vtk") || on("ene") || on("fstat")) && !contactsAreCurrent()) refreshContacts();
    MacroInput in;
    in.volume = box().volume();
    in.time = time();
    in.tau = (time() - testStart()) / testDuration();
    in.stiffness = k_;
    in.mu = mu_;
    const StrainState s = ctrl_.strain(box());
    in.strain = {-s.trueStrain.x, -s.trueStrain.y, -s.trueStrain.z};
    in.epsV = -s.volumetricTrue;
    in.epsDev = s.deviatoric;
    in.epsDevEngineering = s.deviatoricEngineering;
    const double rotational = rotationalEnergy();
    in.kineticEnergy = kineticEnergy() + rotational;
    in.elasticEnergy = elasticEnergy();
    // flow taken up by the particles: axes whose walls move without remapping the particles, at the
    // cosine law's exact rate now (not the last step's: a row written right after a restart is the same)
    std::array<bool, 3> flow{};
    Vec3 rate{};
    for (int a = 0; a < 3; ++a) {
        const AxisControl& c = ctrl_.axis(a);
        flow[static_cast<std::size_t>(a)] = c.mode == AxisMode::Cosine && !c.affine;
        if (flow[static_cast<std::size_t>(a)]) rate[a] = BoxController::cosineRate(c, time()) / box().length()[a];
    }
    const Vec3 centre = 0.5 * (box().lo() + box().hi());
    in.fluctuationKineticEnergy = fluctuationKineticEnergy(particles(), rate, centre, flow) + rotational;
    // the faces that move (any controlled axis) for the mobilisation ratio of the face layer
    for (int a = 0; a < 3; ++a) in.faceAxes[static_cast<std::size_t>(a)] = ctrl_.axis(a).mode != AxisMode::Free;
    in.boxLo = {box().lo().x, box().lo().y, box().lo().z};
    in.boxHi = {box().hi().x, box().hi().y, box().hi().z};
    macro_.append(macroRow(computeMacro(particles(), contacts(), in), in));
}

void ElementTest::saveDriverState(std::vector<std::pair<std::string, std::string>>& kv) const {
    kv.emplace_back("stage", std::to_string(stage_));
    kv.emplace_back("stage_begun", begun_ ? "1" : "0");
    kv.emplace_back("stage_start", fmt(stageStart_));
    // written from actionsAfterTimeStep or writeOutputFiles; under stress control contacts() are then
    // the records the step made (otherwise records re-evaluated at this state, as a straight run uses them)
    if (ctrl_.needsStress() && contactsAreCurrent()) kv.emplace_back("contact_stress_sum", fmt(contactStressSum()));
    ctrl_.save(kv);
}

void ElementTest::loadDriverState(const std::vector<std::pair<std::string, std::string>>& kv) {
    const auto malformed = [](const std::string& k, const std::string& v) {
        inputError("restart file: malformed " + k + " '" + v + "'");
    };
    requireDriverKeys(kv, {"stage", "stage_begun", "stage_start"});
    for (const auto& [k, v] : kv) {
        long x = 0;
        if (k == "stage") {
            if (!parseStrictLong(v, x) || x < 0) malformed(k, v);
            stage_ = static_cast<std::size_t>(x);
        } else if (k == "stage_begun") {
            if (v != "0" && v != "1") malformed(k, v);
            begun_ = v == "1";
        } else if (k == "stage_start") {
            if (!parseDouble(v, stageStart_)) malformed(k, v);
        } else if (k == "contact_stress_sum") {
            // three finite numbers separated by single spaces, nothing else (as saveDriverState writes)
            const auto s1 = v.find(' '), s2 = v.rfind(' ');
            Vec3& c = restoredContactSum_;
            if (s1 == std::string::npos || s1 == s2 || !parseDouble(v.substr(0, s1), c.x) ||
                !parseDouble(v.substr(s1 + 1, s2 - s1 - 1), c.y) || !parseDouble(v.substr(s2 + 1), c.z))
                malformed(k, v);
            haveRestoredContactSum_ = true;
        }
    }
    ctrl_.load(kv);
}

} // namespace pdpm
