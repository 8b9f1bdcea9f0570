// Internal to pdpm-explain's DEM confirmation (DemConfirmation.h has the method and the public
// interface): the lab holds and branches, the DEM runs' records, the shared set-up of the runs
// (DemContext), and each mechanism's confirmation (DemHoldConfirmations.cc: contact_relaxation and
// rate_dependence, calibrated on holds; DemBranchConfirmations.cc: plasticity, wall_friction, cohesion
// and stiffness_nonlinearity, calibrated on unload/reload branches).
#pragma once
#include <chrono>
#include <cstdlib>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "DemConfirmation.h"
#include "ExplainData.h"

namespace pdpm::explain::dem {

/// One hold of the lab recording: time since its start and stress.
struct LabHold {
    std::vector<double> t, s;
    double s0 = 0, tStart = 0;  ///< tStart: recording time of the hold's first sample
};

/// Hold curves of a DEM run, normalised: g(t) = sigma(t)/sigma(0), t from the clock start.
struct DemHold {
    std::vector<double> t, g;
    double fitC = -1, fitT0 = -1;  ///< the driver's Eq. 4.3 fit of the hold (-1: none)
};

double interpolate(const DemHold& h, double t);

std::vector<DemHold> readDemHolds(const std::string& base);

/// DEM prediction of sample i of lab hold k.
double holdPredict(const std::vector<LabHold>& lab, const std::vector<DemHold>& dem, std::size_t k, std::size_t i);

/// RMSE (Pa) of the DEM prediction over the lab holds with index in `which`.
double holdRmse(const std::vector<LabHold>& lab, const std::vector<DemHold>& dem, const std::vector<std::size_t>& which);

/// One compared lab sample: the item (hold or branch), whether it was held out, the abscissa of the
/// figure (recording time or strain), the lab stress and each run's prediction.
struct Compared {
    std::size_t item = 0;
    bool heldout = false;
    double x = 0, lab = 0;
    std::vector<double> pred;
};

/// DIR/comparison.csv and, with gnuplot, DIR/comparison.png: the lab samples the DEM runs were
/// scored on, with every run's prediction (baseline, a, b; the chosen run in the figure's title).
void writeComparison(const std::string& dir, const std::vector<Compared>& rows, const DemResult& d, const std::string& xName,
                     const std::string& xLabel, bool figures);

/// One branch below the largest strain (an unload, or the reload that follows it), in the
/// coordinates of its reference point (strain e_ref and stress s_ref where the unload began, loading
/// tangent E_load before it): u = (e_ref - e) E_load / s_ref, y = s / s_ref. A linear elastic
/// material unloads along y = 1 - u; one whose unloading is lambda times stiffer along y = 1 - lambda u.
struct Branch {
    Phase phase = Phase::Unload;
    double sRef = 0;
    std::vector<double> u, y, s, e;  ///< s, e: stress (Pa) and strain of the samples
    std::vector<double> b;           ///< bottom stress (Pa) of the samples, when recorded
};

/// Least-squares slope of y against x over [i0, i1).
double slope(const std::vector<double>& x, const std::vector<double>& y, std::size_t i0, std::size_t i1);

/// Unload and reload branches of a record, in order (holds are not branches). The reference is
/// taken where an unload follows a loading (holds in between ignored) and kept for the unloads and
/// reloads after it until the next loading; branches without a usable reference (no loading of at
/// least 3 samples before them, a non-positive stress or loading tangent at the start) are skipped.
std::vector<Branch> cycleBranches(const std::vector<double>& t, const std::vector<double>& e, const std::vector<double>& s,
                                  const std::vector<double>& bottom = {});

/// Whether a DEM run's branches pair with the lab's: the same number, the same phase at each index.
bool samePhases(const std::vector<Branch>& lab, const std::vector<Branch>& dem);

/// The branch as a function y(u): samples sorted by u (linear interpolation, constant outside).
double branchAt(const std::vector<std::pair<double, double>>& uy, double u);

/// What a DEM branch predicts of a lab branch.
enum class BranchJudge {
    Stress,        ///< s_pred = s_ref,lab * y_DEM(u_lab): the branch where it lies on the u scale
    BottomStress,  ///< b_pred = s_ref,lab * (b / s_ref)_DEM(u_lab): the bottom sensor's stress
    /// the branch's shape from its own first sample: s_pred = s_lab,0 + s_ref,lab * (y_DEM(u_DEM,0 + u_lab
    /// - u_lab,0) - y_DEM(u_DEM,0)). A reload begins where its unload ended (a calibration sample), so
    /// this judges how the reload climbs, not where in strain the unload of another bed ended.
    StressFromStart,
};

/// DEM predictions of every sample of lab branch k by `judge` (BottomStress: empty when a record
/// lacks the bottom stress).
std::vector<double> branchPredict(const std::vector<Branch>& lab, const std::vector<Branch>& dem, std::size_t k,
                                  BranchJudge judge = BranchJudge::Stress);

/// RMSE (Pa) of the DEM branches predicting the lab branches with index in `which` (BottomStress:
/// their bottom stress; -1 when a record lacks it).
double branchRmse(const std::vector<Branch>& lab, const std::vector<Branch>& dem, const std::vector<std::size_t>& which,
                  BranchJudge judge = BranchJudge::Stress);

/// Unloading stiffness over loading tangent measured on the unload branches in `which`: the slope
/// lambda of 1 - y = lambda u through the origin over the samples with y >= yMin (plasticity: 0.2,
/// the tail near zero stress left out; wall_friction: 0.6, the top of the unload where the wall
/// shear turns round). The same estimator on the lab and on the DEM record.
double unloadRatio(const std::vector<Branch>& b, const std::vector<std::size_t>& which, double yMin);

/// stiffness_nonlinearity: unloading curvature of the unload branches in `which` (DemConfirmation.h):
/// the least-squares slope of y on u at the top over the secant from the top to where y first reaches
/// yLow, averaged over the branches; -1 when no branch gives one. Both ends are found on a running
/// mean of y over kCurvatureSmoothing samples, never on single samples: a window chosen by a noisy
/// y keeps the samples whose noise lifts them (measured on DEM-made Hertz records with AR(1) noise
/// of 2.5 % of the top stress: 1.33 read as 1.18 on average, 1.28 with the running mean).
double unloadCurvature(const std::vector<Branch>& b, const std::vector<std::size_t>& which, double yLow);
/// Standard deviation of unloadCurvature over `draws` replicas of the branches in `which`: each the
/// branch's running mean plus noise drawn from `noise` (its AR(1) and white parts; the reference
/// stress follows the replica's first sample, as cycleBranches takes it); 0 without noise. A fixed
/// seed: the same record and noise model give the same value.
double unloadCurvatureSpread(const std::vector<Branch>& b, const std::vector<std::size_t>& which, double yLow, const NoiseModel& noise,
                             int draws = 200);

/// A DEM run's record: its unload/reload branches and its loading transmission.
struct DemRecord {
    std::vector<Branch> branches;
    double transmission = -1;
};

DemRecord readDemRecord(const std::string& base);

/// Shared set-up of the DEM runs: the driver, the work directory and the clock.
struct DemContext {
    const DemOptions& opt;
    std::string driver, workDir;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    DemResult& d;
    /// geometry arguments of every run (empty: the driver's default laterally periodic bed; ft4: the
    /// FT4 mould, without the preset's protocol: the recording's is used)
    std::string geometry = opt.mode == "ft4" ? " --geometry cylinder --device ft4 --diameter 0.05 --fill_height_m 0.05" : "";
    /// the recording's protocol, read once (null when it could not be read: protocolError says why)
    const recording::Protocol* protocol = nullptr;
    std::string protocolError = "";
    /// the explainer's noise model of the recording (stiffness_nonlinearity: the curvature's spread)
    NoiseModel noise{};

    /// Runs the driver with the recording's protocol and `args`; false when it failed.
    bool run(DemRun run, const std::string& protocolPath, const std::string& args) {
        std::ostringstream cmd;
        cmd << shellQuote(driver) << " --protocol_file " << shellQuote(protocolPath) << args << " --output " << shellQuote(workDir) << " --name "
            << run.name << " --threads " << opt.threads << " --quiet --vtk 0 --ene 0";
        cmd << geometry;
        if (opt.mode == "ft4") cmd << " --hold_tau 0.005 --ramp_rate 1";  // the driver's ft4 preset's numerical settings
        run.command = cmd.str();
        const auto t1 = std::chrono::steady_clock::now();
        const int rc = std::system((run.command + " > " + shellQuote(workDir + "/" + run.name + ".log") + " 2>&1").c_str());
        run.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
        d.runs.push_back(run);
        return rc == 0;
    }
    /// The confirmation is done: the chosen run (d.chosen) and the baseline (run 0) give the held-out errors.
    void scoreChosen() {
        d.heldoutBaseline = d.runs[0].heldoutRmse;
        d.heldoutAugmented = d.runs[static_cast<std::size_t>(d.chosen)].heldoutRmse;
        d.status = "done";
    }
    DemResult fail(const std::string& why) {
        d.status = "failed";
        d.reason = why;
        return finish();
    }
    DemResult finish() {
        d.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return d;
    }
};

/// dem/comparison.csv (and .png) of a hold confirmation: every lab hold sample, the odd holds held out.
void writeHoldComparison(const DemContext& ctx, const std::vector<LabHold>& lab, const std::vector<const std::vector<DemHold>*>& all);

/// Where the piston stopped before the hold that begins at sample `stop` at strain eHold: straight lines
/// of strain and stress against time over the second half of the ramp segment `ramp` before it, or,
/// where the ramp changed its speed (speedChanges, `changes`), over the samples after the last change
/// but its first eighth (at least 4 samples). The stop's time is where the strain line reaches eHold
/// (kept between the ramp's last sample and the hold's first), its stress the stress line's there.
/// False when there are fewer samples.
bool rampStop(const Recording& rec, const PhaseSegment& ramp, std::size_t stop, double eHold, const std::vector<RateChange>& changes,
              double& tStop, double& sStop);

/// The lab recording's position holds (from each hold's first sample), in order. With `stopFromRamp`
/// the hold's clock starts where the piston stopped and its stress at the start is the ramp's there
/// (rampStop; a stress lost within a sample or two of the stop, as a viscous one, has gone before the
/// hold's first sample), else at its first sample, with the stress of its own first samples.
std::vector<LabHold> labHolds(const Recording& rec, bool stopFromRamp = false);

/// Time, strain and stress columns of a DEM run's record.
void readDemSeries(const std::string& base, std::vector<double>& t, std::vector<double>& e, std::vector<double>& s);

// ---- the confirmations (DemConfirmation.h describes each) ----------------------------------------

DemResult confirmRelaxation(DemContext& ctx, const MechanismResult& relax, const Recording& rec, const std::string& protocolPath);

DemResult confirmRate(DemContext& ctx, const MechanismResult& rate, const Recording& rec, const std::string& protocolPath);

DemResult confirmPlasticity(DemContext& ctx, const MechanismResult& plast, const Recording& rec, const std::string& protocolPath);

DemResult confirmWallFriction(DemContext& ctx, const MechanismResult& wall, const Recording& rec, const std::string& protocolPath);

DemResult confirmCohesion(DemContext& ctx, const Recording& rec, const std::string& protocolPath);

DemResult confirmNonlinearity(DemContext& ctx, const MechanismResult& nonlin, const Recording& rec, const std::string& protocolPath);

} // namespace pdpm::explain::dem
