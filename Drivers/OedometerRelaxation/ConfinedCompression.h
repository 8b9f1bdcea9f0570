// ConfinedCompression: the test machine of the OedometerRelaxation driver. A bed confined below a
// flat piston runs a protocol of steps (recording format, Tools/Recording): ramp the piston down to a
// stress, hold its position, unload to a stress, hold the stress (creep). It keeps the lab clock
// that the slow relaxation physics runs on, the per-hold statistics (OedometerHold.h) and the
// recording, writes RUN.recording.csv and RUN.protocol.json, and saves all of it in restart files.
//
// Lab clock: lab time advances by dt * S per DEM step, with S = (t0 + t_hold)/hold_tau during holds
// (log clock; or S = time_scale, linear clock) and S = (DEM piston speed)/(lab piston speed) during
// ramps, so the recording's time axis is lab time (Documentation/driver-oedometer-relaxation.md,
// "Time scaling"). A hold's clock starts after the bed has settled and stands still during
// rearrangement events (E_k/E_p above hold_settle).
//
// A subclass builds the bed in setupInitialConditions() and sets: the bottom and piston walls
// (bottomWall_, pistonWall_), the piston's start height (pistonZ0_ = pistonZ_, then
// installPistonMotion()), the solid volume solid_, grainDensity_ and grainSize_ (inertial number and
// the --ramp_rate bound; grainSize_ is not in the restart file: set it again in actionsOnRestart());
// it gives the loaded area, the lateral stress and the run's description for the protocol file.
#pragma once
#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "Core/DPMBase.h"
#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "IO/Json.h"
#include "IO/NumberFormat.h"
#include "IO/StateFields.h"
#include "OedometerHold.h"
#include "Recording.h"

namespace pdpm {

class ConfinedCompression : public DPMBase {
public:
    ConfinedCompression(const std::string& name, const std::string& description) : DPMBase(name, description) {
        auto& p = parameters();
        p.add("relax_C", &relaxC_, 0.0792, "-", "relaxation exponent C of Eq. 4.1 (0: off)", Range::nonNegative());
        p.add("relax_t0", &relaxT0_, 0.2894, "s", "relaxation time t0 of Eq. 4.1 (lab seconds)", Range::positive());
        p.add("relax_in_ramps", &relaxInRamps_, true, "contacts relax during ramps and unloads too (1), or their relaxation clocks stand still there (0: every contact loaded by a ramp starts the following hold at clock 0, the assumption under which Eq. 4.3 is fitted to a hold; lab time still runs)");
        p.add("relax_memory", &relaxMemory_, 0, "-", "relaxation clock memory m: a load increase f_ref -> f shortens a contact's clock by (f_ref/f)^(1/m) (0: restarts it)", Range::nonNegative());
        p.add("steps", &stepsText_, "ramp:5e-5:10000,hold:300",
              "protocol: ramp:V:S, hold:T, unload:V:S, creep:T[:S] (V lab m/s, S Pa, T lab s), comma separated");
        p.add("protocol", &protocolPreset_, 0, "-", "Table 4.3 protocol 1-9 (0: use --steps or --protocol_file)", Range::closed(0, 9));
        p.add("protocol_file", &protocolFile_, "", "JSON protocol file (recording format); overrides --steps");
        p.add("max_stress", &maxStress_, 25e3, "Pa", "cap of the preset target stresses (FT4: 22 kPa)", Range::positive());
        p.add("stress_scale", &stressScale_, 1, "-", "multiplies the protocol's target stresses (preset, --steps or --protocol_file; small tests, or a lab protocol brought into the material's stress range)", Range::positive());
        p.add("hold_clock", &holdClock_, "log", "lab clock of holds: log (lab time grows exponentially, S = (t0 + t)/hold_tau) or linear (S = time_scale)", {"log", "linear"});
        p.add("hold_tau", &holdTau_, 0.02, "s", "log hold clock: DEM seconds per e-fold of (relax_t0 + lab time in the hold)", Range::positive());
        p.add("hold_settle", &holdSettle_, 1e-4, "-", "a hold's lab clock runs only while E_k/E_p <= this: it starts after the bed settles and pauses during rearrangement events (mechanical motion is instantaneous in lab time; 0: never waits)", Range::nonNegative());
        p.add("hold_settle_max", &holdSettleMax_, 0.05, "s", "longest DEM time a hold's clock waits for settling (at the start and per pause)", Range::nonNegative());
        p.add("time_scale", &timeScale_, 2e3, "lab s / DEM s", "linear hold clock: lab seconds per DEM second", Range::positive());
        p.add("ramp_rate", &rampRate_, 0.5, "1/s", "DEM axial strain rate of ramps and unloads", Range::positive());
        p.add("approach", &approach_, 0.2, "-", "ramps slow down over this fraction of the target stress", Range::openClosed(0, 1));
        p.add("record_every", &recordEvery_, 100L, "steps", "DEM steps between recorded samples", Range::atLeast(1));
        p.add("max_strain", &maxStrain_, 0.5, "-", "a ramp stops (with a warning) at this axial strain", Range::open(0, 0.9));
        // machine state in restart files (besides the recording and the holds)
        state_.add("pistonZ", pistonZ_).add("pistonZ0", pistonZ0_).add("pistonV", pistonV_).add("labTime", labTime_)
            .add("labScale", labScale_).add("stepLabStart", stepLabStart_).add("rampStartStress", rampStartStress_)
            .add("creepStress", creepStress_).add("solid", solid_).add("maxInertial", maxInertial_)
            .add("stepIndex", stepIndex_).add("pistonWall", pistonWall_).add("bottomWall", bottomWall_)
            .add("inHold", inHold_).add("settling", settling_).add("settleStart", settleStart_)
            .add("paused", paused_).add("pauseStart", pauseStart_);
    }

    // ---- results (for self-tests) -------------------------------------------------------------
    using HoldResult = OedometerHold;
    const std::vector<HoldResult>& holds() const { return holds_; }
    const recording::Recording& recordingData() const { return rec_; }
    double maxInertialNumber() const { return maxInertial_; }
    std::size_t particleCount() const { return particles().size(); }

protected:
    // ---- what the subclass provides -----------------------------------------------------------
    /// Loaded cross-section of the bed (m^2).
    virtual double area() const = 0;
    /// Lateral stress at the current piston height h (Pa).
    virtual double lateralStress(double h) const = 0;
    /// Device, geometry and material of the run for the protocol file (and its "extra" object).
    virtual void describe(recording::Protocol& p, Json& extra) const = 0;

    /// Protocol steps from the parameters (also after a restart, whose file restores the parameters
    /// but not the steps).
    void loadProtocol() {
        if (protocolPreset_ > 0 && !protocolFile_.empty()) inputError("--protocol and --protocol_file are exclusive");
        if (!protocolFile_.empty()) steps_ = recording::readProtocol(protocolFile_).steps;
        else if (protocolPreset_ > 0) steps_ = recording::presetSteps(protocolPreset_, maxStress_);
        else steps_ = recording::parseSteps(stepsText_);
        for (recording::Step& st : steps_) {
            st.targetStress *= stressScale_;
            if (st.stress > 0) st.stress *= stressScale_;  // creep at a given stress (negative: the stress reached)
        }
    }
    void installPistonMotion() {
        const double z0 = pistonZ0_;
        wall(pistonWall_).setMotion(WallMotion::custom([this, z0](double) { return Vec3{0, 0, pistonZ_ - z0}; },
                                                       [this](double) { return Vec3{0, 0, pistonV_}; }));
    }
    double axialStress() const { return walls()[pistonWall_]->force.z / area(); }
    /// No particle touches the piston (every contact adds force, so an exactly zero force is no contact).
    bool liftedOff() const { const Vec3& f = walls()[pistonWall_]->force; return f.x == 0 && f.y == 0 && f.z == 0; }
    double bottomStress() const { return -walls()[bottomWall_]->force.z / area(); }

    void actionsOnRestart() override {
        loadProtocol();
        if (stepIndex_ > steps_.size()) inputError("restart file: protocol step " + std::to_string(stepIndex_) + " beyond the protocol");
        // the lab clock cannot be ahead of the protocol so far: a hold adds its duration and at most
        // one more step of its clock (linear: time_scale dt; log: (t0 + duration) dt / hold_tau), a
        // ramp or unload at most the piston's whole travel (pistonZ0) at its lab speed; the check
        // allows twice that
        double labBound = 0;
        for (std::size_t k = 0; k <= stepIndex_ && k < steps_.size(); ++k) {
            const recording::Step& st = steps_[k];
            const bool moves = st.kind == recording::Step::Kind::Ramp || st.kind == recording::Step::Kind::Unload;
            const double lastStep = std::max(timeScale_, (relaxT0_ + st.duration) / holdTau_) * timeStep();
            labBound += moves ? pistonZ0_ / st.velocity : st.duration + lastStep;
        }
        if (!(labTime_ <= 2 * labBound))
            inputError("restart file: lab clock " + fmt(labTime_) + " s ahead of what protocol steps 0 to " + std::to_string(stepIndex_) +
                       " can take (at most " + fmt(labBound) + " s)");
        installPistonMotion();
        restarted_ = true;
    }

    void actionsBeforeTimeLoop() override {
        // a piston that moves a sizeable part of a grain per step crushes the top layer in one step
        // (and ran into NaN with only a warning before); the default ramp moves ~1e-6 of a grain
        const double perStep = rampRate_ * pistonZ0_ * timeStep();
        if (!(perStep <= kMaxPistonStepPerGrain * grainSize_))
            inputError("--ramp_rate " + fmt(rampRate_) + " 1/s moves the piston " + fmt(perStep) + " m per time step, more than " +
                       fmt(kMaxPistonStepPerGrain) + " of the grain size " + fmt(grainSize_) + " m");
        if (restarted_) {
            if (stepIndex_ < steps_.size()) setLabScale(labScale_, relaxes(steps_[stepIndex_]));
        } else {
            startStep(0);
        }
    }

    bool continueSolve() const override { return stepIndex_ < steps_.size(); }

    /// Progress: completed protocol steps plus the fraction of the current one (hold: lab time,
    /// ramp/unload: stress change).
    double progressFraction() const override {
        if (steps_.empty()) return 1;
        if (stepIndex_ >= steps_.size()) return 1;
        const recording::Step& st = steps_[stepIndex_];
        double inner = 0;
        switch (st.kind) {
            case recording::Step::Kind::Ramp:
            case recording::Step::Kind::Unload: {
                // (an unload into tension counts to zero force: its end, the tension or lift-off, is not known ahead)
                const double span = std::max(st.targetStress, 0.0) - rampStartStress_;
                inner = std::abs(span) > 0 ? (axialStress() - rampStartStress_) / span : 0;
                break;
            }
            case recording::Step::Kind::HoldPosition:
            case recording::Step::Kind::HoldStress: {
                const double t = labTime_ - stepLabStart_;
                if (holdClock_ == "linear") inner = st.duration > 0 ? t / st.duration : 1;
                else inner = std::log1p(t / relaxT0_) / std::log1p(st.duration / relaxT0_);  // DEM time fraction
                break;
            }
        }
        return (static_cast<double>(stepIndex_) + std::clamp(inner, 0.0, 1.0)) / static_cast<double>(steps_.size());
    }

    static constexpr double kMinApproachSpeed = 0.05;
    /// Piston speed as a fraction of the ramp speed for the remaining relative stress gap.
    double approachSpeed(double gap) const { return std::clamp(std::sqrt(std::max(gap, 0.0) / approach_), kMinApproachSpeed, 1.0); }

    void actionsBeforeTimeStep() override {
        const double dt = timeStep();
        const recording::Step& st = steps_[stepIndex_];
        double v = 0;  // piston velocity along z (negative: down)
        const double h = pistonZ_;
        const double vRamp = rampRate_ * pistonZ0_;
        switch (st.kind) {
            // Ramps brake over the last `approach` fraction of the target stress so that the piston
            // stops quasi-statically: speed ~ sqrt(remaining gap), a constant deceleration in stress
            // that reaches the target in finite time (a speed proportional to the gap approaches it
            // exponentially and spent 80 % of a ramp in the tail), never below kMinApproachSpeed of
            // the ramp speed (E_k ~ speed^2: 0.25 % of the ramp's kinetic energy at the stop). The
            // lab clock follows the speed.
            case recording::Step::Kind::Ramp: {
                const double gap = (st.targetStress - axialStress()) / std::max(st.targetStress, 1.0);
                v = -vRamp * approachSpeed(gap);
                setLabScale(std::abs(v) / st.velocity, relaxes(st));
                break;
            }
            case recording::Step::Kind::Unload: {
                const double gap = (axialStress() - st.targetStress) / std::max(rampStartStress_, 1.0);
                v = vRamp * approachSpeed(gap);
                setLabScale(std::abs(v) / st.velocity, relaxes(st));
                break;
            }
            case recording::Step::Kind::HoldPosition:
                v = 0;
                setLabScale(settling_ || paused_ ? 0.0 : holdScale());
                break;
            case recording::Step::Kind::HoldStress: {
                setLabScale(settling_ || paused_ ? 0.0 : holdScale());
                const double err = (creepStress_ - axialStress()) / creepStress_;
                v = -vRamp * std::clamp(5 * err, -1.0, 1.0);
                break;
            }
        }
        pistonV_ = v;
        pistonZ_ = h + v * dt;
        labTime_ += dt * labScale_;
        if ((step() + 1) % recordEvery_ == 0) requestContacts();  // records of the step about to be made
    }

    void actionsAfterTimeStep() override {
        const recording::Step& st = steps_[stepIndex_];
        const double sAx = axialStress();
        const double strain = (pistonZ0_ - pistonZ_) / pistonZ0_;
        bool done = false;
        switch (st.kind) {
            case recording::Step::Kind::Ramp:
                done = sAx >= st.targetStress;
                if (strain > maxStrain_) {
                    std::cerr << programName() << ": warning: ramp " << stepIndex_ << " stopped at the maximal strain\n";
                    done = true;
                }
                break;
            case recording::Step::Kind::Unload:
                // an unload into tension (negative target, adhesive walls) also ends at lift-off: the
                // piston touches no particle any more (its force is exactly zero)
                done = sAx <= st.targetStress || pistonZ_ > pistonZ0_ || (st.targetStress < 0 && liftedOff());
                break;
            case recording::Step::Kind::HoldPosition:
            case recording::Step::Kind::HoldStress: done = labTime_ - stepLabStart_ >= st.duration - 1e-9 * st.duration; break;
        }
        const bool recordNow = (step() % recordEvery_ == 0) || done;
        if (recordNow) record(done);
        if (done) {
            finishStep();
            if (stepIndex_ + 1 < steps_.size()) startStep(stepIndex_ + 1);
            else stepIndex_ = steps_.size();
        }
    }

    void actionsAfterSolve() override {
        writeOutputs();
        if (quiet()) return;
        std::cout << programName() << ": " << rec_.rows.size() << " samples, lab time " << fmt(labTime_)
                  << " s, max inertial number during ramps " << fmt(maxInertial_) << "\n";
        for (const auto& hr : holds_) hr.print();
    }

    // Restart: the machine's whole state, including the recording and hold curves gathered so far,
    // so that a restarted run writes the same files as a straight one.
    void saveDriverState(std::vector<std::pair<std::string, std::string>>& kv) const override {
        state_.save(kv);
        std::string cols;
        for (const auto& c : rec_.columns) {
            if (!cols.empty()) cols += ' ';
            cols += c;
        }
        kv.emplace_back("recColumns", cols.empty() ? "-" : cols);
        for (const auto& row : rec_.rows) kv.emplace_back("recRow", joinNumbers(row));
        for (const auto& h : holds_) {
            kv.emplace_back("hold", joinNumbers(h.numbers()));
            kv.emplace_back("holdT", joinNumbers(h.t));
            kv.emplace_back("holdS", joinNumbers(h.s));
        }
    }
    void loadDriverState(const std::vector<std::pair<std::string, std::string>>& kv) override {
        state_.requireAll(kv);
        requireDriverKeys(kv, {"recColumns"});
        rec_ = recording::Recording{};
        holds_.clear();
        for (const auto& [k, v] : kv) {
            if (state_.load(k, v)) continue;
            if (k == "recColumns") {
                std::istringstream is(v);
                for (std::string c; is >> c;)
                    if (c != "-") rec_.columns.push_back(c);
            } else if (k == "recRow") rec_.rows.push_back(splitNumbers(v, k));
            else if (k == "hold") {
                holds_.push_back(OedometerHold::fromNumbers(splitNumbers(v, k)));
            } else if (k == "holdT" || k == "holdS") {
                if (holds_.empty()) inputError("restart file: hold samples before their hold");
                (k == "holdT" ? holds_.back().t : holds_.back().s) = splitNumbers(v, k);
            }
        }
        if (pistonWall_ >= walls().size() || bottomWall_ >= walls().size() || pistonWall_ == bottomWall_)
            inputError("restart file: wall indices out of range");
        // what a straight run can have been in: rows as wide as the header, paired hold samples, a
        // running hold clock with at least its first sample, a lab clock that never runs backwards
        for (const auto& row : rec_.rows)
            if (row.size() != rec_.columns.size()) inputError("restart file: a recRow does not match recColumns");
        for (const auto& h : holds_)
            if (h.t.size() != h.s.size()) inputError("restart file: holdT and holdS differ in length");
        if (inHold_ && (holds_.empty() || (!settling_ && holds_.back().t.empty())))
            inputError("restart file: a hold in progress without its samples");
        if (labScale_ < 0 || pistonZ0_ <= 0 || pistonZ_ <= 0) inputError("restart file: invalid piston or lab clock state");
        // the piston wall is where pistonZ puts it (its motion is pistonZ - pistonZ0 from the start height)
        if (!(std::abs(walls()[pistonWall_]->offset().z - (pistonZ_ - pistonZ0_)) <= 1e-9 * pistonZ0_))
            inputError("restart file: pistonZ " + fmt(pistonZ_) + " m does not match the piston wall's displacement " +
                       fmt(walls()[pistonWall_]->offset().z) + " m from pistonZ0 " + fmt(pistonZ0_) + " m");
        // the lab clock starts at 0 and only runs forward: the current step began, and every sample was
        // taken, at or before the clock's time
        if (!(labTime_ >= 0) || !(stepLabStart_ >= 0 && stepLabStart_ <= labTime_) ||
            (!rec_.rows.empty() && !rec_.rows.back().empty() && !(rec_.rows.back()[0] <= labTime_)))
            inputError("restart file: lab clock " + fmt(labTime_) + " s behind its step start (" + fmt(stepLabStart_) +
                       " s) or its last sample, or negative");
    }

    // parameters and state a subclass reads or sets
    double relaxC_ = 0, relaxT0_ = 0, relaxMemory_ = 0;
    std::size_t pistonWall_ = 0, bottomWall_ = 0;
    double pistonZ_ = 0, pistonZ0_ = 0;
    double solid_ = 0, grainDensity_ = 0, grainSize_ = 0;
    static constexpr double kMaxPistonStepPerGrain = 0.05;  ///< the --ramp_rate bound, per time step
    StateFields state_;  ///< scalar state in restart files: a subclass adds its own fields

private:
    /// Lab seconds per DEM second during a hold. Log clock: S = (t0 + t)/tau, t = lab time since the
    /// hold began, so that the relaxation rate C/(t0 + t) per lab second becomes C/tau per DEM second,
    /// constant: the hold is as quasi-static at its start as at its end, and a hold of T lab seconds
    /// costs tau ln(1 + T/t0) DEM seconds. Linear clock: S = time_scale.
    double holdScale() const {
        if (holdClock_ == "linear") return timeScale_;
        return (relaxT0_ + (labTime_ - stepLabStart_)) / holdTau_;
    }
    /// Lab seconds per DEM second of the recording's clock and the contacts' viscous branches (s) and
    /// of the contacts' relaxation clocks (s, or 0 where the step does not relax).
    void setLabScale(double s, bool relaxing = true) {
        labScale_ = s;
        for (int a = 0; a < species().size(); ++a)
            for (int b = 0; b < species().size(); ++b) {
                ContactParameters& c = species().pairMutable(a, b);
                c.relaxTimeScale = relaxing ? s : 0.0;
                c.viscTimeScale = s;
            }
    }
    /// Whether contacts relax during a step: always in holds, in ramps and unloads with relax_in_ramps.
    bool relaxes(const recording::Step& st) const {
        const bool moving = st.kind == recording::Step::Kind::Ramp || st.kind == recording::Step::Kind::Unload;
        return !moving || relaxInRamps_;
    }
    void startStep(std::size_t k) {
        stepIndex_ = k;
        const recording::Step& st = steps_[k];
        stepLabStart_ = labTime_;
        rampStartStress_ = axialStress();
        const double vRamp = rampRate_ * pistonZ0_;
        switch (st.kind) {
            case recording::Step::Kind::Ramp:
            case recording::Step::Kind::Unload: setLabScale(vRamp / st.velocity, relaxes(st)); break;
            case recording::Step::Kind::HoldPosition: setLabScale(0); break;
            case recording::Step::Kind::HoldStress:
                setLabScale(0);
                // a creep at the stress reached needs a compressive one (not after an unload into tension)
                if (st.stress < 0 && axialStress() <= 0)
                    inputError("protocol step " + std::to_string(k) + ": a creep at the stress reached, but the stress is " +
                               fmt(axialStress()) + " Pa (not compressive, e.g. after an unload into tension); give its stress (creep:T:S)");
                creepStress_ = st.stress >= 0 ? st.stress : std::max(axialStress(), 1.0);
                break;
        }
        if (st.kind == recording::Step::Kind::HoldPosition || st.kind == recording::Step::Kind::HoldStress) {
            HoldResult hr;
            hr.step = static_cast<int>(k);
            hr.creep = st.kind == recording::Step::Kind::HoldStress;
            holds_.push_back(hr);
            inHold_ = true;
            settling_ = true;
            paused_ = false;
            settleStart_ = time();
            if (holdSettle_ <= 0) startHoldClock();
        } else {
            inHold_ = false;
            settling_ = false;
            paused_ = false;
        }
    }
    /// The hold's clock starts (after the mechanical settling): Eq. 4.3's f_max is the stress now.
    void startHoldClock() {
        HoldResult& hr = holds_.back();
        settling_ = false;
        hr.settleDem = time() - settleStart_;
        hr.labStart = labTime_;
        hr.stressStart = axialStress();
        hr.strainStart = (pistonZ0_ - pistonZ_) / pistonZ0_;
        hr.t.assign(1, labTime_);
        hr.s.assign(1, hr.stressStart);
    }
    void finishStep() {
        if (!inHold_) return;
        if (settling_) startHoldClock();
        HoldResult& hr = holds_.back();
        hr.labDuration = labTime_ - hr.labStart;
        hr.stressEnd = axialStress();
        hr.strainEnd = (pistonZ0_ - pistonZ_) / pistonZ0_;
        if (!hr.creep) hr.fit = recording::fitRelaxation(hr.t, hr.s);
        inHold_ = false;
    }
    void record(bool force) {
        if (force && !contactsAreCurrent()) refreshContacts();  // a step ended between record steps
        const double A = area();
        const double h = pistonZ_;
        const double sAx = axialStress();
        const double lateral = lateralStress(h);
        const double ek = kineticEnergy(), ep = elasticEnergy();
        const double ratio = ep > 0 ? ek / ep : 0;
        double inertial = 0;
        if (pistonV_ != 0 && sAx > 0) {
            inertial = std::abs(pistonV_) / h * grainSize_ * std::sqrt(grainDensity_ / sAx);
            if (!inHold_ && (steps_[stepIndex_].kind == recording::Step::Kind::Ramp)) maxInertial_ = std::max(maxInertial_, inertial);
        }
        if (inHold_ && settling_ && (ratio <= holdSettle_ || time() - settleStart_ >= holdSettleMax_)) startHoldClock();
        if (inHold_ && !settling_) {
            HoldResult& hr = holds_.back();
            hr.maxEkEp = std::max(hr.maxEkEp, ratio);
            if (!paused_) {
                // the state reached while the clock ran: a sample above the threshold is a
                // rearrangement event, and the clock stands still until the bed has settled again
                ++hr.samples;
                if (ratio > 1e-4) ++hr.samplesAbove;
                if (holdSettle_ > 0 && ratio > holdSettle_ && !force) {
                    paused_ = true;
                    pauseStart_ = time();
                    ++hr.pauses;
                }
            } else if (ratio <= holdSettle_ || time() - pauseStart_ >= holdSettleMax_ || force) {
                if (ratio > holdSettle_) ++hr.forcedResumes;
                hr.pauseDem += time() - pauseStart_;
                paused_ = false;
            }
            if (labTime_ > hr.t.back()) {
                hr.t.push_back(labTime_);
                hr.s.push_back(sAx);
            }
        }
        // one row per lab time (time_s strictly increasing): while the clock stands still (settling at
        // the start of a hold) no rows are added
        if (!rec_.rows.empty() && !(labTime_ > rec_.rows.back()[0])) return;
        if (rec_.columns.empty())
            rec_.columns = {"time_s", "step", "piston_position_m", "axial_strain", "axial_stress_Pa", "bottom_stress_Pa",
                            "lateral_stress_Pa", "volume_fraction", "Ek_over_Ep", "inertial_number", "dem_time_s"};
        rec_.rows.push_back({labTime_, static_cast<double>(stepIndex_), h, (pistonZ0_ - h) / pistonZ0_, sAx, bottomStress(),
                             lateral, solid_ / (A * h), ratio, inertial, time()});
    }
    void writeOutputs() {
        ensureDirectory(commonOptions().output);
        rec_.comments = {"PowderDPM " + programName() + " recording (Documentation/recording-format.md)",
                         "source: simulation; time_s is lab time; dem_time_s is simulation time",
                         "particles: " + std::to_string(particles().size()) + "; relax_C " + fmt(relaxC_) + "; relax_t0 " +
                             fmt(relaxT0_) + " s" + (relaxMemory_ > 0 ? "; relax_memory " + fmt(relaxMemory_) : "") +
                             (relaxInRamps_ ? "" : "; no relaxation in ramps") + "; hold clock " +
                             (holdClock_ == "linear" ? "linear, " + fmt(timeScale_) + " lab s per DEM s"
                                                     : "log, (t0 + t)/" + fmt(holdTau_) + " lab s per DEM s")};
        recording::writeRecording(outputPath(".recording.csv"), rec_);
        recording::Protocol p;
        p.source = "simulation";
        p.height = pistonZ0_;
        p.steps = steps_;
        Json extra = Json::object();
        describe(p, extra);
        extra.set("hold_clock", holdClock_);
        if (holdClock_ == "linear") extra.set("time_scale_hold_lab_s_per_dem_s", timeScale_);
        else extra.set("hold_tau_dem_s", holdTau_);
        extra.set("ramp_dem_strain_rate_1_s", rampRate_);
        extra.set("dt_s", timeStep());
        extra.set("max_inertial_number_ramps", maxInertial_);
        Json hj = Json::array();
        for (const auto& hr : holds_) hj.push(hr.json());
        extra.set("holds", hj);
        p.extra = extra;
        recording::writeProtocol(outputPath(".protocol.json"), p);
    }

    // parameters
    std::string stepsText_, protocolFile_, holdClock_;
    double holdTau_ = 0.02, approach_ = 0.2, maxStress_ = 0, stressScale_ = 1, timeScale_ = 0, rampRate_ = 0, maxStrain_ = 0.5;
    double holdSettle_ = 1e-4, holdSettleMax_ = 0.05;
    int protocolPreset_ = 0;
    long recordEvery_ = 100;
    // state
    std::vector<recording::Step> steps_;
    std::size_t stepIndex_ = 0;
    double pistonV_ = 0, labTime_ = 0, labScale_ = 0, stepLabStart_ = 0, creepStress_ = 1, rampStartStress_ = 0;
    double maxInertial_ = 0, settleStart_ = 0, pauseStart_ = 0;
    bool relaxInRamps_ = true;
    bool inHold_ = false, restarted_ = false, settling_ = false, paused_ = false;
    std::vector<HoldResult> holds_;
    recording::Recording rec_;
};

} // namespace pdpm
