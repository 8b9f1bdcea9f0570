#include "DemConfirmation.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>

#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "IO/NumberFormat.h"
#include "DemRuns.h"
#include "Recording.h"


namespace pdpm::explain {

namespace fs = std::filesystem;
using namespace dem;

std::string defaultDemDriver() {
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return "OedometerRelaxation";
    return (self.parent_path() / "OedometerRelaxation").string();
}


namespace {
/// The reason of a `not_supported` status.
std::string notWired(const std::string& mechanism) {
    return "the DEM re-run is implemented for contact_relaxation, plasticity, wall_friction, stiffness_nonlinearity, cohesion and "
           "rate_dependence; " +
           mechanism + " maps to a driver ingredient (Documentation/tools-explain.md) that is not wired yet";
}
} // namespace

DemResult confirmWithDem(const ExplainResult& r, const Recording& rec, const std::string& protocolPath,
                         const DemOptions& opt, const std::string& workDir) {
    DemResult d;
    if (opt.mode == "off") {
        d.reason = "switched off (--dem off)";
        return d;
    }
    if (r.mechanisms.empty()) {
        d.status = "not_needed";
        d.reason = "no mechanism was accepted, so there is nothing to add to the DEM model";
        return d;
    }
    recording::Protocol proto;
    std::string protoError;
    try {
        proto = recording::readProtocol(protocolPath);
    } catch (const InputError& e) {
        protoError = e.what();
    }
    // the first accepted mechanism with a DEM counterpart; wall_friction only when the protocol gives
    // the device's size (the mould's H/D), else a later one is preferred (it still gets its not_run
    // when it is the only one)
    const MechanismResult* m = nullptr;
    const MechanismResult* wallWithoutSize = nullptr;
    const MechanismResult* cohesionWithoutPull = nullptr;  // cohesion on a protocol without an unload into tension
    const MechanismResult* nonlinearity = nullptr;
    for (const auto& mr : r.mechanisms) {
        if (!demSupported(mr.comp)) continue;
        if (mr.comp == kCohesion && (!protoError.empty() || !pullsOnTheBed(proto))) {  // it would only say not_run
            if (!cohesionWithoutPull) cohesionWithoutPull = &mr;
            continue;
        }
        if (mr.comp == kNonlinearity) {  // last choice: every other ingredient changes the loading curve too
            if (!nonlinearity) nonlinearity = &mr;
            continue;
        }
        if (mr.comp == kWallFriction && !wallWithoutSize) {
            if (!protoError.empty() || !(proto.diameter > 0 && proto.height > 0)) {
                wallWithoutSize = &mr;
                continue;
            }
        }
        m = &mr;
        break;
    }
    if (!m) m = nonlinearity;
    if (!m) m = wallWithoutSize;
    if (!m) m = cohesionWithoutPull;
    if (!opt.mechanism.empty()) {  // the user's choice among the accepted mechanisms
        m = nullptr;
        for (const auto& mr : r.mechanisms)
            if (opt.mechanism == compName(mr.comp)) m = &mr;
        if (!m) {
            d.mechanism = opt.mechanism;
            d.reason = "--dem_mechanism " + opt.mechanism + " was not accepted by the explanation, so there is nothing to confirm";
            return d;
        }
        if (!demSupported(m->comp)) {
            d.status = "not_supported";
            d.mechanism = opt.mechanism;
            d.reason = notWired(d.mechanism);
            return d;
        }
    }
    if (!m) {
        d.status = "not_supported";
        d.mechanism = compName(r.mechanisms.front().comp);
        d.reason = notWired(d.mechanism);
        return d;
    }
    DemContext ctx{opt, opt.driver.empty() ? defaultDemDriver() : opt.driver, workDir, std::chrono::steady_clock::now(), d};
    if (protoError.empty()) ctx.protocol = &proto;
    ctx.protocolError = protoError;
    ctx.noise = r.noise;
    if (::access(ctx.driver.c_str(), X_OK) != 0) {
        d.status = "not_run";
        d.mechanism = compName(m->comp);
        d.reason = "driver executable not found: " + ctx.driver + " (give --dem_driver)";
        return d;
    }
    fs::create_directories(workDir);
    switch (m->comp) {
        case kRelaxation: return confirmRelaxation(ctx, *m, rec, protocolPath);
        case kPlasticity: return confirmPlasticity(ctx, *m, rec, protocolPath);
        case kNonlinearity: return confirmNonlinearity(ctx, *m, rec, protocolPath);
        case kCohesion: return confirmCohesion(ctx, rec, protocolPath);
        case kRate: return confirmRate(ctx, *m, rec, protocolPath);
        default: return confirmWallFriction(ctx, *m, rec, protocolPath);
    }
}

bool pullsOnTheBed(const recording::Protocol& p) {
    for (const recording::Step& st : p.steps)
        if (st.kind == recording::Step::Kind::Unload && st.targetStress < 0) return true;
    return false;
}

bool demSupported(int comp) {
    return comp == kRelaxation || comp == kPlasticity || comp == kWallFriction || comp == kNonlinearity || comp == kCohesion ||
           comp == kRate;
}

Json demJson(const DemResult& d) {
    Json j = Json::object();
    j.set("status", d.status);
    if (!d.reason.empty()) j.set("reason", d.reason);
    if (!d.mechanism.empty()) j.set("mechanism", d.mechanism);
    const auto num = [](double x) { return x >= 0 && std::isfinite(x) ? Json(x) : Json(); };
    const bool plastic = d.mechanism == "plasticity", wall = d.mechanism == "wall_friction";
    const bool hertz = d.mechanism == "stiffness_nonlinearity", coh = d.mechanism == "cohesion", branches = plastic || wall || hertz || coh;
    const bool rate = d.mechanism == "rate_dependence";
    const auto finite = [](double x) { return std::isfinite(x) ? Json(x) : Json(); };
    j.set("heldout_rmse_baseline", num(d.heldoutBaseline));
    j.set("heldout_rmse_augmented", num(d.heldoutAugmented));
    if (d.status == "done") {
        j.set("heldout_reduction", d.heldoutBaseline > 0 ? Json(1 - d.heldoutAugmented / d.heldoutBaseline) : Json());
        j.set(branches ? "calibration_branches" : "calibration_holds", d.calibrationHolds);
        j.set(branches ? "heldout_branches" : "heldout_holds", d.heldoutHolds);
        j.set("chosen_run", d.runs[static_cast<std::size_t>(d.chosen)].name);
        if (branches) j.set("stress_scale", d.stressScale);
        if (rate) {
            j.set("recording_hold_drop_calibration_holds", finite(d.labMacro));
            j.set("recording_speed_changes", d.rateChanges);
            j.set("recording_speed_change_step", finite(d.labRateStep));
        } else if (!branches) {  // contact_relaxation: the probe that decides whether run b's contacts relax in the ramps
            j.set("run_a_hold_t0_over_contact_t0", num(d.rampAgedT0Ratio));
            j.set("ramp_aged_t0_ratio_threshold", kRampAgedT0Ratio);
        }
        if (plastic || wall) {
            j.set("recording_unload_stiffness_ratio_calibration_branches", num(d.labMacro));
            j.set("unload_ratio_min_y", d.ratioYMin);
        }
        if (coh) j.set("recording_tension_over_start_stress_calibration_branches", num(d.labMacro));
        if (hertz) {
            j.set("surrogate_exponent_n", num(d.surrogateValue));
            if (d.control >= 0) {
                j.set("control_run", d.runs[static_cast<std::size_t>(d.control)].name);
                j.set("contact_law_distinguished", d.contactLawDistinguished());
                j.set("contact_law_judged_by", d.lawJudge);
                j.set("contact_law_favoured", contactLawName(d.contactLaw));
            } else if (!d.controlNote.empty()) {
                j.set("control_note", d.controlNote);
            }
            if (std::isfinite(d.labExponent)) j.set("recording_unload_stiffness_exponent", d.labExponent);
            j.set("heldout_judge", "reload_from_its_start");
            j.set("heldout_rmse_u_scale_baseline", num(d.heldoutUScaleBaseline));
            j.set("heldout_rmse_u_scale_augmented", num(d.heldoutUScaleAugmented));
        }
        if (wall) {
            j.set("mould_diameter_m", d.mouldDiameter);
            j.set("mould_height_m", d.mouldHeight);
            j.set("recording_aspect_ratio_H_over_D", d.recordingAspect);
        }
    }
    if (branches && !d.calibration.empty()) j.set("calibration", d.calibration);
    if (hertz && d.labMacro > 0) {
        j.set("recording_unload_curvature_calibration_branches", d.labMacro);
        j.set("curvature_secant_to_y", d.ratioYMin);
        if (d.labMacroSpread > 0) j.set("recording_unload_curvature_noise_sd", d.labMacroSpread);
    }
    if (d.labTransmission > 0) j.set("recording_bottom_over_piston_loading", d.labTransmission);
    if (d.transmissionTarget > 0) j.set("bottom_over_piston_target", d.transmissionTarget);
    if (d.heldoutBottomBaseline >= 0) {
        j.set("heldout_bottom_rmse_baseline", num(d.heldoutBottomBaseline));
        j.set("heldout_bottom_rmse_augmented", num(d.heldoutBottomAugmented));
    }
    Json runs = Json::array();
    for (const DemRun& r : d.runs) {
        Json o = Json::object({{"name", r.name}});
        if (hertz) {
            o.set("hertz_modulus_Pa", r.hertzModulus);
            o.set("normal_stiffness_scale", r.normalStiffnessScale);
            if (std::isfinite(r.exponent)) o.set("dem_unload_stiffness_exponent", r.exponent);
            o.set("dem_unload_curvature_calibration_branches", num(r.macro));
        } else if (coh) {
            o.set("kc_over_k", r.kcOverK);
            o.set("wall_kc_over_k", r.kcOverK);
            o.set("dem_tension_over_start_stress_calibration_branches", num(r.macro));
        } else if (branches) {
            if (plastic) o.set("k_over_k1", r.kOverK1);
            else o.set("wall_friction", r.wallFriction);
            if (d.calibration == "bottom_over_piston_secant") o.set("dem_bottom_over_piston_loading", num(r.transmission));
            o.set("dem_unload_stiffness_ratio_calibration_branches", num(r.macro));
        } else if (rate) {
            o.set("contact_viscous_time_s", r.viscTime);
            o.set("dem_hold_drop_calibration_holds", finite(r.macro));
            o.set("dem_speed_change_step", finite(r.rateStep));
        } else {
            o.set("relax_C", r.relaxC);
            o.set("relax_t0_s", r.relaxT0);
            o.set("relax_in_ramps", r.relaxInRamps);
            o.set("dem_macroscopic_C_calibration_holds", num(r.macro));
        }
        o.set("calibration_rmse_Pa", num(r.calibrationRmse));
        o.set("heldout_rmse_Pa", num(r.heldoutRmse));
        if (r.heldoutBottomRmse >= 0) o.set("heldout_bottom_rmse_Pa", r.heldoutBottomRmse);
        if (hertz) o.set("heldout_rmse_u_scale_Pa", num(r.heldoutUScaleRmse));
        o.set("command", r.command);
        runs.push(o);
    }
    j.set("runs", runs);
    return j;
}

namespace {
/// printf into a string.
__attribute__((format(printf, 1, 2))) std::string formatted(const char* format, ...) {
    va_list args, again;
    va_start(args, format);
    va_copy(again, args);
    const int n = std::vsnprintf(nullptr, 0, format, args);
    va_end(args);
    std::string out(static_cast<std::size_t>(std::max(n, 0)) + 1, '\0');
    std::vsnprintf(out.data(), out.size(), format, again);
    va_end(again);
    out.pop_back();
    return out;
}
} // namespace

// The paragraph: what was re-run (shared opening), how the ingredient was set (the mechanism's
// middle), and the held-out errors of the two runs (shared ending).
std::string demMarkdown(const DemResult& d) {
    std::ostringstream os;
    os << "\n## DEM confirmation\n\n";
    if (d.status != "done") {
        os << "Status: " << d.status << (d.reason.empty() ? "" : " — " + d.reason) << ".\n";
        return os.str();
    }
    const DemRun& a = d.runs[static_cast<std::size_t>(d.chosen)];
    const double change = d.heldoutBaseline > 0 ? 100 * (1 - d.heldoutAugmented / d.heldoutBaseline) : 0.0;
    const bool branches = d.mechanism != "contact_relaxation" && d.mechanism != "rate_dependence";  // else holds
    const std::string scaled = formatted(" (stresses scaled by %.4g into the material's range", d.stressScale);
    const auto mould = [&] {
        return formatted(" in a mould D = %.3g m across and H = %.3g m high (H/D %.3g; the recording's %.3g), every bed poured "
                         "with frictionless walls, once with frictionless walls and with wall friction mu_w = %.4g",
                         d.mouldDiameter, d.mouldHeight, d.mouldHeight / d.mouldDiameter, d.recordingAspect, a.wallFriction);
    };
    const char* units = "Compared in units of each branch's start stress and loading stiffness, on ";
    os << "The OedometerRelaxation driver was re-run on this protocol";
    std::string without, with, extra;  // the two runs in the ending, and what follows their errors
    if (d.mechanism == "plasticity") {
        os << scaled << "), once with an elastic contact law (Luding k/k1 = 1) and once with plastic contacts "
           << formatted("(k/k1 = %.4g, calibrated on %d unload/reload branch(es) to the recording's unloading stiffness ratio "
                        "%.3g; the DEM gives %.3g). %sthe %d branch(es) the calibration did not see",
                        a.kOverK1, d.calibrationHolds, d.labMacro, a.macro, units, d.heldoutHolds);
        without = "elastic contacts", with = "plastic ones";
    } else if (d.mechanism == "cohesion") {
        os << scaled << "; Luding's law with the material's plasticity), once without adhesion and once with adhesive contacts "
           << formatted("and sticky walls (kc/k = %.3g for the particle pairs and the walls, of %zu values the one with the smallest "
                        "error on %d unload branch(es); largest tension over the start stress: recording %.3g, "
                        "DEM %.3g with adhesion, %.3g without). %sthe %d reload branch(es) the choice did not see",
                        a.kcOverK, d.runs.size() - 1, d.calibrationHolds, d.labMacro, a.macro, d.runs.front().macro, units,
                        d.heldoutHolds);
        without = "no adhesion", with = "adhesion";
    } else if (d.mechanism == "stiffness_nonlinearity") {
        os << scaled << "; the non-cohesive frictional material), once with linear elastic contacts and with Hertzian ones, "
           << formatted("whose stiffness falls with the force: E* = %.4g Pa (of %zu values), calibrated on %d unload branch(es) "
                        "to the recording's unloading curvature (tangent at the top over the secant to %.0f %% of the start "
                        "stress: recording %.3g, Hertzian DEM %.3g, linear DEM %.3g). On the %d reload branch(es) the "
                        "calibration did not see, each followed from its own first sample (where the unload ended: how the "
                        "reload climbs, not where in strain another bed's unload ended), in units of the branch's start stress "
                        "and loading stiffness,",
                        a.hertzModulus, d.runs.size() - (d.control >= 0 ? 2 : 1), d.calibrationHolds, 100 * d.ratioYMin, d.labMacro, a.macro,
                        d.runs.front().macro, d.heldoutHolds);
        without = "linear contacts", with = "Hertzian ones";
        if (d.heldoutUScaleBaseline >= 0 && d.heldoutUScaleAugmented >= 0)
            extra = formatted(" (placed on the u scale instead, without following the reload from its start: %.4g Pa and %.4g Pa)",
                              d.heldoutUScaleBaseline, d.heldoutUScaleAugmented);
    } else if (d.mechanism == "wall_friction" && d.calibration == "bottom_over_piston_secant") {
        const std::string atMould = d.transmissionTarget > 0 && std::abs(d.transmissionTarget - d.labTransmission) > 1e-9 * d.labTransmission
                                        ? formatted(", %.3g at the mould's H/D", d.transmissionTarget)
                                        : "";
        os << scaled << ")" << mould()
           << formatted(", calibrated so that the bottom plate carries the share of the piston stress the recording's bottom "
                        "sensor shows on first loading (recording %.3g%s; DEM %.3g with friction, %.3g without; %zu runs with "
                        "friction, secant on its logarithm). On the %d reload branch(es), compared in units of each branch's "
                        "start stress and loading stiffness,",
                        d.labTransmission, atMould.c_str(), a.transmission, d.runs.front().transmission, d.runs.size() - 1,
                        d.heldoutHolds);
        without = "frictionless walls", with = "wall friction";
        if (d.heldoutBottomBaseline >= 0 && d.heldoutBottomAugmented >= 0)
            extra = formatted("; the bottom stress on the same branches by %.4g Pa and %.4g Pa", d.heldoutBottomBaseline,
                              d.heldoutBottomAugmented);
    } else if (d.mechanism == "wall_friction") {
        os << scaled << ")" << mould()
           << formatted(" (of %zu values around max(2 muK, %.2g) = %.3g, the one with the smallest error on %d unload "
                        "branch(es)). %sthe %d branch(es) the choice did not see",
                        d.runs.size() - 1, kMinWallFrictionGuess, d.runs.size() > 1 ? d.runs[1].wallFriction : 0.0,
                        d.calibrationHolds, units, d.heldoutHolds);
        without = "frictionless walls", with = "wall friction";
    } else if (d.mechanism == "rate_dependence") {
        os << formatted(", once with the standard contact law and once with a contact viscosity on the lab clock (viscous time "
                        "%.4g lab s, of %zu values the one with the smaller error on %d hold(s); the stress lost over the last third "
                        "of those holds: recording %.3g, DEM %.3g with the viscosity, %.3g without)",
                        a.viscTime, d.runs.size() - 1, d.calibrationHolds, d.labMacro, a.macro, d.runs.front().macro);
        if (d.rateChanges > 0)
            os << formatted(". Where the loading speed changes without a stop (%d change(s)), the stress steps by %.3g of the stress "
                            "there in the recording, %.3g with the viscosity and %.3g without (model-free: straight lines either "
                            "side; not used in the choice)",
                            d.rateChanges, d.labRateStep, a.rateStep, d.runs.front().rateStep);
        os << formatted(". On the %d hold(s) the calibration did not see,", d.heldoutHolds);
        without = "viscosity", with = "it";
    } else {
        os << formatted(", once with the standard contact law and once with contact relaxation switched on (contact C = "
                        "%.4g, t0 = %.4g s, calibrated on %d hold(s); the contacts relaxing %s",
                        a.relaxC, a.relaxT0, d.calibrationHolds, a.relaxInRamps ? "in the ramps as well as in the holds" : "in the holds only");
        if (d.rampAgedT0Ratio > kRampAgedT0Ratio)
            os << formatted(": with relaxation in the ramps too, the DEM holds relaxed on a time scale %.3g times t0, the contacts "
                            "aged by the ramp", d.rampAgedT0Ratio);
        os << formatted("). On the %d hold(s) the calibration did not see,", d.heldoutHolds);
        without = "relaxation", with = "it";
    }
    os << (branches ? " the DEM misses" : " the DEM hold curves miss") << " the recording by "
       << formatted("%.4g Pa (RMS) %s %s and %.4g Pa with %s (%.1f %% %s)", d.heldoutBaseline, branches ? "with" : "without",
                    without.c_str(), d.heldoutAugmented, with.c_str(), std::abs(change), change >= 0 ? "lower" : "higher")
       << extra << ".";
    if (d.mechanism == "wall_friction" && d.calibration != "bottom_over_piston_secant")
        os << formatted(" Unloading ratio over the top %.0f %% of the unloads: recording %.3g, chosen run %.3g, frictionless %.3g.",
                        100 * (1 - d.ratioYMin), d.labMacro, a.macro, d.runs.front().macro);
    if (!d.controlNote.empty()) os << " The contact law was not judged: " << d.controlNote << ".";
    if (d.control >= 0) {
        const DemRun& c = d.runs[static_cast<std::size_t>(d.control)];
        const bool byExponent = d.judgedByExponent;
        os << formatted(" A control run with linear contacts as soft as the chosen Hertzian ones at the top stress (normal "
                        "stiffness x %.3g) unloads with curvature %.3g (held-out %.4g Pa)",
                        c.normalStiffnessScale, c.macro, c.heldoutRmse);
        if (byExponent)
            os << formatted("; the unloading stiffness grows with the stress it unloads from as stress^%.2f in the recording, "
                            "^%.2f with the Hertzian contacts and ^%.2f with the linear control",
                            d.labExponent, d.runs[static_cast<std::size_t>(d.chosen)].exponent, c.exponent);
        else if (d.lawJudge == "reload_from_its_start")
            os << formatted("; followed from its start, the held-out reload is missed by %.4g Pa with the control and %.4g Pa with "
                            "the Hertzian contacts",
                            c.heldoutRmse, d.runs[static_cast<std::size_t>(d.chosen)].heldoutRmse);
        os << ": ";
        if (d.contactLaw == ContactLaw::Hertz)
            os << (d.lawJudge == "unload_curvature" ? "clearly further from the recording's, so the curvature needs the Hertzian force law."
                                                    : "the control is clearly further from the recording, so the record needs the Hertzian force law.");
        else if (d.contactLaw == ContactLaw::LinearAsSoft)
            os << "the control is clearly closer to the recording: the record shows linear contacts that soft, not Hertz's force "
                  "law (the curvature is the contacts' softness under the load).";
        else if (d.lawJudge != "unload_curvature")
            os << "the control is about as close to the recording, so the record does not tell Hertz's force law from a linear "
                  "one that soft (the bulk nonlinearity is confirmed, the contact law is not).";
        else
            os << "about as close to the recording's, so the record shows contacts that are soft under the load; it does not "
                  "tell Hertz's force law from a linear one that soft (the bulk nonlinearity is confirmed, the contact law is "
                  "not; unloads from two stress levels at least a factor "
               << fmt(kExponentStressRatio) << " apart would judge it by how the unloading stiffness grows with the stress).";
    }
    os << " Runs, commands and logs are in `dem/`.\n";
    return os.str();
}

} // namespace pdpm::explain
