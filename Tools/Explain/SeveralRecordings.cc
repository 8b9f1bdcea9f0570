#include "SeveralRecordings.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <sstream>

#include "IO/AtomicFile.h"
#include "IO/Json.h"

namespace pdpm::explain {

namespace {

/// Fits a recording with its own baseline model free (baseline, its nuisances and any always-on
/// components: the device parameters), the components `on` switched on and every other parameter
/// (the transferred material parameters) held at the start values.
FitResult fitDevice(const Model& M, const Recording& rec, const ExplainResult& own, const std::vector<char>& on,
                    const std::vector<std::vector<double>>& starts) {
    FitOptions fo;
    fo.freeParams = freeParamsFor(M, own.onBaseline, own.heldParam);  // a calibrated compliance stays held
    fo.whitener = own.noise.whitener();
    FitResult best;
    best.rss = -1;
    for (const auto& s : starts) {
        FitResult f = fitModel(M, rec.stress, on, s, fo);
        if (best.rss < 0 || f.rss < best.rss) best = std::move(f);
    }
    return best;
}

Transfer transfer(const std::vector<Recording>& recs, const std::vector<Protocol>& protos,
                  const std::vector<ExplainResult>& per, std::size_t a, std::size_t b, const std::vector<int>& mechs) {
    Transfer T;
    T.from = a;
    T.to = b;
    T.mechanisms = mechs;
    const ExplainResult& own = per[b];
    Model M(makeModelInput(recs[b], protos[b]));
    M.limitsForLoadingCurve(own.onBaseline[kLoadingCurve] != 0);  // as in its own explain()
    const std::vector<char>& on = own.onBaseline;  // its baseline model; its own mechanisms stay off
    const FitResult base = fitDevice(M, recs[b], own, on, {own.pBaseline, own.pFinal});
    std::vector<char> onAug = on;
    std::vector<double> start = base.p, startOwn = own.pFinal;
    for (int c : mechs) {
        onAug[c] = 1;
        for (int k : M.paramsOf(c)) start[k] = startOwn[k] = per[a].pFinal[k];
    }
    const FitResult aug = fitDevice(M, recs[b], own, onAug, {start, startOwn});
    T.yBaseline = base.model;
    T.yAugmented = aug.model;
    T.rmseBaseline = rmsOf(recs[b].stress, base.model);
    T.rmseAugmented = rmsOf(recs[b].stress, aug.model);
    T.termRms = rmsOf(base.model, aug.model);
    T.acts = T.termRms >= own.minDetectableRms;
    T.noiseSigma = own.noise.sigma;
    // whitened residual energies of the same free parameters: a log-likelihood ratio (times 2)
    T.evidence = double(recs[b].size()) * std::log(std::max(base.rss, 1e-300) / std::max(aug.rss, 1e-300));
    return T;
}

std::string names(const std::vector<int>& comps) {
    std::string s;
    for (std::size_t k = 0; k < comps.size(); ++k) s += (k ? ", " : "") + std::string(compName(comps[k]));
    return s;
}

} // namespace

double Transfer::excessGain() const {
    const double s2 = noiseSigma * noiseSigma;
    const double eb = std::sqrt(std::max(0.0, rmseBaseline * rmseBaseline - s2));
    const double ea = std::sqrt(std::max(0.0, rmseAugmented * rmseAugmented - s2));
    return eb > 0 ? 1 - ea / eb : -1;
}

SeveralResult explainSeveral(const std::vector<Recording>& recs, const std::vector<Protocol>& protos,
                             const ExplainOptions& opt) {
    SeveralResult R;
    for (std::size_t k = 0; k < recs.size(); ++k) R.per.push_back(explain(recs[k], protos[k], opt));
    for (const auto& r : R.per)
        for (const auto& m : r.mechanisms)
            if (std::find(R.mechanisms.begin(), R.mechanisms.end(), m.comp) == R.mechanisms.end())
                R.mechanisms.push_back(m.comp);
    R.confirmed.assign(R.mechanisms.size(), 0);
    R.testedElsewhere.assign(R.mechanisms.size(), 0);
    std::vector<char> worse(R.mechanisms.size(), 0);
    // each mechanism alone, from every recording that accepted it to every other recording
    for (std::size_t u = 0; u < R.mechanisms.size(); ++u)
        for (std::size_t a = 0; a < recs.size(); ++a) {
            bool has = false;
            for (const auto& m : R.per[a].mechanisms) has = has || m.comp == R.mechanisms[u];
            if (!has) continue;
            for (std::size_t b = 0; b < recs.size(); ++b) {
                if (b == a) continue;
                Transfer T = transfer(recs, protos, R.per, a, b, {R.mechanisms[u]});
                if (T.acts) {
                    R.testedElsewhere[u] = 1;
                    if (T.evidence >= opt.bicThreshold) R.confirmed[u] = 1;
                    if (T.evidence <= -opt.bicThreshold) worse[u] = 1;
                }
                R.transfers.push_back(std::move(T));
            }
        }
    R.foundIn.assign(R.mechanisms.size(), 0);
    const std::vector<char> helped = R.confirmed;  // some transfer reached the threshold
    for (std::size_t u = 0; u < R.mechanisms.size(); ++u) {
        for (const auto& r : R.per)
            for (const auto& m : r.mechanisms) R.foundIn[u] += m.comp == R.mechanisms[u];
        if (worse[u]) R.confirmed[u] = 0;
        R.status.push_back(R.confirmed[u]          ? "confirmed"
                           : !R.testedElsewhere[u] ? "not_testable_elsewhere"
                           : !worse[u]             ? "inconclusive"
                           : R.foundIn[u] >= 2     ? "recording_dependent"
                                                   : "not_transferable");
    }
    // one set of material parameters for the recordings that inform each mechanism
    for (std::size_t u = 0; u < R.mechanisms.size(); ++u) {
        const int c = R.mechanisms[u];
        std::vector<std::size_t> which;
        for (std::size_t k = 0; k < recs.size(); ++k) {
            bool informs = false;
            for (const auto& m : R.per[k].mechanisms) informs = informs || m.comp == c;
            for (const auto& T : R.transfers)
                informs = informs || (T.to == k && T.acts && T.mechanisms.size() == 1 && T.mechanisms[0] == c);
            if (informs) which.push_back(k);
        }
        if (which.size() >= 2) {
            R.joint.push_back(fitJointly(c, which, recs, protos, R.per));
            // three or more and inconsistent: which of them differs (each left out in turn)
            if (!R.joint.back().consistent) leaveOneOut(R.joint.back(), recs, protos, R.per);
        }
    }
    // The joint fit votes on the transfers' status. Its consistency test asks "can one set of material
    // parameters serve every recording?" with each recording's uncertainty counted, where a transfer
    // only tries one recording's point estimate on another. So a mechanism accepted in several
    // recordings whose transfers confirmed it but whose recordings need different values is
    // recording_dependent, and one whose point estimate made another recording worse, while another
    // transfer helped, and for which a common value fits all is confirmed.
    R.transferStatus = R.status;
    for (const JointFit& J : R.joint) {
        const auto u = static_cast<std::size_t>(std::find(R.mechanisms.begin(), R.mechanisms.end(), J.comp) -
                                                R.mechanisms.begin());
        if (u >= R.mechanisms.size()) continue;
        if (R.status[u] == "confirmed" && !J.consistent && R.foundIn[u] >= 2) {
            R.status[u] = "recording_dependent";
            R.confirmed[u] = 0;
        } else if (R.status[u] == "recording_dependent" && J.consistent && helped[u]) {
            R.status[u] = "confirmed";
            R.confirmed[u] = 1;
        }
    }
    // each recording's whole accepted set (when it has more than one mechanism)
    for (std::size_t a = 0; a < recs.size(); ++a) {
        std::vector<int> set;
        for (const auto& m : R.per[a].mechanisms) set.push_back(m.comp);
        if (set.size() < 2) continue;
        for (std::size_t b = 0; b < recs.size(); ++b)
            if (b != a) R.transfers.push_back(transfer(recs, protos, R.per, a, b, set));
    }

    // verdict
    std::ostringstream sum;
    bool allNull = true, anyAmbiguous = false;
    for (const auto& r : R.per) {
        allNull = allNull && r.verdict == "no_missing_physics";
        anyAmbiguous = anyAmbiguous || r.verdict == "ambiguous";
    }
    std::vector<int> conf, recur, refuted, open;
    for (std::size_t u = 0; u < R.mechanisms.size(); ++u) {
        const std::string& st = R.status[u];
        (st == "confirmed" ? conf : st == "recording_dependent" ? recur : st == "not_transferable" ? refuted : open)
            .push_back(R.mechanisms[u]);
    }
    std::string qualified;  // recordings whose own verdict was ambiguous or unexplained
    for (std::size_t k = 0; k < R.per.size(); ++k)
        if (R.per[k].verdict == "ambiguous" || R.per[k].verdict == "unexplained")
            qualified += " Recording " + std::to_string(k + 1) + " on its own: " + R.per[k].verdict + " (" +
                         R.per[k].summary + ")";
    if (allNull) {
        R.verdict = "no_missing_physics";
        sum << "None of the " << recs.size() << " recordings shows a mismatch beyond its noise.";
    } else if (!conf.empty() || !recur.empty() || !open.empty()) {
        R.verdict = conf.empty() && recur.empty() && anyAmbiguous ? "ambiguous" : "missing_physics";
        sum << "Missing: " << names(conf.empty() ? (recur.empty() ? open : recur) : conf);
        if (!conf.empty())
            sum << " (confirmed on a held-out recording: the term calibrated on one recording improves the fit of another)";
        if (!conf.empty() && !recur.empty()) sum << "; also " << names(recur);
        if (!recur.empty())
            sum << " (present in several recordings, but one set of its parameters does not serve them all: "
                << "the values differ between the recordings)";
        if ((!conf.empty() || !recur.empty()) && !open.empty()) sum << "; also " << names(open);
        if (!open.empty()) sum << " (the other recordings can neither confirm nor contradict it)";
        if (!refuted.empty()) sum << "; found in one recording but contradicted by another: " << names(refuted);
        sum << ".";
    } else if (R.mechanisms.empty()) {
        R.verdict = anyAmbiguous ? "ambiguous" : "unexplained";
        sum << "At least one recording disagrees with the baseline, but no mechanism was accepted.";
    } else {
        R.verdict = "unexplained";
        sum << "The mechanisms found in single recordings (" << names(R.mechanisms)
            << ") make the other recordings fit worse with the same material parameters: the difference "
            << "between the recordings is not explained by the library.";
    }
    sum << qualified;
    R.summary = sum.str();
    return R;
}

namespace {
/// What an inconsistent joint fit says about which recording differs: the leave-one-out verdict when it
/// ran (three or more recordings), else, for three or more, the recording carrying most of the
/// likelihood ratio (JointFit::recordingStatistic); nothing for two recordings.
std::string whichRecordingDiffers(const JointFit& J) {
    if (!J.leftOut.empty()) {  // the leave-one-out test decides, the parts only point
        std::string d;
        int count = 0;
        for (const JointFit::LeftOut& L : J.leftOut)
            if (L.differs) d += (count++ ? ", " : "") + std::to_string(L.recording + 1);
        return count == 0 ? "; no single recording differs from the others (leave-one-out)"
                          : std::string(count == 1 ? "; recording " : "; recordings ") + d +
                                (count == 1 ? " differs" : " each differ") + " from the others (leave-one-out, p < " +
                                num(kJointConsistencyLevel, 2) + ")";
    }
    // with two recordings the split says only which one bends more to share (the less precise one)
    if (J.recordingStatistic.size() != J.recordings.size() || J.recordings.size() < 3) return "";
    double total = 0;
    std::size_t q = 0;
    for (std::size_t k = 0; k < J.recordingStatistic.size(); ++k) {
        total += J.recordingStatistic[k];
        if (J.recordingStatistic[k] > J.recordingStatistic[q]) q = k;
    }
    if (!(total > 0)) return "";
    return "; most of the ratio from recording " + std::to_string(J.recordings[q] + 1) + " (" +
           num(100 * J.recordingStatistic[q] / total, 2) + " %)";
}
} // namespace

void writeSeveralReport(const std::string& dir, const SeveralResult& R, const std::vector<Recording>& recs,
                        const std::vector<Protocol>& protos, const ExplainOptions& opt) {
    ensureDirectory(dir);
    std::vector<std::string> sub;
    for (std::size_t k = 0; k < recs.size(); ++k) {
        sub.push_back("recording_" + std::to_string(k + 1));
        writeReport(dir + "/" + sub.back(), R.per[k], recs[k], protos[k], opt);
    }
    const Model M0(makeModelInput(recs[0], protos[0]));
    const auto& defs = M0.defs();

    Json j = Json::object();
    j.set("tool", "pdpm-explain");
    j.set("seed", double(opt.seed));
    j.set("verdict", R.verdict);
    j.set("summary", R.summary);
    Json rj = Json::array();
    for (std::size_t k = 0; k < recs.size(); ++k) {
        Json o = Json::object();
        o.set("recording", recs[k].source);
        o.set("protocol", protos[k].source);
        o.set("device", protos[k].device);
        o.set("verdict", R.per[k].verdict);
        o.set("report", sub[k] + "/report.json");
        rj.push(o);
    }
    j.set("recordings", rj);
    Json mechs = Json::array();
    for (std::size_t u = 0; u < R.mechanisms.size(); ++u) {
        const int c = R.mechanisms[u];
        Json mj = Json::object();
        mj.set("name", compName(c));
        Json per = Json::array();
        double incl = 0;
        bool first = true;
        for (std::size_t k = 0; k < recs.size(); ++k)
            for (const auto& m : R.per[k].mechanisms) {
                if (m.comp != c) continue;
                const Json ps = parametersJson(m, defs);
                if (first) mj.set("parameters", ps);  // from the first recording that found it
                first = false;
                Json o = Json::object();
                o.set("recording", double(k + 1));
                o.set("parameters", ps);
                per.push(o);
                incl = std::max(incl, m.inclusionProbability);
            }
        mj.set("inclusion_probability", incl);
        mj.set("per_recording", per);
        mj.set("tested_on_heldout_recording", bool(R.testedElsewhere[u]));
        mj.set("confirmed_on_heldout_recording", bool(R.confirmed[u]));
        mj.set("found_in_recordings", double(R.foundIn[u]));
        mj.set("heldout_recording_status", R.status[u]);
        // the transfers' own answer, before the joint fit's consistency test voted (equal when it agreed)
        mj.set("heldout_recording_status_from_transfers", R.transferStatus[u]);
        mechs.push(mj);
    }
    j.set("mechanisms", mechs);
    Json wins = Json::array();
    for (std::size_t k = 0; k < recs.size(); ++k)
        for (const auto& w : R.per[k].windows) {
            Json o = windowJson(w);
            o.set("recording", double(k + 1));
            wins.push(o);
        }
    j.set("windows", wins);
    {  // the fit block of the first recording; the held-out recordings follow
        const auto& r = R.per[0];
        Json fit = Json::object();
        fit.set("rmse_baseline", r.rmseBaseline);
        fit.set("rmse_augmented", r.rmseAugmented);
        fit.set("heldout_rmse_baseline", r.heldoutBaseline);
        fit.set("heldout_rmse_augmented", r.heldoutAugmented);
        fit.set("note", "recording 1 with its own blocked cross-validation; each recording's block is in its report, "
                        "the transfer between recordings in heldout_recordings");
        j.set("fit", fit);
    }
    Json tr = Json::array();
    for (const auto& T : R.transfers) {
        Json o = Json::object();
        o.set("calibrated_on", double(T.from + 1));
        o.set("heldout_recording", double(T.to + 1));
        Json ms = Json::array();
        for (int c : T.mechanisms) ms.push(Json(compName(c)));
        o.set("mechanisms", ms);
        o.set("heldout_rmse_baseline", T.rmseBaseline);
        o.set("heldout_rmse_augmented", T.rmseAugmented);
        o.set("gain", T.gain());
        o.set("excess_gain", T.excessGain());
        o.set("evidence", T.evidence);
        o.set("term_rms_Pa", T.termRms);
        o.set("term_acts", T.acts);
        tr.push(o);
    }
    j.set("heldout_recordings", tr);
    Json jf = Json::array();
    for (const JointFit& J : R.joint) {
        Json o = Json::object();
        o.set("mechanism", compName(J.comp));
        Json used = Json::array();
        for (std::size_t k : J.recordings) used.push(Json(double(k + 1)));
        o.set("recordings", used);
        o.set("parameters", parametersJson(J.joint, defs));
        Json sep = Json::array();
        for (std::size_t q = 0; q < J.recordings.size(); ++q) {
            Json so = Json::object();
            so.set("recording", double(J.recordings[q] + 1));
            Json ps = Json::object();
            for (std::size_t a = 0; a < J.joint.params.size(); ++a) ps.set(defs[J.joint.params[a]].name, J.separate[q][a]);
            so.set("parameters", ps);
            // this recording's part of the likelihood ratio (JointFit::recordingStatistic)
            so.set("likelihood_ratio_part", J.recordingStatistic[q]);
            sep.push(so);
        }
        o.set("separate", sep);
        Json cons = Json::object();
        cons.set("likelihood_ratio", J.statistic);
        cons.set("dof", double(J.dof));
        cons.set("p_value", J.pValue);
        cons.set("level", kJointConsistencyLevel);
        cons.set("says", J.consistent ? "consistent" : "inconsistent");
        o.set("consistency", cons);
        if (!J.leftOut.empty()) {
            Json lo = Json::array();
            for (const JointFit::LeftOut& L : J.leftOut) {
                Json x = Json::object();
                x.set("recording", double(L.recording + 1));
                x.set("likelihood_ratio", L.statistic);
                x.set("dof", double(L.dof));
                x.set("p_value", L.pValue);
                x.set("others_consistent", L.othersConsistent);
                x.set("says", L.differs             ? "differs_from_the_others"
                              : !L.othersConsistent ? "the_others_disagree_among_themselves"
                                                    : "agrees_with_the_others");
                lo.push(x);
            }
            o.set("leave_one_out", lo);
        }
        o.set("profile_evaluations", double(J.evaluations));
        o.set("intervals", J.intervalMethod);
        jf.push(o);
    }
    j.set("joint_material_parameters", jf);
    j.set("joint_material_parameters_scheme",
          "profile likelihood over all recordings that accepted the mechanism or on which its transfer acts: the "
          "material parameters shared, each recording's device parameters (E, eps0, nuisances, loading curve, its other "
          "mechanisms) refitted at every trial value; 95 % intervals: likelihood-ratio scan of the profile for one "
          "material parameter, the profile's curvature for two (see intervals); consistency: "
          "likelihood ratio against each recording with its own material parameters, chi-square with "
          "(recordings - 1) x (parameters) degrees of freedom");
    j.set("heldout_recording_scheme",
          "the held-out recording is fitted with its device parameters free (E, eps0, its nuisances) and the "
          "mechanism's material parameters fixed at the values of the recording that found it");
    Json dem = Json::object();
    dem.set("status", "not_run");
    dem.set("heldout_rmse_baseline", Json());
    dem.set("heldout_rmse_augmented", Json());
    j.set("dem_confirmation", dem);
    writeJsonFile(dir + "/report.json", j);

    // held-out series and figures
    for (std::size_t q = 0; q < R.transfers.size(); ++q) {
        const Transfer& T = R.transfers[q];
        const std::string stem = dir + "/heldout_" + std::to_string(q + 1) + "_" + std::to_string(T.from + 1) + "_to_" +
                                 std::to_string(T.to + 1);
        const Recording& rec = recs[T.to];
        std::ostringstream os;
        os << "# held-out recording " << T.to + 1 << " (" << rec.source << "); mechanisms " << names(T.mechanisms)
           << " calibrated on recording " << T.from + 1 << "\n";
        os << "time_s,axial_stress_Pa,baseline_Pa,augmented_Pa\n" << std::setprecision(10);
        for (std::size_t i = 0; i < rec.size(); ++i)
            os << rec.t[i] << ',' << rec.stress[i] << ',' << T.yBaseline[i] << ',' << T.yAugmented[i] << '\n';
        writeWholeFile(stem + ".csv", os.str());
        if (!opt.figures) continue;
        std::ostringstream g;
        g << "set terminal pngcairo size 1000,500 noenhanced\nset output " << gnuplotQuote(stem + ".png.tmp") << "\n"
          << "set datafile separator ','\nset xlabel 'time (s)'\nset ylabel 'axial stress (Pa)'\nset key left top\n"
          << "set title 'held-out recording " << T.to + 1 << ": " << names(T.mechanisms) << " from recording "
          << T.from + 1 << "'\n"
          << "plot " << gnuplotQuote(stem + ".csv") << " u 1:2 w l lc rgb '#999999' t 'recording', '' u 1:3 w l lw 2 t "
          << "'baseline (RMSE " << num(T.rmseBaseline, 3) << " Pa)', '' u 1:4 w l lw 2 t 'with the transferred term(s) (RMSE "
          << num(T.rmseAugmented, 3) << " Pa)'\n";
        writeWholeFile(stem + ".gp", g.str());
        runGnuplot(stem + ".gp", {stem + ".png"});
    }

    std::ostringstream md;
    md << "# pdpm-explain report: " << recs.size() << " recordings of one material\n\n";
    md << "## Verdict: **" << R.verdict << "**\n\n" << R.summary << "\n\n";
    md << "| recording | device | verdict | own report |\n|---|---|---|---|\n";
    for (std::size_t k = 0; k < recs.size(); ++k)
        md << "| " << k + 1 << ": `" << recs[k].source << "` | " << protos[k].device << " | " << R.per[k].verdict << " | "
           << sub[k] << "/report.md |\n";
    md << "\n## Does the physics found in one recording explain the others?\n\n"
       << "Each held-out recording is fitted twice with only its device parameters free (stiffness, zero strain, "
       << "compliance, drift): with the baseline alone, and with the mechanism switched on at the material "
       << "parameters of the recording that found it (same free parameters in both fits). Evidence = n ln(RSS "
       << "without / RSS with) of the whitened residuals; a mechanism counts as confirmed when it reaches "
       << num(opt.bicThreshold, 3) << " (the acceptance threshold) on a recording where its term acts and falls "
       << "below -" << num(opt.bicThreshold, 3) << " on none.\n\n"
       << "| mechanisms | calibrated on | held-out recording | RMSE without (Pa) | RMSE with (Pa) | change | evidence | term acts |\n"
       << "|---|---|---|---|---|---|---|---|\n";
    for (const auto& T : R.transfers)
        md << "| " << names(T.mechanisms) << " | " << T.from + 1 << " | " << T.to + 1 << " | " << num(T.rmseBaseline, 4)
           << " | " << num(T.rmseAugmented, 4) << " | " << num(-100 * T.gain(), 3) << " % | " << num(T.evidence, 3) << " | "
           << (T.acts ? "yes" : "no (below what the noise lets one see)") << " |\n";
    md << "\n";
    for (std::size_t u = 0; u < R.mechanisms.size(); ++u) {
        const std::string& st = R.status[u];
        md << "- " << compName(R.mechanisms[u]) << " (found in " << R.foundIn[u] << " of " << recs.size() << "): "
           << (st == "confirmed"             ? "confirmed on a held-out recording"
               : st == "recording_dependent" ? "present in several recordings, but one set of its parameters does not "
                                               "serve them all (device, geometry or rate dependence of the effective parameter)"
               : st == "not_testable_elsewhere" ? "not testable on the other recordings (its term does not act there)"
               : st == "inconclusive"           ? "acts on another recording, but neither clearly helps nor hurts there"
                                                : "contradicted: it makes another recording fit worse")
           << (st != R.transferStatus[u]
                   ? std::string(st == "confirmed"
                                     ? " (the transferred values alone made a recording worse, but one common set fits all:"
                                     : " (the transferred values helped, but the recordings need different values:") +
                         " joint fit below)"
                   : std::string())
           << ";";
        for (std::size_t k = 0; k < recs.size(); ++k)
            for (const auto& m : R.per[k].mechanisms)
                if (m.comp == R.mechanisms[u])
                    for (std::size_t q = 0; q < m.params.size(); ++q)
                        md << " " << defs[m.params[q]].name << " = " << num(m.value[q], 3) << " (recording " << k + 1 << ")";
        md << "\n";
    }
    if (!R.joint.empty()) {
        md << "\n## One set of material parameters for all recordings?\n\n"
           << "A mechanism's parameters belong to the material; stiffness, zero strain, compliance and drift belong "
           << "to the device. Each mechanism below is fitted to the recordings it acts on together (the material "
           << "parameters shared, every recording's device parameters refitted), and once more with each recording "
           << "keeping its own material parameters. The likelihood ratio of the two tells whether one set explains "
           << "them all (p >= " << num(kJointConsistencyLevel, 2) << ") or the effective parameter differs between "
           << "devices, geometries or rates.\n\n"
           << "| mechanism | recordings | joint value (95 %) | each recording alone | likelihood ratio (dof) | p | says |\n"
           << "|---|---|---|---|---|---|---|\n";
        for (const JointFit& J : R.joint) {
            std::string used, joint, alone;
            for (std::size_t q = 0; q < J.recordings.size(); ++q) used += (q ? ", " : "") + std::to_string(J.recordings[q] + 1);
            for (std::size_t a = 0; a < J.joint.params.size(); ++a)
                joint += std::string(a ? "; " : "") + defs[J.joint.params[a]].name + " = " + num(J.joint.value[a], 3) + " (" +
                         (J.intervalMethod != "not_determined" ? num(J.joint.lo[a], 3) + " to " + num(J.joint.hi[a], 3) : std::string("interval not determined")) + ")";
            for (std::size_t q = 0; q < J.recordings.size(); ++q) {
                alone += std::string(q ? "; " : "") + std::to_string(J.recordings[q] + 1) + ":";
                for (std::size_t a = 0; a < J.joint.params.size(); ++a)
                    alone += std::string(a ? "," : "") + " " + defs[J.joint.params[a]].name + " = " + num(J.separate[q][a], 3);
            }
            md << "| " << compName(J.comp) << " | " << used << " | " << joint << " | " << alone << " | "
               << num(J.statistic, 3) << " (" << J.dof << ") | " << num(J.pValue, 2) << " | "
               << (J.consistent ? "one set explains all" : "the recordings need different values" + whichRecordingDiffers(J)) << " |\n";
        }
    }
    writeWholeFile(dir + "/report.md", md.str());
}

} // namespace pdpm::explain
