// pdpm-explain blind benchmark, DEM-made cases: recordings produced by the project's own DEM (the
// OedometerRelaxation driver, cocoa meso-particles without adhesion) instead of the surrogate. The
// issue asks for both: the surrogate cases give the volume (450 per run), these show that the tool
// also works on records whose physics it did not write itself.
//
// A case: the driver runs a fixed protocol shape (three ramps with holds, a partial unload, a
// reload and a last hold; hold length and targets drawn from the seed) twice with the same seed
// (the same poured bed): with contact relaxation ("with") and without ("without"). The positive
// case shows the explainer the "with" record, its null twin the "without" record; both resampled to
// a uniform lab-time grid, plus an offset and a drift, AR(1) noise and quantisation, with the same
// noise sd: the peak of |with - without| over the SNR. (A null's noise is thus the level at which
// its twin's relaxation has that SNR.) The DEM bed's own loading curvature and plastic unloading
// (Luding k/k1 = 5) are part of its baseline, so the case's MODEL.json puts stiffness_nonlinearity
// and plasticity into the baseline; the truth is what the contact law added on top. The bed also
// relaxes a little without contact relaxation (rearrangements, damping): its macroscopic C is
// stored as `intrinsic_macroscopic_C` in both truths.
//
// Wall friction (family wall_friction): the same protocol in a mould 30 mm across and 30 mm high
// (12 mean diameters, H/D 1; the bed poured with frictionless walls, so both runs compress the same
// bed), elastic contacts, no relaxation; "with" has wall friction mu_w in [0.15, 0.45], "without"
// none. The truth's primary value is Janssen's mu_w K of the noise-free "with" record,
// -ln(T)/(4 H/D) from its bottom/piston transmission T on first loading (the quantity the surrogate's
// muK stands for; mu_w itself is stored too). With bottomSensor the record shown also carries the
// bottom stress with its own offset, AR(1) noise of the same sd and quantisation. MODEL.json:
// stiffness_nonlinearity, plasticity (the frictional bed unloads stiffer than it loads, elastic
// contacts notwithstanding) and a free loading curve (the bed's own first loading).
//
// Creep (family creep): the relaxation family's protocol shape and parameter ranges (its own seeds) with every hold a creep step at
// constant stress (creep:T, the piston keeping the stress reached), so contact relaxation shows as
// strain growing at constant stress, not as stress decay. The truth's mechanism is contact_relaxation;
// the shown record carries the driver's `step` column (which tells the explainer the creep steps).
// The effect is what a baseline without relaxation gets wrong at the recorded strain: in a creep step,
// the loading tangent before the step (top 20 % of the preceding ramp's stress) times the strain crept
// so far, "with" minus "without" at the same lab time since the step began (the stress sags a little in both
// runs while the piston follows; the driver's controller). No macroscopic C (Eq. 4.3 needs a
// position hold).
//
// Cohesion (family cohesion, since 2026-12-05): the relaxation family's protocol shape (its own seeds)
// whose unload is a lift-off test (unload:V:-S, S 4-8 % of the top stress: pull on the bed to the
// tension S or until the piston is free, then hold the piston there), no relaxation; "with" has
// Luding adhesion kc/k in [0.5, 1] for the particle pairs and the walls (--kc_over_k,
// --wall_kc_over_k), "without" none; both the cocoa plasticity k/k1 = 5 (Luding's law has no tension
// without it). The truth's primary value is the largest tension of the noise-free "with" record (the
// surrogate's `tension`). MODEL.json as for contact_relaxation.
//
// Rate dependence (family rate_dependence, since 2026-12-06): its own protocol shape (a slow ramp that
// speeds up five-fold half way without stopping, a hold, a slow ramp, a fast unload, a fast reload and
// a last hold; holds a quarter of the relaxation family's), its own seeds, no relaxation; "with" has a contact viscosity on the lab clock, viscous time tau_v in
// [0.05, 0.5] lab s (--contact_viscous_time, a Maxwell branch: Contacts/ViscousLaws.h), "without" none.
// The viscous stress rides on every ramp, vanishes in the holds and reverses in the unload. The truth's
// primary value is the contact tau_v (the surrogate's tau_v is macroscopic: the viscous stress over
// its loading modulus and strain rate, several times the contact value, since the branch acts with the
// unloading stiffness k and the bed loads with about k1 = k/5). MODEL.json as for contact_relaxation.
//
// Positive: contact C in [0.02, 0.08], t0 in [0.1, 2] s. The truth's primary value is the contact C;
// `primary_value_identifiable` is the macroscopic C of the noise-free "with" record (the mean Eq. 4.3
// fit of its holds, which the bed's rearrangements make smaller than the contact C). Windows: the
// protocol phases carrying the raw effect's energy (selectMismatch rule). A run already in the work
// folder with the same command is reused (a case and its twin share both runs).
#pragma once
#include <string>
#include <vector>

#include "ExplainBench.h"

namespace pdpm::explain {

struct DemCaseSpec {
    std::string kind = "null";  ///< null | contact_relaxation | wall_friction | creep | cohesion | rate_dependence
    double snr = 3, rho = 0.5;
    unsigned long seed = 1;
    int samples = 2000;
    std::string driver;      ///< OedometerRelaxation executable (empty: next to this program)
    std::string driverArgs;  ///< appended to every driver command (e.g. a smaller bed for tests)
    int threads = 1;
    /// the family of the pair (a null case is the twin without its mechanism): contact_relaxation,
    /// wall_friction, creep or cohesion; empty: the kind (contact_relaxation for a null)
    std::string family = "";
    bool bottomSensor = false;  ///< wall_friction family: the record also has a noisy bottom_stress_Pa
};

/// Runs the DEM (its files go to workDir) and returns the case; `model` receives the case's MODEL.json.
GeneratedCase generateDemCase(const DemCaseSpec& spec, const std::string& workDir, Json& model);

/// The families of DEM-made cases.
inline const std::vector<std::string> kDemCaseFamilies = {"contact_relaxation", "wall_friction", "creep", "cohesion", "rate_dependence"};
/// The mechanism a positive case of family `f` carries (creep: contact_relaxation; else f itself).
inline std::string demFamilyMechanism(const std::string& f) { return f == "creep" ? "contact_relaxation" : f; }
/// The report parameter a positive case of family `f` is scored on (wall_friction: muK; cohesion: tension; else C).
inline std::string demFamilyPrimary(const std::string& f) {
    return f == "wall_friction" ? "muK" : f == "cohesion" ? "tension" : f == "rate_dependence" ? "tau_v" : "C";
}
/// InputError "WHAT: unknown family 'F' (contact_relaxation, wall_friction, creep, cohesion)" unless `f` is a family.
void checkDemCaseFamily(const std::string& f, const std::string& what);

/// The DEM-made part of the blind benchmark: for each family (contact_relaxation, wall_friction, creep, cohesion),
/// `perSnr` positive cases at each SNR, each with its null twin (AR(1) rho cycled over 0, 0.5, 0.9;
/// wall_friction: every second pair with a bottom stress sensor), generated (out/dem_runs),
/// explained with each case's MODEL.json (out/cases, out/reports; the explainer sees only the case
/// folder) and scored against the sealed truth (out/truth). Pairs run in parallel, one DEM thread
/// each. Returns a markdown section.
std::string demCaseBenchmark(int perSnr, const std::vector<double>& snrs, int samples, unsigned long seed, const std::string& out,
                             const std::string& driverArgs, const std::vector<std::string>& families = {"contact_relaxation"});

} // namespace pdpm::explain
