#include "Core/DPMBase.h"
#include "Core/MemoryPolicy.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <tuple>

#include "Core/Error.h"
#include "Core/RunMain.h"
#include "IO/AtomicFile.h"
#include "IO/NumberFormat.h"
#include "IO/SnapshotWriter.h"
#include "Math/DeterministicSum.h"

namespace pdpm {

DPMBase::DPMBase(std::string name, std::string description)
    : name_(std::move(name)), description_(std::move(description)), runName_(name_) {
    params_.add("time_max", &timeMax_, 0.0, "s", "simulated time at which the run ends", Range::nonNegative());
    params_.add("dt", &dt_, 0.0, "s", "time step (0: t_c/50 of the fastest pair)", Range::nonNegative());
    params_.add("save_every", &saveEvery_, 0.0, "s", "time between outputs (0: 100 outputs per run)", Range::nonNegative());
    params_.add("contact_law", &lawName_, "linear", "contact law, registered by name (see Documentation/contact-laws.md)",
                [] {
                    std::vector<std::string> n;
                    for (auto& [k, d] : contactLawNames()) n.push_back(k);
                    return n;
                }());
    params_.add("vtk", &vtkOutput_, true, "write RUN_NNNN.vtu particle snapshots for ParaView");
    params_.add("fstat", &fstatOutput_, false, "write RUN.fstat with every contact at each output");
    params_.add("restart_output", &restartOutput_, true, "write RUN.restart at each output");
    params_.add("ene", &eneOutput_, true, "write RUN.ene energies at each output");
    params_.add("seed", &seed_, 12345L, "-", "seed of the random number generator", Range::nonNegative());
    params_.add("max_initial_overlap", &maxInitialOverlap_, 0.1, "-",
                "largest initial overlap allowed, as a fraction of the smaller radius", Range::closed(0, 1));
    params_.add("skin", &skinParameter_, 0.0, "m", "neighbour-list skin (0: 10 % of the smallest radius)", Range::nonNegative());
    law_ = makeContactLaw(lawName_);
}

DPMBase::~DPMBase() = default;

void DPMBase::setContactLaw(const std::string& name) {
    if (params_.wasSetOnCommandLine("contact_law")) return;  // --contact_law wins over the driver's choice
    if (stateLoaded_ && name != lawName_) discardLoadedContacts();
    params_.set("contact_law", name);
    law_ = makeContactLaw(name);
    lawRevision_ = ~0ul;  // choose the form again before the next force evaluation
    neighbours_.invalidate();
}

// One form of a law stores one slot fewer than the other (ContactLaw::omittedSlot). The list holds the
// layout of the form that ran last, or the canonical one (read from a restart file).
void DPMBase::specialiseLaw() {
    lawRevision_ = species_.revision();
    std::unique_ptr<ContactLaw> form = law_->specialised(species_);
    if (!form) return;
    const int stored = neighbours_.historySize;
    if (stored > 0) {
        if (form->omittedSlot() >= 0 && stored == form->historySize() + 1)
            neighbours_.removeHistorySlot(form->omittedSlot());
        else if (form->omittedSlot() < 0 && law_->omittedSlot() >= 0 && stored == form->historySize() - 1)
            neighbours_.insertHistorySlot(law_->omittedSlot());
    }
    law_ = std::move(form);
}

// The one rule for a state loaded with readRestart(path, true) that is run under another contact law
// than the file's (--contact_law, or a driver's setContactLaw): the file's contact histories and
// stored forces belong to the file's law, so every contact starts afresh (the first neighbour build
// finds the pairs with zero history) and the forces are evaluated at t = 0 like a fresh start.
// Resuming a run (readRestart(path, false)) under another law is refused in readRestart.
void DPMBase::discardLoadedContacts() {
    neighbours_.dropHistories();
    stateLoaded_ = false;
}

int DPMBase::addSpecies(const std::string& name, double density, const ContactParameters& self) {
    return species_.add(name, density, self);
}

std::size_t DPMBase::addParticle(const Vec3& x, double radius, int s, const Vec3& v, const Vec3& w, bool fixed) {
    if (!(radius > 0) || !std::isfinite(radius))
        inputError("particle radius must be > 0 (got " + fmt(radius) + ")");
    if (s < 0 || s >= species_.size()) inputError("particle species index " + std::to_string(s) + " is not defined");
    if (!isFinite(x) || !isFinite(v) || !isFinite(w)) inputError("particle position/velocity must be finite");
    neighbours_.invalidate();
    return particles_.add(x, radius, species_[s].density, s, v, w, fixed);
}

std::size_t DPMBase::addWall(std::unique_ptr<Wall> w) {
    if (w->species < 0 || w->species >= species_.size())
        inputError("wall species index " + std::to_string(w->species) + " is not defined");
    walls_.push_back(std::move(w));
    neighbours_.invalidate();
    return walls_.size() - 1;
}

void DPMBase::setOutput(const std::string& dir, const std::string& runName) {
    outDir_ = dir.empty() ? "." : dir;
    runName_ = runName.empty() ? name_ : runName;
}

void DPMBase::setTimeStep(double dt) {
    if (!params_.wasSetOnCommandLine("dt")) dt_ = dt;
}
void DPMBase::setTimeMax(double t) {
    if (!params_.wasSetOnCommandLine("time_max")) timeMax_ = t;
}
void DPMBase::setSaveEvery(double dt) {
    if (!params_.wasSetOnCommandLine("save_every")) saveEvery_ = dt;
}

void DPMBase::disableFileOutput() {
    for (const char* flag : {"vtk", "ene", "fstat", "restart_output"}) params_.set(flag, "0");
}

std::string DPMBase::outputPath(const std::string& suffix) const {
    return (std::filesystem::path(outDir_) / (runName_ + suffix)).string();
}

// ---- command line -----------------------------------------------------------------------------------
int DPMBase::run(int argc, char** argv) {
    applyMemoryPolicy();  // before the run allocates: freed scratch goes back to the system
    return runMain(name_.c_str(), [&]() -> int {
        options_ = parseCommandLine(argc, argv, params_);
        if (options_.help) {
            params_.printHelp(std::cout, name_, description_);
            return 0;
        }
        if (options_.threads > 0) omp_set_num_threads(options_.threads);
        quiet_ = options_.quiet;
        setOutput(options_.output, options_.name);
        law_ = makeContactLaw(lawName_);
        rng_.seed(static_cast<uint64_t>(seed_));
        if (!options_.restart.empty()) {
            readRestart(options_.restart);
            actionsOnRestart();
            prepare(false);
        } else {
            setupInitialConditions();
            prepare(true);
        }
        solve();
        return 0;
    });
}

double DPMBase::minCollisionTime() const {
    if (particles_.empty()) return 0;
    // For each species present: smallest particle; pairs of smallest particles are the fastest.
    const int ns = species_.size();
    std::vector<double> rmin(ns, 1e300), mmin(ns, 1e300);
    for (std::size_t i = 0; i < particles_.size(); ++i) {
        const int s = particles_.species[i];
        rmin[s] = std::min(rmin[s], particles_.r[i]);
        mmin[s] = std::min(mmin[s], particles_.m[i]);
    }
    double tc = 1e300;
    auto consider = [&](const ContactParameters& p, double m, double rEff) {
        const double k = law_->stiffness(p, rEff);
        const double g = law_->normalDamping(p);
        if (!(k > 0)) return;
        const double w2 = k / m - (g / (2 * m)) * (g / (2 * m));
        // over-damped pairs: the relevant time scale is the damping time 2m/g, bounded by the elastic one
        const double t = w2 > 0 ? M_PI / std::sqrt(w2) : M_PI * std::sqrt(m / k);
        tc = std::min(tc, t);
    };
    for (int a = 0; a < ns; ++a) {
        if (rmin[a] > 1e299) continue;
        for (int b = a; b < ns; ++b) {
            if (rmin[b] > 1e299) continue;
            consider(species_.pair(a, b), reducedMass(mmin[a], mmin[b]), rmin[a] * rmin[b] / (rmin[a] + rmin[b]));
        }
        for (const auto& w : walls_) consider(species_.pair(a, w->species), mmin[a], rmin[a]);
    }
    return tc;
}

void DPMBase::prepare(bool freshStart) {
    if (particles_.empty()) inputError("no particles: setupInitialConditions() added none");
    if (species_.size() == 0) inputError("no species defined");
    // Validate every species pair in use.
    std::vector<char> used(species_.size(), 0);
    for (int32_t s : particles_.species) used[s] = 1;
    for (int a = 0; a < species_.size(); ++a) {
        if (!used[a]) continue;
        for (int b = a; b < species_.size(); ++b) {
            if (!used[b]) continue;
            const auto& p = species_.pair(a, b);
            const std::string who = "species pair (" + species_[a].name + ", " + species_[b].name + ")";
            if (!p.defined) inputError(who + ": no contact parameters given (mixed pairs need explicit parameters)");
            law_->validate(p, who);
        }
        for (const auto& w : walls_) {
            const auto& p = species_.pair(a, w->species);
            const std::string who = "species pair (" + species_[a].name + ", wall " + species_[w->species].name + ")";
            if (!p.defined) inputError(who + ": no contact parameters given");
            law_->validate(p, who);
        }
    }
    specialiseLaw();
    const double tc = minCollisionTime();
    if (dt_ == 0) dt_ = tc / 50;
    if (!(dt_ > 0) || !std::isfinite(dt_)) inputError("time step could not be determined (dt = " + fmt(dt_) + ")");
    if (dt_ > tc / 10)
        inputError("time step dt = " + fmt(dt_) + " s is above t_c/10 = " + fmt(tc / 10) +
                   " s of the fastest pair (t_c = " + fmt(tc) + " s)");
    // Lower bounds: not physics, but a run that would take forever (a stiffness of 1e300, a time step
    // of 1e-300 s) is refused instead of showing an ETA of many lifetimes.
    if (tc < 1e-15)
        inputError("the fastest pair's contact time t_c = " + fmt(tc) +
                   " s is below 1e-15 s: stiffness, density or radius out of range");
    if (tc < 1e299 && dt_ < 1e-6 * tc)  // (1e300: no pair has a stiffness, nothing to resolve)
        inputError("time step dt = " + fmt(dt_) + " s is below t_c/1e6 = " + fmt(1e-6 * tc) +
                   " s of the fastest pair (more than a million steps per contact)");
    // a step the clock can resolve at this time (a restart at t = 1e10 s with dt = 1e-7 s would never advance)
    if (!((time_ + dt_) - time_ >= 0.5 * dt_))
        inputError("time step dt = " + fmt(dt_) + " s is below the clock's resolution at t = " + fmt(time_) + " s");
    if (!(timeMax_ > time_)) inputError("time_max (" + fmt(timeMax_) + " s) must exceed the current time " + fmt(time_) + " s");
    for (const auto& w : walls_) w->moveTo(time_);

    // On a restart the neighbour list comes from the file, exactly as it was (pair order matters for
    // bitwise continuation); it is rebuilt only on a fresh start.
    if (freshStart || !neighbours_.isValid()) {
        neighbours_.setSkin(skinParameter_);
        neighbours_.build(particles_, box_, walls_, law_->historySize(), law_->wallHistorySize());
    }
    slabRecords_.resize(neighbours_.slabCount() + 1);
    slabEnergy_.assign(neighbours_.slabCount() + 1, 0.0);

    if (freshStart) {
        // Initial overlaps above 10 % of the smaller radius are refused.
        for (std::size_t k = 0; k < neighbours_.pairCount(); ++k) {
            const uint32_t i = neighbours_.pairI[k], j = neighbours_.pairJ[k];
            Vec3 d = particles_.x[i] - particles_.x[j];
            box_.minimumImage(d);
            const double overlap = particles_.r[i] + particles_.r[j] - norm(d);
            if (overlap > maxInitialOverlap_ * std::min(particles_.r[i], particles_.r[j]))
                inputError("initial overlap of particles " + std::to_string(i) + " and " + std::to_string(j) + " is " +
                           fmt(overlap) + " m, above " + fmt(100 * maxInitialOverlap_) +
                           " % of the smaller radius (--max_initial_overlap)");
        }
    }
    std::filesystem::path dir(outDir_);
    ensureDirectory(outDir_);
    if (freshStart || eneBuffer_.empty()) {
        std::ostringstream h;
        writeEneHeader(h);
        h << '\n';
        eneBuffer_ = h.str();
    }
    if (freshStart) {
        outputEvery_ = outputInterval();
        nextOutput_ = time_;
    } else if (saveEvery_ > 0) {
        outputEvery_ = saveEvery_;  // --save_every given again on restart wins
    }
    if (vtkOutput_ && snapshotWriterFactory() && !snapshotWriter_) snapshotWriter_ = snapshotWriterFactory()();
    if (freshStart && stateLoaded_) {
        // A state loaded with readRestart(path, true) carries the forces of its last step; evaluating
        // them again would advance the contact histories (incremental springs) a second time.
        if (outputNeedsContacts()) refreshContacts();
    } else if (freshStart) {
        // The forces at t = 0 with zero elapsed time: no spring increment and no relaxation time, so that
        // after n steps the springs hold n increments, as in a run continued from a restart file (only a
        // Coulomb cap met by the dashpot alone can set a spring at t = 0).
        const bool rec = outputNeedsContacts();
        computeForces(rec, 0.0);
        addBodyForces();
        if (rec) gatherRecords();
    }
    stateLoaded_ = false;
    prepared_ = true;
}

void DPMBase::advanceNextOutput(double every) {
    const double now = time_ + 0.5 * dt_;
    for (int k = 0; nextOutput_ <= now; ++k) {
        const double next = nextOutput_ + every;
        // An interval far below the step, or below the clock's resolution at this time (where adding
        // it changes nothing): output every step from now on, as such an interval asks.
        if (k == 64 || !(next > nextOutput_)) {
            nextOutput_ = time_ + dt_;
            return;
        }
        nextOutput_ = next;
    }
}

double DPMBase::outputInterval() const {
    if (saveEvery_ > 0) return saveEvery_;
    return std::max(timeMax_ - time_, dt_) / 100;
}

// ---- time loop --------------------------------------------------------------------------------------
void DPMBase::solve() {
    if (!prepared_) prepare(true);
    progress_ = std::make_unique<ProgressReporter>(quiet_);
    progress_->setFractionSource([this] { return progressFraction(); });
    progress_->setLabel(progressLabel_);
    actionsBeforeTimeLoop();
    const double every = outputEvery_ > 0 ? outputEvery_ : outputInterval();
    if (time_ >= nextOutput_ - 0.5 * dt_) {
        nextOutput_ += every;
        writeOutputFiles();
    }
    progress_->start(time_, timeMax_);
    bool lastWasOutput = true;
    while (time_ < timeMax_ - 0.5 * dt_ && continueSolve()) {
        actionsBeforeTimeStep();  // may call requestContacts() for this step's force evaluation
        const bool record = recordRequested_ || (outputNeedsContacts() && time_ + dt_ >= nextOutput_ - 0.5 * dt_);
        recordRequested_ = false;
        specialiseLawIfSpeciesChanged();  // a driver may have changed mu_s or mu_d
        const double maxDisplacement = integrateFirstHalf();
        time_ += dt_;
        for (auto& w : walls_) w->moveTo(time_);
        if (neighbours_.needsRebuild(maxDisplacement, particles_, box_, walls_)) {
            if (box_.flowing()) wrapWithFlow();
            neighbours_.build(particles_, box_, walls_, law_->historySize(), law_->wallHistorySize());
            slabRecords_.resize(neighbours_.slabCount() + 1);
            slabEnergy_.assign(neighbours_.slabCount() + 1, 0.0);
        }
        computeForces(record, dt_);
        const bool finite = integrateSecondHalf();
        ++step_;
        if (!finite) reportNonFinite();
        if (record) gatherRecords();
        actionsAfterTimeStep();
        lastWasOutput = false;
        if (time_ >= nextOutput_ - 0.5 * dt_) {
            // advance first, so that a restart written now continues the same output schedule
            advanceNextOutput(every);
            writeOutputFiles();
            lastWasOutput = true;
        }
        progress_->update(time_, step_);
    }
    actionsAfterSolve();
    if (!lastWasOutput) {
        // the last step's own records when it made them (a driver's requestContacts()): a refresh would
        // re-evaluate them with the current rather than the step's predicted velocities
        if (outputNeedsContacts() && !lastStepRecorded_) refreshContacts();
        writeOutputFiles();
    }
    progress_->finish(step_);
    finishFiles();
}

// The two half steps are fused with the other per-particle passes (force reset, displacement
// check for the neighbour list, body forces, NaN check) so that each step streams through the
// particle arrays twice plus the contact loop.
double DPMBase::integrateFirstHalf() {
    ParticleData& P = particles_;
    const long n = static_cast<long>(P.size());
    const double h = 0.5 * dt_, dt = dt_;
    const bool haveRef = neighbours_.referenceCount() == P.size();
    vPred_.resize(P.size());
    wPred_.resize(P.size());
    // Raw restrict pointers: through the vectors, every store would force the compiler to reload
    // the other arrays' data pointers.
    Vec3* __restrict x = P.x.data();
    Vec3* __restrict v = P.v.data();
    Vec3* __restrict w = P.w.data();
    Vec3* __restrict f = P.f.data();
    Vec3* __restrict t = P.t.data();
    const double* __restrict invM = P.invM.data();
    const double* __restrict m = P.m.data();
    const double* __restrict r = P.r.data();
    const uint8_t* __restrict fixed = P.fixed.data();
    const Vec3* __restrict x0 = neighbours_.referencePositions();
    Vec3* __restrict vp = vPred_.data();
    Vec3* __restrict wp = wPred_.data();
    double maxD2 = 0;
#pragma omp parallel for schedule(static) reduction(max : maxD2)
    for (long i = 0; i < n; ++i) {
        if (!fixed[i]) {
            const Vec3 dv = (h * invM[i]) * f[i];
            const Vec3 dw = (h * ParticleData::inverseInertia(m[i], r[i])) * t[i];
            v[i] += dv;
            w[i] += dw;
            x[i] += dt * v[i];
            vp[i] = v[i] + dv;  // predicted v(n+1), assuming F(n+1) = F(n)
            wp[i] = w[i] + dw;
        } else {
            vp[i] = v[i];
            wp[i] = w[i];
        }
        f[i] = {};
        t[i] = {};
        if (haveRef) {
            const double d2 = norm2(x[i] - x0[i]);
            maxD2 = d2 > maxD2 ? d2 : maxD2;
        }
    }
    forcesZeroed_ = true;
    usePredicted_ = true;
    return haveRef ? std::sqrt(maxD2) : 1e300;
}

// Across a boundary that moves without remapping, a particle that leaves at one side re-enters as
// the image with the flow of that side: position -k L and velocity -k L' (the predicted velocity too;
// fixed particles as well, so that their contacts stay consistent). The neighbour list would wrap the
// positions alone.
void DPMBase::wrapWithFlow() {
    ParticleData& P = particles_;
    const long n = static_cast<long>(P.size());
    const bool pred = vPred_.size() == P.size();
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) {
        const Vec3 dv = box_.wrapWithVelocityShift(P.x[i]);
        P.v[i] += dv;
        if (pred) vPred_[i] += dv;
    }
}

bool DPMBase::integrateSecondHalf() {
    ParticleData& P = particles_;
    const long n = static_cast<long>(P.size());
    const double h = 0.5 * dt_;
    const Vec3 g = gravity_;
    const double gbt = gammaBt_, gbr = gammaBr_;
    bool bad = false;
    Vec3* __restrict v = P.v.data();
    Vec3* __restrict w = P.w.data();
    Vec3* __restrict f = P.f.data();
    Vec3* __restrict t = P.t.data();
    const double* __restrict m = P.m.data();
    const double* __restrict invM = P.invM.data();
    const double* __restrict r = P.r.data();
    const uint8_t* __restrict fixed = P.fixed.data();
    const Vec3* __restrict vp = vPred_.data();
    const Vec3* __restrict wp = wPred_.data();
#pragma omp parallel for schedule(static) reduction(|| : bad)
    for (long i = 0; i < n; ++i) {
        f[i] += m[i] * g - gbt * vp[i];
        t[i] -= gbr * wp[i];
        if (!fixed[i]) {
            v[i] += (h * invM[i]) * f[i];
            w[i] += (h * ParticleData::inverseInertia(m[i], r[i])) * t[i];
        }
        if (!std::isfinite(v[i].x + v[i].y + v[i].z + w[i].x + w[i].y + w[i].z)) bad = true;
    }
    return !bad;
}

void DPMBase::addBodyForces() {
    ParticleData& P = particles_;
    const long n = static_cast<long>(P.size());
    const Vec3 g = gravity_;
    const double gbt = gammaBt_, gbr = gammaBr_;
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) {
        P.f[i] += P.m[i] * g - gbt * P.v[i];
        P.t[i] -= gbr * P.w[i];
    }
}

void DPMBase::computeForces(bool record, double historyDt) {
    ParticleData& P = particles_;
    const long n = static_cast<long>(P.size());
    if (!forcesZeroed_) {
#pragma omp parallel for schedule(static)
        for (long i = 0; i < n; ++i) {
            P.f[i] = {};
            P.t[i] = {};
        }
    }
    forcesZeroed_ = false;
    const std::size_t nWallEntries = neighbours_.wallParticle.size();
    if (wallForce_.size() < nWallEntries) {
        wallForce_.resize(nWallEntries);
        wallTorque_.resize(nWallEntries);
        wallEnergy_.resize(nWallEntries);
        wallSliding_.resize(nWallEntries);
    }
    ForceContext c{P, box_, neighbours_, walls_, species_};
    c.velocity = usePredicted_ ? vPred_.data() : P.v.data();
    c.angularVelocity = usePredicted_ ? wPred_.data() : P.w.data();
    usePredicted_ = false;
    c.dt = historyDt;
    c.time = time_;
    c.record = record;
    c.records = &slabRecords_;
    c.energy = &slabEnergy_;
    c.wallForce = &wallForce_;
    c.wallTorque = &wallTorque_;
    c.wallEnergy = &wallEnergy_;
    c.wallSliding = &wallSliding_;
    law_->computePairForces(c);
    law_->computeWallForces(c);
    lastStepRecorded_ = record;
    computeAdditionalForces();
}

void DPMBase::gatherRecords() {
    contactsFlat_.clear();
    for (const auto& v : slabRecords_) contactsFlat_.insert(contactsFlat_.end(), v.begin(), v.end());
    double e = 0;
    for (double x : slabEnergy_) e += x;
    elasticEnergy_ = e;
}

void DPMBase::refreshContacts() {
    specialiseLawIfSpeciesChanged();
    if (!neighbours_.isValid()) {
        neighbours_.setSkin(skinParameter_);
        neighbours_.build(particles_, box_, walls_, law_->historySize(), law_->wallHistorySize());
        slabRecords_.resize(neighbours_.slabCount() + 1);
        slabEnergy_.assign(neighbours_.slabCount() + 1, 0.0);
    }
    // Forces at the current state with records, with zero elapsed time (the springs as stored). The law
    // may still update histories (projection, caps), so evaluate on a copy.
    auto savedHistory = neighbours_.history;
    auto savedWallHistory = neighbours_.wallHistory;
    auto savedF = particles_.f;
    auto savedT = particles_.t;
    std::vector<std::pair<Vec3, Vec3>> savedWall;
    for (const auto& w : walls_) savedWall.emplace_back(w->force, w->torque);
    computeForces(true, 0.0);
    gatherRecords();
    for (std::size_t k = 0; k < walls_.size(); ++k) std::tie(walls_[k]->force, walls_[k]->torque) = savedWall[k];
    neighbours_.history = std::move(savedHistory);
    neighbours_.wallHistory = std::move(savedWallHistory);
    particles_.f = std::move(savedF);
    particles_.t = std::move(savedT);
}

// The check at output steps: position, velocity and spin finite, and the squares of velocity and
// spin too, so that no energy written to the .ene file (or a later macro file) overflows to inf.
static bool particleStateIsFinite(const ParticleData& P, long i) {
    return std::isfinite(P.x[i].x + P.x[i].y + P.x[i].z + norm2(P.v[i]) + norm2(P.w[i]));
}

void DPMBase::reportNonFinite() {
    const ParticleData& P = particles_;
    const long n = static_cast<long>(P.size());
    long first = 0;
    while (first < n && particleStateIsFinite(P, first)) ++first;
    // finite values whose squares overflow (a speed beyond 1e154 m/s, e.g. from an edited restart)
    const bool overflow = first < n && isFinite(P.x[first]) && isFinite(P.v[first]) && isFinite(P.w[first]);
    std::string where = lastFiniteRestartTime_ >= 0
                            ? "; last finite state (t = " + fmt(lastFiniteRestartTime_) + " s) is in " + outputPath(".restart")
                            : "";
    try {
        finishFiles();  // the contact blocks written so far are kept
    } catch (const InputError& e) {
        where += std::string("; ") + e.what();  // the NaN stays the message's subject
    }
    inputError(std::string(overflow ? "overflow (velocity squared not finite)" : "NaN") + " in the state of particle " +
               std::to_string(first) + " at t = " + fmt(time_) + " s (step " + std::to_string(step_) + ")" + where);
}

// ---- energies (deterministic sums) ------------------------------------------------------------------
double DPMBase::kineticEnergy() const {
    const ParticleData& P = particles_;
    return deterministicSum(P.size(), [&](std::size_t i) { return P.fixed[i] ? 0.0 : 0.5 * P.m[i] * norm2(P.v[i]); });
}
double DPMBase::rotationalEnergy() const {
    const ParticleData& P = particles_;
    return deterministicSum(P.size(), [&](std::size_t i) {
        return P.fixed[i] ? 0.0 : 0.2 * P.m[i] * P.r[i] * P.r[i] * norm2(P.w[i]);
    });
}
double DPMBase::gravitationalEnergy() const {
    const ParticleData& P = particles_;
    const Vec3 g = gravity_;
    return deterministicSum(P.size(), [&](std::size_t i) { return P.fixed[i] ? 0.0 : -P.m[i] * dot(g, P.x[i]); });
}

std::size_t DPMBase::memoryBytes() const { return particles_.bytes() + neighbours_.bytes(); }

// ---- output -----------------------------------------------------------------------------------------
void DPMBase::writeEneHeader(std::ostream& os) const {
    os << "# time ke_trans ke_rot e_elastic e_gravity e_dissipated";
}
void DPMBase::writeEneTimeStep(std::ostream& os) const {
    os << fmt(time_) << ' ' << fmt(kineticEnergy()) << ' ' << fmt(rotationalEnergy()) << ' ' << fmt(elasticEnergy_)
       << ' ' << fmt(gravitationalEnergy()) << " nan";
}

bool DPMBase::outputNeedsContacts() const { return eneOutput_ || vtkOutput_ || fstatOutput_; }

std::size_t DPMBase::countContacts() const {
    const ParticleData& P = particles_;
    std::size_t n = 0;
    for (std::size_t k = 0; k < neighbours_.pairCount(); ++k) {
        const uint32_t i = neighbours_.pairI[k], j = neighbours_.pairJ[k];
        Vec3 d = P.x[i] - P.x[j];
        box_.minimumImage(d);
        const double rs = P.r[i] + P.r[j];
        if (norm2(d) < rs * rs) ++n;
    }
    return n;
}

bool DPMBase::stateIsFinite() const {
    const ParticleData& P = particles_;
    const long n = static_cast<long>(P.size());
    bool bad = false;
#pragma omp parallel for schedule(static) reduction(|| : bad)
    for (long i = 0; i < n; ++i)
        if (!particleStateIsFinite(P, i)) bad = true;
    return !bad;
}

void DPMBase::writeOutputFiles() {
    // Never write a restart (or anything) from a non-finite state: a driver hook may have
    // produced it after the step's own check.
    if (!stateIsFinite()) reportNonFinite();
    if (!lastStepRecorded_ && outputNeedsContacts()) refreshContacts();
    if (eneOutput_) writeEne();
    if (vtkOutput_) writeSnapshot();
    if (fstatOutput_) writeFstat();
    ++outputIndex_;  // before the restart file, so that a restarted run continues the numbering
    if (restartOutput_) {
        writeRestart(outputPath(".restart"));
        lastFiniteRestartTime_ = time_;
    }
}

void DPMBase::writeEne() {
    std::ostringstream row;
    writeEneTimeStep(row);
    row << '\n';
    eneBuffer_ += row.str();
    writeWholeFile(outputPath(".ene"), eneBuffer_);
}

void DPMBase::writeSnapshot() {
    if (!snapshotWriter_) {
        static bool warned = false;
        if (!warned && !quiet_)
            std::cerr << name_ << ": note: VTK output is not linked into this program (include IO/VtkWriter.h)\n";
        warned = true;
        return;
    }
    const std::size_t n = particles_.size();
    std::vector<int> coordination(n, 0);
    std::vector<Vec3> force(n);
    for (const auto& c : contactsFlat_) {
        const Vec3 F = c.fn * c.n + c.ft;
        ++coordination[c.i];
        force[c.i] += F;
        if (c.j >= 0) {
            ++coordination[c.j];
            force[c.j] -= F;
        }
    }
    SnapshotView view{particles_, coordination, force, walls_, box_, time_, step_};
    snapshotWriter_->write(outDir_, runName_, outputIndex_, view);
}

void DPMBase::writeFstat() {
    if (!fstatStream_) {
        fstatStream_ = std::make_unique<AtomicOFStream>(outputPath(".fstat"));
    }
    std::ostream& os = *fstatStream_;
    const Vec3 lo = box_.lo(), hi = box_.hi();
    os << "# time " << fmt(time_) << " step " << step_ << " contacts " << contactsFlat_.size() << '\n';
    os << "# box " << fmt(lo.x) << ' ' << fmt(hi.x) << ' ' << fmt(lo.y) << ' ' << fmt(hi.y) << ' ' << fmt(lo.z) << ' '
       << fmt(hi.z) << " periodic " << box_.periodic(0) << ' ' << box_.periodic(1) << ' ' << box_.periodic(2) << '\n';
    for (const auto& c : contactsFlat_) {
        os << c.i << ' ' << c.j << ' ' << fmt(c.point) << ' ' << fmt(c.overlap) << ' ' << fmt(c.n) << ' ' << fmt(c.fn)
           << ' ' << fmt(c.ft) << ' ' << fmt(c.branch) << ' ' << (c.sliding ? 1 : 0) << '\n';
    }
    os.flush();
}

void DPMBase::finishFiles() {
    if (fstatStream_) {
        fstatStream_->commit();  // InputError naming the file if it cannot be completed; the .tmp is removed
        fstatStream_.reset();
    }
}

} // namespace pdpm
