// OedometerRelaxation: confined (oedometric) compression of a powder with holds at constant piston
// position (stress relaxation, thesis chapter 4) or at constant stress (creep).
// Documentation/driver-oedometer-relaxation.md describes geometry, protocol, time scaling and output.
//
// Run: fill (separate settling simulation, then levelled at the fill height: the FT4 "split"),
// then the protocol steps one after the other. The relaxation physics runs on a lab clock:
// lab time advances by dt * S per DEM step with S = (t0 + t_hold)/hold_tau during holds (log clock;
// or S = time_scale, linear clock) and S = (DEM piston speed)/(lab piston speed) during ramps, so the
// recording's time axis is lab time.
// Header-only so that the self-tests can run the driver in-process. Material presets are in
// OedometerMaterial.h, the per-hold results in OedometerHold.h; the pour is the kernel's
// PourSimulation, the recording format and fits are Tools/Recording.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "Core/DPMBase.h"
#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "IO/Json.h"
#include "IO/NumberFormat.h"
#include "IO/StateFields.h"
#include "Particles/Insertion.h"
#include "OedometerHold.h"
#include "OedometerMaterial.h"
#include "Particles/PourSimulation.h"
#include "Recording.h"

namespace pdpm {

class OedometerRelaxation : public DPMBase {
public:
    OedometerRelaxation() : DPMBase("OedometerRelaxation", "Oedometric compression with relaxation (constant position) and creep (constant stress) holds") {
        auto& p = parameters();
        p.add("geometry", &geometry_, "periodic", "periodic: laterally periodic box; cylinder: mould of diameter D", {"periodic", "cylinder"});
        p.add("device", &device_, "periodic", "device name written to the protocol file (ft4, lambdameter, periodic, ...)");
        p.add("diameter", &diameter_, 0.05, "m", "mould diameter D (cylinder)", Range::positive());
        p.add("width", &width_, 6, "d_mean", "lateral period of the periodic box in mean diameters", Range::atLeast(3));
        p.add("fill_height", &fillHeight_, 6, "d_mean", "height of the levelled bed (periodic: in mean diameters)", Range::positive());
        p.add("fill_height_m", &fillHeightM_, 0, "m", "height of the levelled bed in metres (0: use fill_height)", Range::nonNegative());
        p.add("wall_friction", &muWall_, 0.2, "-", "wall friction mu_w (bottom, piston, mould)", Range::nonNegative());
        p.add("material", &material_, "cocoa", "material preset", {"cocoa", "frictional"});
        p.add("d_mean", &dMean_, 2.5e-3, "m", "mean particle diameter", Range::positive());
        p.add("relax_C", &relaxC_, 0.0792, "-", "relaxation exponent C of Eq. 4.1 (0: off)", Range::nonNegative());
        p.add("relax_t0", &relaxT0_, 0.2894, "s", "relaxation time t0 of Eq. 4.1 (lab seconds)", Range::positive());
        p.add("steps", &stepsText_, "ramp:5e-5:10000,hold:300",
              "protocol: ramp:V:S, hold:T, unload:V:S, creep:T[:S] (V lab m/s, S Pa, T lab s), comma separated");
        p.add("protocol", &protocolPreset_, 0, "-", "Table 4.3 protocol 1-9 (0: use --steps or --protocol_file)", Range::closed(0, 9));
        p.add("protocol_file", &protocolFile_, "", "JSON protocol file (recording format); overrides --steps");
        p.add("max_stress", &maxStress_, 25e3, "Pa", "cap of the preset target stresses (FT4: 22 kPa)", Range::positive());
        p.add("stress_scale", &stressScale_, 1, "-", "multiplies preset target stresses (small tests)", Range::positive());
        p.add("hold_clock", &holdClock_, "log", "lab clock of holds: log (lab time grows exponentially, S = (t0 + t)/hold_tau) or linear (S = time_scale)", {"log", "linear"});
        p.add("hold_tau", &holdTau_, 0.02, "s", "log hold clock: DEM seconds per e-fold of (relax_t0 + lab time in the hold)", Range::positive());
        p.add("hold_settle", &holdSettle_, 1e-4, "-", "a hold's lab clock runs only while E_k/E_p <= this: it starts after the bed settles and pauses during rearrangement events (mechanical motion is instantaneous in lab time; 0: never waits)", Range::nonNegative());
        p.add("hold_settle_max", &holdSettleMax_, 0.05, "s", "longest DEM time a hold's clock waits for settling (at the start and per pause)", Range::nonNegative());
        p.add("time_scale", &timeScale_, 2e3, "lab s / DEM s", "linear hold clock: lab seconds per DEM second", Range::positive());
        p.add("ramp_rate", &rampRate_, 0.5, "1/s", "DEM axial strain rate of ramps and unloads", Range::positive());
        p.add("pour_drag_time", &pourDragTime_, 0.1, "s", "drag time of the particles falling while filling (mass-proportional drag; terminal speed g x this)", Range::positive());
        p.add("approach", &approach_, 0.2, "-", "ramps slow down over this fraction of the target stress", Range::openClosed(0, 1));
        p.add("record_every", &recordEvery_, 100L, "steps", "DEM steps between recorded samples", Range::atLeast(1));
        p.add("dt_fraction", &dtFraction_, 25, "-", "time step = t_c / dt_fraction", Range::atLeast(10));
        p.add("gravity", &gravityOn_, true, "gravity along -z");
        p.add("max_strain", &maxStrain_, 0.5, "-", "a ramp stops (with a warning) at this axial strain", Range::open(0, 0.9));
        // The mould presets hold thousands of particles: they also take the faster numerical settings
        // whose effect on a hold was measured to be small (driver documentation, "Cost").
        p.addPreset("ft4", "FT4 rheometer: cylinder D = H = 50 mm, protocol 1 capped at 22 kPa (faster numerical settings)",
                    {{"geometry", "cylinder"}, {"device", "ft4"}, {"diameter", "0.05"}, {"fill_height_m", "0.05"},
                     {"protocol", "1"}, {"max_stress", "22000"}, {"hold_tau", "0.005"}, {"ramp_rate", "1"}});
        p.addPreset("lambdameter", "lambdameter: cylinder D = 149 mm, H = 60 mm, protocol 1 to 25 kPa (faster numerical settings)",
                    {{"geometry", "cylinder"}, {"device", "lambdameter"}, {"diameter", "0.149"}, {"fill_height_m", "0.06"},
                     {"protocol", "1"}, {"max_stress", "25000"}, {"hold_tau", "0.005"}, {"ramp_rate", "1"}});
        p.set("vtk", "0");
        p.set("restart_output", "0");
        p.set("contact_law", "luding-relax");
        // driver state in restart files (besides the recording and the holds)
        state_.add("pistonZ", pistonZ_).add("pistonZ0", pistonZ0_).add("pistonV", pistonV_).add("labTime", labTime_)
            .add("labScale", labScale_).add("stepLabStart", stepLabStart_).add("rampStartStress", rampStartStress_)
            .add("creepStress", creepStress_).add("solid", solid_).add("fillTime", fillTime_).add("poured", poured_)
            .add("maxInertial", maxInertial_).add("stepIndex", stepIndex_).add("pistonWall", pistonWall_)
            .add("bottomWall", bottomWall_).add("mouldWall", mouldWall_).add("inHold", inHold_)
            .add("settling", settling_).add("settleStart", settleStart_).add("paused", paused_)
            .add("pauseStart", pauseStart_);
    }

    // ---- results (for self-tests) -------------------------------------------------------------
    using HoldResult = OedometerHold;
    const std::vector<HoldResult>& holds() const { return holds_; }
    const recording::Recording& recordingData() const { return rec_; }
    double maxInertialNumber() const { return maxInertial_; }
    std::size_t particleCount() const { return particles().size(); }

protected:
    double area() const {
        return cylinder() ? std::numbers::pi * 0.25 * diameter_ * diameter_ : box().length().x * box().length().y;
    }
    bool cylinder() const { return geometry_ == "cylinder"; }

    /// Protocol steps and material from the parameters (also after a restart, whose file restores
    /// the parameters but not these derived objects).
    void loadProtocolAndMaterial() {
        if (protocolPreset_ > 0 && !protocolFile_.empty())
            inputError("--protocol and --protocol_file are exclusive");
        if (!protocolFile_.empty()) {
            const recording::Protocol pf = recording::readProtocol(protocolFile_);
            steps_ = pf.steps;
        } else if (protocolPreset_ > 0) {
            steps_ = recording::presetSteps(protocolPreset_, maxStress_, stressScale_);
        } else {
            steps_ = recording::parseSteps(stepsText_);
        }
        mat_ = oedometerMaterial(material_, muWall_);
        mat_.dMean = dMean_;
    }

    void setupInitialConditions() override {
        loadProtocolAndMaterial();
        for (ContactParameters* c : {&mat_.pp, &mat_.pw}) {
            c->relaxC = relaxC_;
            c->relaxT0 = relaxT0_;
            c->relaxTimeScale = 0;  // no lab time passes while filling
        }
        const double rMean = 0.5 * dMean_;
        // r_max / r_min = sizeRatio with mean radius rMean (uniform distribution)
        const double rMin = 2 * rMean / (1 + mat_.sizeRatio), rMax = mat_.sizeRatio * rMin;
        const double H = fillHeightM_ > 0 ? fillHeightM_ : fillHeight_ * dMean_;
        double lx = width_ * dMean_;
        double R = 0.5 * diameter_;
        if (cylinder()) lx = diameter_;
        // Particle count: the poured beds settle at a volume fraction of 0.53-0.57 (0.533 in the FT4
        // mould); pour 15 % more than a bed at 0.55 so that the levelling at H (the split) has
        // something to remove (a warning says when the bed ends up below H).
        const double meanR3 = (std::pow(rMax, 4) - std::pow(rMin, 4)) / (4 * (rMax - rMin));
        const double vp = 4.0 / 3.0 * std::numbers::pi * meanR3;
        const double a = cylinder() ? std::numbers::pi * R * R : lx * lx;
        const auto n = static_cast<std::size_t>(std::ceil(1.15 * 0.55 * a * H / vp));
        auto radii = uniformRadii(n, rMin, rMax, random());

        // ---- fill: grid in a tall column, settle under gravity ------------------------------------
        // Settling without adhesion (a dense, reproducible start, like the FT4 conditioning), no relaxation.
        PourSimulation fill(runName() + "_fill");
        fill.dragTime = pourDragTime_;
        fill.setQuiet(quiet());
        setupSpecies(fill, 0, true);
        // staggered grid in a tall column (no vertical stacks), clipped to the mould
        const double s = 2.05 * rMax;
        const std::vector<Vec3> pts = staggeredColumn(n, s, lx, cylinder() ? R : 0.0, 1.02 * rMax);
        setDomainFor(fill, lx, R, pts.back().z + 2 * s);
        fill.addWall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, 1));
        if (cylinder()) fill.addWall(std::make_unique<CylinderWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, R, 0.0, 1));
        std::shuffle(radii.begin(), radii.end(), random());  // uniformRadii sorts them: mix the sizes
        // the column starts at the terminal speed g * pour_drag_time (it would reach it after about a
        // drag time; every particle lands at that speed either way), with a random sideways jitter
        std::uniform_real_distribution<double> U(-1, 1);
        const double vFall = 9.81 * pourDragTime_;
        for (std::size_t k = 0; k < n; ++k)
            fill.addParticle(pts[k], radii[k], 0, Vec3{0.2 * U(random()), 0.2 * U(random()), -vFall});
        fill.setGravity({0, 0, -9.81});
        fill.setTimeStep(fill.minCollisionTime() / dtFraction_);
        fill.setOutput(commonOptions().output, runName() + "_fill");
        fill.pour();
        fillTime_ = fill.time();
        poured_ = static_cast<double>(n);

        // ---- level at H (the FT4 "split") and set up the main simulation ---------------------------
        setupSpecies(*this, relaxC_);
        double top = 0, solid = 0;
        const ParticleData& F = fill.particles();
        for (std::size_t i = 0; i < F.size(); ++i) {
            if (F.x[i].z > H) continue;
            addParticle(F.x[i], F.r[i], 0);
            top = std::max(top, F.x[i].z + F.r[i]);
            solid += 4.0 / 3.0 * std::numbers::pi * std::pow(F.r[i], 3);
        }
        if (particles().size() < 10) inputError("fill produced fewer than 10 particles below the fill height");
        if (particles().size() == n && !quiet())
            std::cerr << "OedometerRelaxation: warning: the poured bed (top " << fmt(top) << " m) did not reach the fill height " << fmt(H) << " m: nothing levelled away\n";
        solid_ = solid;
        setDomainFor(*this, lx, R, top * 1.5 + 4 * rMax);
        addWall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, 1));
        bottomWall_ = 0;
        pistonZ0_ = top;
        pistonZ_ = top;
        auto piston = std::make_unique<PlaneWall>(Vec3{0, 0, top}, Vec3{0, 0, -1}, 1);
        piston->label = "piston";
        pistonWall_ = addWall(std::move(piston));
        if (cylinder()) {
            auto cyl = std::make_unique<CylinderWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, R, 0.0, 1);
            cyl->label = "mould";
            mouldWall_ = static_cast<long>(addWall(std::move(cyl)));
        }
        installPistonMotion();
        if (gravityOn_) setGravity({0, 0, -9.81});
        setTimeStep(minCollisionTime() / dtFraction_);
        setTimeMax(1e30);
        setSaveEvery(1e30);
    }

    void actionsOnRestart() override {
        loadProtocolAndMaterial();
        if (stepIndex_ > steps_.size()) inputError("restart file: protocol step " + std::to_string(stepIndex_) + " beyond the protocol");
        installPistonMotion();
        restarted_ = true;
    }

    void actionsBeforeTimeLoop() override {
        if (restarted_) {
            if (stepIndex_ < steps_.size()) setLabScale(labScale_);
        } else {
            startStep(0);
        }
        if (!quiet())
            std::cout << "OedometerRelaxation: " << particles().size() << " particles, bed height " << fmt(pistonZ0_)
                      << " m, dt " << fmt(timeStep()) << " s, fill took " << fmt(fillTime_) << " s DEM with " << fmt(poured_)
                      << " particles poured\n";
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
                const double span = st.targetStress - rampStartStress_;
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
                setLabScale(std::abs(v) / st.velocity);
                break;
            }
            case recording::Step::Kind::Unload: {
                const double gap = (axialStress() - st.targetStress) / std::max(rampStartStress_, 1.0);
                v = vRamp * approachSpeed(gap);
                setLabScale(std::abs(v) / st.velocity);
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
                    std::cerr << "OedometerRelaxation: warning: ramp " << stepIndex_ << " stopped at the maximal strain\n";
                    done = true;
                }
                break;
            case recording::Step::Kind::Unload: done = sAx <= st.targetStress || pistonZ_ > pistonZ0_; break;
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
        std::cout << "OedometerRelaxation: " << rec_.rows.size() << " samples, lab time " << fmt(labTime_)
                  << " s, max inertial number during ramps " << fmt(maxInertial_) << "\n";
        for (const auto& hr : holds_) hr.print();
    }

    // Restart: the driver's whole state, including the recording and hold curves gathered so far,
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
        if (pistonWall_ >= walls().size() || bottomWall_ >= walls().size()) inputError("restart file: wall indices out of range");
    }

private:
    void setupSpecies(DPMBase& d, double relaxC, bool settling = false) {
        ContactParameters pp = mat_.pp, pw = mat_.pw;
        pp.relaxC = pw.relaxC = relaxC;
        if (settling) pp.kc = 0;
        d.setContactLaw(parameters().get("contact_law"));
        const int a = d.addSpecies(mat_.name, mat_.density, pp);
        const int w = d.addSpecies("wall", mat_.density, pp);
        d.setPairParameters(a, w, pw);
        (void)w;
    }
    void setDomainFor(DPMBase& d, double lx, double R, double zTop) {
        if (cylinder()) d.setDomain({-R, -R, 0}, {R, R, zTop}, false, false, false);
        else d.setDomain({0, 0, 0}, {lx, lx, zTop}, true, true, false);
    }
    void installPistonMotion() {
        const double z0 = pistonZ0Geometry();
        wall(pistonWall_).setMotion(WallMotion::custom([this, z0](double) { return Vec3{0, 0, pistonZ_ - z0}; },
                                                       [this](double) { return Vec3{0, 0, pistonV_}; }));
    }
    double pistonZ0Geometry() const { return pistonZ0_; }
    /// Lab seconds per DEM second during a hold. Log clock: S = (t0 + t)/tau, t = lab time since the
    /// hold began, so that the relaxation rate C/(t0 + t) per lab second becomes C/tau per DEM second,
    /// constant: the hold is as quasi-static at its start as at its end, and a hold of T lab seconds
    /// costs tau ln(1 + T/t0) DEM seconds. Linear clock: S = time_scale.
    double holdScale() const {
        if (holdClock_ == "linear") return timeScale_;
        return (relaxT0_ + (labTime_ - stepLabStart_)) / holdTau_;
    }
    double axialStress() const { return walls()[pistonWall_]->force.z / area(); }
    double bottomStress() const { return -walls()[bottomWall_]->force.z / area(); }
    void setLabScale(double s) {
        labScale_ = s;
        for (int a = 0; a < species().size(); ++a)
            for (int b = 0; b < species().size(); ++b) species().pairMutable(a, b).relaxTimeScale = s;
    }
    void startStep(std::size_t k) {
        stepIndex_ = k;
        const recording::Step& st = steps_[k];
        stepLabStart_ = labTime_;
        rampStartStress_ = axialStress();
        const double vRamp = rampRate_ * pistonZ0_;
        switch (st.kind) {
            case recording::Step::Kind::Ramp:
            case recording::Step::Kind::Unload: setLabScale(vRamp / st.velocity); break;
            case recording::Step::Kind::HoldPosition: setLabScale(0); break;
            case recording::Step::Kind::HoldStress:
                setLabScale(0);
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
        double lateral = 0;
        if (cylinder()) {
            // radial force on the mould over its wetted area pi D h
            double fr = 0;
            for (const auto& c : contacts())
                if (c.j == -1 - mouldWall_) fr += std::abs(c.fn);
            lateral = fr / (std::numbers::pi * diameter_ * h);
        } else {
            double sxx = 0, syy = 0;
            for (const auto& c : contacts()) {
                const Vec3 f = c.fn * c.n + c.ft;
                sxx += f.x * c.branch.x;
                syy += f.y * c.branch.y;
            }
            lateral = 0.5 * (sxx + syy) / (A * h);
        }
        const double ek = kineticEnergy(), ep = elasticEnergy();
        const double ratio = ep > 0 ? ek / ep : 0;
        double inertial = 0;
        if (pistonV_ != 0 && sAx > 0) {
            inertial = std::abs(pistonV_) / h * dMean_ * std::sqrt(mat_.density / sAx);
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
        rec_.comments = {"PowderDPM OedometerRelaxation recording (Documentation/recording-format.md)",
                         "source: simulation; time_s is lab time; dem_time_s is simulation time",
                         "particles: " + std::to_string(particles().size()) + "; relax_C " + fmt(relaxC_) + "; relax_t0 " +
                             fmt(relaxT0_) + " s; hold clock " +
                             (holdClock_ == "linear" ? "linear, " + fmt(timeScale_) + " lab s per DEM s"
                                                     : "log, (t0 + t)/" + fmt(holdTau_) + " lab s per DEM s")};
        recording::writeRecording(outputPath(".recording.csv"), rec_);
        recording::Protocol p;
        p.source = "simulation";
        p.device = device_;
        p.diameter = cylinder() ? diameter_ : 0;
        p.height = pistonZ0_;
        p.wallFriction = muWall_;
        p.material = Json::object({{"name", mat_.name},
                                   {"density_kg_m3", mat_.density},
                                   {"d_mean_m", dMean_},
                                   {"r_max_over_r_min", mat_.sizeRatio},
                                   {"contact_law", parameters().get("contact_law")},
                                   {"k_N_m", mat_.pp.k},
                                   {"k1_N_m", mat_.pp.k1},
                                   {"kc_N_m", mat_.pp.kc},
                                   {"phi_f", mat_.pp.phiF},
                                   {"mu", mat_.pp.muS},
                                   {"mu_r", mat_.pp.muR},
                                   {"relax_C", relaxC_},
                                   {"relax_t0_s", relaxT0_}});
        p.steps = steps_;
        Json extra = Json::object();
        extra.set("particles", static_cast<double>(particles().size()));
        extra.set("geometry", geometry_);
        extra.set("lateral_period_m", cylinder() ? 0.0 : box().length().x);
        extra.set("hold_clock", holdClock_);
        if (holdClock_ == "linear") extra.set("time_scale_hold_lab_s_per_dem_s", timeScale_);
        else extra.set("hold_tau_dem_s", holdTau_);
        extra.set("ramp_dem_strain_rate_1_s", rampRate_);
        extra.set("dt_s", timeStep());
        extra.set("max_inertial_number_ramps", maxInertial_);
        Json hj = Json::array();
        for (const auto& hr : holds_) {
            hj.push(hr.json());
        }
        extra.set("holds", hj);
        p.extra = extra;
        recording::writeProtocol(outputPath(".protocol.json"), p);
    }

    // parameters
    std::string geometry_, device_, material_, stepsText_, protocolFile_, holdClock_;
    double diameter_ = 0, width_ = 0, fillHeight_ = 0, fillHeightM_ = 0, muWall_ = 0, dMean_ = 0, relaxC_ = 0, relaxT0_ = 0;
    double holdTau_ = 0.02, pourDragTime_ = 0.1, approach_ = 0.2, maxStress_ = 0, stressScale_ = 1, timeScale_ = 0, rampRate_ = 0, dtFraction_ = 25, maxStrain_ = 0.5;
    int protocolPreset_ = 0;
    long recordEvery_ = 100;
    bool gravityOn_ = true;
    // state
    OedometerMaterial mat_;
    std::vector<recording::Step> steps_;
    std::size_t stepIndex_ = 0, pistonWall_ = 0, bottomWall_ = 0;
    long mouldWall_ = -1;
    double pistonZ_ = 0, pistonZ0_ = 0, pistonV_ = 0, labTime_ = 0, labScale_ = 0, stepLabStart_ = 0, creepStress_ = 1;
    double rampStartStress_ = 0;
    double solid_ = 0, fillTime_ = 0, poured_ = 0, maxInertial_ = 0;
    bool inHold_ = false, restarted_ = false, settling_ = false, paused_ = false;
    double holdSettle_ = 1e-4, holdSettleMax_ = 0.05, settleStart_ = 0, pauseStart_ = 0;
    std::vector<HoldResult> holds_;
    StateFields state_;
    recording::Recording rec_;
};

} // namespace pdpm
