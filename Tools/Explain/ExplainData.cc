#include "ExplainData.h"

#include <algorithm>
#include <limits>
#include <cmath>
#include <sstream>

#include "Core/Error.h"
#include "Core/Parameters.h"
#include "IO/Json.h"
#include "Recording.h"

namespace pdpm::explain {

const char* stepTypeName(StepType t) {
    switch (t) {
    case StepType::Ramp: return "ramp";
    case StepType::Hold: return "hold";
    case StepType::Unload: return "unload";
    case StepType::Creep: return "creep";
    }
    return "?";
}

const char* phaseName(Phase p) {
    switch (p) {
    case Phase::Load: return "load";
    case Phase::Hold: return "hold";
    case Phase::Unload: return "unload";
    case Phase::Reload: return "reload";
    }
    return "?";
}


// Protocol files are in the one documented format (Documentation/recording-format.md), read by the
// shared recording library; this converts to the explainer's view of the steps.
Protocol readProtocol(const std::string& path) {
    const recording::Protocol rp = recording::readProtocol(path);
    Protocol p;
    p.source = path;
    p.device = rp.device;
    const Json* name = rp.material.isObject() ? rp.material.find("name") : nullptr;
    p.material = name && name->isString() ? name->asString() : rp.material.dump(0);
    p.diameter = rp.diameter;  // 0: laterally periodic (no side wall)
    p.height = rp.height;
    p.zeroBeforeContact = rp.zeroBeforeContact;
    if (!(p.height > 0)) inputError(path + ": device.height_m must be > 0 (the explainer converts piston travel to strain)");
    if (rp.steps.empty()) inputError(path + ": steps is empty");
    for (const auto& st : rp.steps) {
        ProtocolStep q;
        switch (st.kind) {
        case recording::Step::Kind::Ramp: q.type = StepType::Ramp; break;
        case recording::Step::Kind::HoldPosition: q.type = StepType::Hold; break;
        case recording::Step::Kind::Unload: q.type = StepType::Unload; break;
        case recording::Step::Kind::HoldStress: q.type = StepType::Creep; break;
        }
        if (st.kind == recording::Step::Kind::Ramp || st.kind == recording::Step::Kind::Unload) {
            q.velocity = st.velocity;
            q.targetStress = st.targetStress;
            if (st.targetStress < 0) {  // an unload into tension (recording format: a negative target)
                q.tension = -st.targetStress;
                q.targetStress = -1;
            }
        } else {
            q.duration = st.duration;
        }
        p.steps.push_back(q);
    }
    return p;
}

recording::Protocol toRecordingProtocol(const Protocol& p) {
    recording::Protocol rp;
    rp.source = "experiment";
    rp.device = p.device.empty() ? "oedometer" : p.device;
    rp.diameter = p.diameter;
    rp.height = p.height;
    rp.zeroBeforeContact = p.zeroBeforeContact;
    rp.material = Json::object();
    rp.material.set("name", p.material);
    for (const auto& s : p.steps) {
        recording::Step st;
        switch (s.type) {
        case StepType::Ramp: st.kind = recording::Step::Kind::Ramp; break;
        case StepType::Hold: st.kind = recording::Step::Kind::HoldPosition; break;
        case StepType::Unload: st.kind = recording::Step::Kind::Unload; break;
        case StepType::Creep: st.kind = recording::Step::Kind::HoldStress; break;
        }
        st.velocity = s.velocity > 0 ? s.velocity : 0;
        st.targetStress = s.targetStress > 0 ? s.targetStress : 0;
        if (s.type == StepType::Unload && s.tension > 0) st.targetStress = -s.tension;
        st.duration = s.duration > 0 ? s.duration : 0;
        rp.steps.push_back(st);
    }
    return rp;
}

Recording readRecording(const std::string& path, const Protocol& proto) {
    // the documented recording format, checked as pdpm-recording-check does (header, units, finite
    // numbers, time_s strictly increasing, at least one measured channel): the first problem found
    // ends the run with its line number
    const recording::Recording tab = recording::readRecording(path);
    const auto has = [&](const char* name) { return tab.column(name) >= 0; };
    // a sample's position in the file, as the checker reports it ("PATH:LINE: ...")
    const auto at = [&](std::size_t i) {
        return path + ":" + std::to_string(i < tab.rowLines.size() ? tab.rowLines[i] : long(i) + 1) + ": ";
    };
    Recording r;
    r.source = path;
    if (tab.rows.size() < 20) inputError(path + ": " + std::to_string(tab.rows.size()) + " samples; at least 20 are needed");
    r.t = tab.values("time_s");
    if (!has("axial_stress_Pa"))
        inputError(path + ": pdpm-explain needs the response column axial_stress_Pa");
    r.stress = tab.values("axial_stress_Pa");
    if (has("axial_strain")) {
        r.strain = tab.values("axial_strain");
        r.strainSource = "axial_strain";
    } else if (has("piston_position_m")) {
        const auto z = tab.values("piston_position_m");
        r.strain.resize(z.size());
        for (std::size_t i = 0; i < z.size(); ++i) r.strain[i] = (z[0] - z[i]) / proto.height;
        r.strainSource = "piston_position_m";
    } else {
        inputError(path + ": pdpm-explain needs a control channel: axial_strain or piston_position_m");
    }
    for (std::size_t i = 0; i < r.strain.size(); ++i)
        if (!(std::abs(r.strain[i]) < 1))
            inputError(at(i) + "axial strain " + formatDoubleShort(r.strain[i]) + " (from " + r.strainSource +
                       ") is not in (-1, 1)");
    if (has("lateral_stress_Pa")) r.lateral = tab.values("lateral_stress_Pa");
    if (has("bottom_stress_Pa")) r.bottom = tab.values("bottom_stress_Pa");
    if (has("step")) {
        const std::vector<double> st = tab.values("step");
        for (std::size_t i = 0; i < st.size(); ++i) {
            if (!(st[i] >= 0) || st[i] != std::floor(st[i]) || st[i] >= double(std::max<std::size_t>(proto.steps.size(), 1)))
                inputError(at(i) + "step " + formatDoubleShort(st[i]) + " is not a step of the protocol (" +
                           std::to_string(proto.steps.size()) + " steps)");
            r.step.push_back(static_cast<int>(st[i]));
        }
    }
    // magnitudes far beyond any powder test would overflow the squared residuals of the fits
    const auto bounded = [&](const std::vector<double>& col, const char* name, double limit, const char* unit) {
        for (std::size_t i = 0; i < col.size(); ++i)
            if (!(std::abs(col[i]) <= limit))
                inputError(at(i) + name + " " + formatDoubleShort(col[i]) + " is beyond +-" + formatDoubleShort(limit) +
                           " " + unit);
    };
    bounded(r.t, "time_s", 1e12, "s");
    bounded(r.stress, "axial_stress_Pa", 1e12, "Pa");
    bounded(r.lateral, "lateral_stress_Pa", 1e12, "Pa");
    bounded(r.bottom, "bottom_stress_Pa", 1e12, "Pa");
    double smax = 0, emin = r.strain[0], emax = r.strain[0];
    for (std::size_t i = 0; i < r.size(); ++i) {
        smax = std::max(smax, std::abs(r.stress[i]));
        emin = std::min(emin, r.strain[i]);
        emax = std::max(emax, r.strain[i]);
    }
    if (!(smax > 0)) inputError(path + ": axial_stress_Pa is zero throughout");
    if (!(emax > emin)) inputError(path + ": the control channel (" + r.strainSource + ") never changes");
    return r;
}

std::vector<char> creepSamples(const Recording& rec, const Protocol& proto) {
    std::vector<char> c(rec.size(), 0);
    if (rec.step.size() != rec.size()) return c;
    for (std::size_t i = 0; i < rec.size(); ++i) {
        const auto k = static_cast<std::size_t>(rec.step[i]);
        c[i] = k < proto.steps.size() && proto.steps[k].type == StepType::Creep;
    }
    return c;
}

std::vector<PhaseSegment> recordPhases(const Recording& rec, const Protocol& proto) {
    std::vector<PhaseSegment> ph = detectPhases(rec.t, rec.strain);
    const std::vector<char> creep = creepSamples(rec, proto);
    const std::size_t n = rec.size();
    for (std::size_t a = 0; a < n;) {
        if (!creep[a]) {
            ++a;
            continue;
        }
        std::size_t b = a;
        while (b < n && creep[b] && rec.step[b] == rec.step[a]) ++b;
        // [a, b) is one creep step: cut the segments that overlap it and put a Hold in their place
        std::vector<PhaseSegment> out;
        for (const PhaseSegment& s : ph) {
            if (s.end <= a || s.begin >= b) {
                out.push_back(s);
                continue;
            }
            if (s.begin < a) out.push_back({s.phase, s.begin, a});
            if (s.end > b) out.push_back({s.phase, b, s.end});
        }
        out.push_back({Phase::Hold, a, b});
        std::sort(out.begin(), out.end(), [](const PhaseSegment& x, const PhaseSegment& y) { return x.begin < y.begin; });
        ph = std::move(out);
        a = b;
    }
    return ph;
}

void checkConsistency(const Recording& rec, const Protocol& proto) {
    double total = 0;
    bool all = true;
    for (const auto& s : proto.steps) {
        if (s.duration < 0) all = false;
        else total += s.duration;
    }
    const double span = rec.t.back() - rec.t.front();
    // Steps without a duration (ramps to a stress or strain target) only add time: the known
    // durations alone may not exceed the recording; with every duration known, the sum must match it.
    if (total > 0 && (total > 1.25 * span + 1 || (all && total < 0.75 * span - 1))) {
        std::ostringstream os;
        os << "protocol " << proto.source << (all ? " lasts " : " lasts at least ") << total << " s (sum of duration_s) but recording "
           << rec.source << " spans " << span << " s: they do not describe the same test";
        inputError(os.str());
    }
    double smax = 0;
    for (double s : rec.stress) smax = std::max(smax, s);
    for (std::size_t i = 0; i < proto.steps.size(); ++i) {
        const double ts = proto.steps[i].targetStress;
        if (ts > 0 && ts > 2.0 * smax + 1) {
            std::ostringstream os;
            os << "protocol step " << i << " targets " << ts << " Pa but recording " << rec.source
               << " never exceeds " << smax << " Pa: inconsistent inputs";
            inputError(os.str());
        }
    }
}

std::vector<double> smoothedRate(const std::vector<double>& t, const std::vector<double>& x, int hw) {
    const std::size_t n = t.size();
    std::vector<double> r(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t a = i >= std::size_t(hw) ? i - hw : 0;
        const std::size_t b = std::min(n - 1, i + hw);
        double st = 0, sx = 0;
        const double m = double(b - a + 1);
        for (std::size_t k = a; k <= b; ++k) { st += t[k]; sx += x[k]; }
        st /= m; sx /= m;
        double stt = 0, stx = 0;
        for (std::size_t k = a; k <= b; ++k) {
            stt += (t[k] - st) * (t[k] - st);
            stx += (t[k] - st) * (x[k] - sx);
        }
        r[i] = stt > 0 ? stx / stt : 0;
    }
    return r;
}

std::vector<PhaseSegment> detectPhases(const std::vector<double>& t, const std::vector<double>& e) {
    const std::size_t n = t.size();
    const int hw = std::max(1, int(n / 800));
    const auto rate = smoothedRate(t, e, hw);
    std::vector<double> a;
    for (double r : rate) a.push_back(std::abs(r));
    std::vector<double> s = a;
    std::sort(s.begin(), s.end());
    double typical = s[std::size_t(0.95 * (n - 1))];
    double mean = 0;
    for (double r : s) mean += r / double(n);
    if (typical < 0.1 * mean) {
        // ramps are less than 5 % of the samples (long holds, fast ramps): the 95th percentile is a
        // hold's round-off; take the median rate of the samples that move (above 10 % of the mean
        // rate; the median, not the fastest, so that a glitch in the strain does not set the scale)
        const auto first = std::upper_bound(s.begin(), s.end(), 0.1 * mean);
        typical = *(first + (s.end() - first - 1) / 2);
    }
    const double thr = 0.02 * typical;
    std::vector<Phase> ph(n);
    double emax = e[0];
    const double range = *std::max_element(e.begin(), e.end()) - *std::min_element(e.begin(), e.end());
    for (std::size_t i = 0; i < n; ++i) {
        if (a[i] <= thr) ph[i] = Phase::Hold;
        else if (rate[i] < 0) ph[i] = Phase::Unload;
        else ph[i] = (e[i] < emax - 1e-3 * range) ? Phase::Reload : Phase::Load;
        emax = std::max(emax, e[i]);
    }
    std::vector<PhaseSegment> seg;
    for (std::size_t i = 0; i < n;) {
        std::size_t j = i;
        while (j < n && ph[j] == ph[i]) ++j;
        seg.push_back({ph[i], i, j});
        i = j;
    }
    // merge pieces shorter than the smoothing window into the longer neighbour
    const std::size_t minLen = std::size_t(2 * hw + 2);
    bool changed = true;
    while (changed && seg.size() > 1) {
        changed = false;
        for (std::size_t k = 0; k < seg.size(); ++k) {
            if (seg[k].end - seg[k].begin >= minLen) continue;
            std::size_t into;
            if (k == 0) into = 1;
            else if (k + 1 == seg.size()) into = k - 1;
            else into = (seg[k - 1].end - seg[k - 1].begin >= seg[k + 1].end - seg[k + 1].begin) ? k - 1 : k + 1;
            seg[into].begin = std::min(seg[into].begin, seg[k].begin);
            seg[into].end = std::max(seg[into].end, seg[k].end);
            seg.erase(seg.begin() + long(k));
            changed = true;
            break;
        }
        for (std::size_t k = 1; k < seg.size();) {
            if (seg[k].phase == seg[k - 1].phase) {
                seg[k - 1].end = seg[k].end;
                seg.erase(seg.begin() + long(k));
            } else {
                ++k;
            }
        }
    }
    return seg;
}

std::size_t holdReach(std::size_t n) { return 2 * std::max<std::size_t>(1, n / 800) + 3; }

bool atHoldStrain(double strain, double eh) { return std::fabs(strain - eh) <= 1e-9 * std::max(1e-12, std::fabs(eh)); }

PhaseSegment holdExtent(const std::vector<double>& strain, const PhaseSegment& hold) {
    const std::size_t n = strain.size();
    if (hold.end <= hold.begin || hold.end > n) return hold;
    const std::size_t mid = hold.begin + (hold.end - hold.begin) / 2, reach = holdReach(n);
    const double eh = strain[mid];
    const std::size_t bMin = hold.begin > reach ? hold.begin - reach : 0, eMax = std::min(n, hold.end + reach);
    std::size_t b = mid, e = mid + 1;
    while (b > bMin && atHoldStrain(strain[b - 1], eh)) --b;
    while (e < eMax && atHoldStrain(strain[e], eh)) ++e;
    if (2 * (e - b) < hold.end - hold.begin) return hold;  // a noisy control channel
    if (e < n) --e;  // the last sample at the hold's strain may be the next ramp's first
    return {hold.phase, b, e};
}

Transmission loadingTransmission(const std::vector<double>& t, const std::vector<double>& e, const std::vector<double>& s,
                                 const std::vector<double>& b) {
    Transmission out;
    if (b.size() != s.size() || s.size() != e.size()) return out;
    // the first loading: its Load phases and the holds that follow one, up to the first unload
    std::vector<std::size_t> first;
    std::vector<std::pair<std::size_t, std::size_t>> loads;
    bool loaded = false;
    for (const PhaseSegment& seg : detectPhases(t, e)) {
        if (seg.phase == Phase::Unload || seg.phase == Phase::Reload) break;
        if (seg.phase == Phase::Load) loaded = true, loads.push_back({seg.begin, seg.end});
        if (seg.phase == Phase::Load || (seg.phase == Phase::Hold && loaded))
            for (std::size_t i = seg.begin; i < seg.end; ++i) first.push_back(i);
    }
    // where the loading passes 30 % of its top, judged on the piston stress smoothed within each Load
    // phase (a centred moving average of up to 21 samples), so that the cut is a strain and no
    // sample is kept or dropped for its own noise
    // (the window shrinks to the raw sample at a ramp's ends: ramps of a few samples between long
    // holds, as in the DEM-made records, would otherwise lose their crossing sample and the cut would
    // move past the first hold; one sample's noise moves the 30 % level by a negligible amount)
    std::vector<double> sm(s.size(), std::nan(""));
    double top = 0;
    for (auto [lo, hi] : loads)
        for (std::size_t i = lo; i < hi; ++i) {
            const std::size_t w = std::min<std::size_t>({10, i - lo, hi - 1 - i});
            double sum = 0;
            int cnt = 0;
            for (std::size_t k = i - w; k <= i + w; ++k)
                if (std::isfinite(s[k])) sum += s[k], ++cnt;
            if (cnt > 0) sm[i] = sum / cnt, top = std::max(top, sm[i]);
        }
    double eCut = std::numeric_limits<double>::infinity();
    for (auto [lo, hi] : loads)
        for (std::size_t i = lo; i < hi && !(eCut < std::numeric_limits<double>::infinity()); ++i)
            if (top > 0 && std::isfinite(sm[i]) && sm[i] >= 0.3 * top) eCut = e[i];
    std::vector<std::size_t> idx;
    for (std::size_t i : first)
        if (e[i] >= eCut && std::isfinite(b[i]) && std::isfinite(s[i])) idx.push_back(i);
    const double n = static_cast<double>(idx.size());
    if (idx.size() < 5) return out;
    // instrumental variable: the strain (the control channel) is uncorrelated with the noise of both
    // stress channels, so cov(b, e) / cov(s, e) is not biased towards 0 by the piston stress's own
    // noise, as the least-squares slope cov(b, s) / var(s) is (errors in the regressor)
    double ms = 0, mb = 0, me = 0;
    for (std::size_t i : idx) ms += s[i], mb += b[i], me += e[i];
    ms /= n, mb /= n, me /= n;
    double szz = 0, ssz = 0, sbz = 0;
    for (std::size_t i : idx) {
        const double z = e[i] - me;
        szz += z * z, ssz += (s[i] - ms) * z, sbz += (b[i] - mb) * z;
    }
    if (!(szz > 0) || !(std::abs(ssz) > 0)) return out;
    out.slope = sbz / ssz;
    out.intercept = mb - out.slope * ms;
    out.samples = static_cast<int>(idx.size());
    // residual sd and lag-1 autocorrelation (consecutive samples): n_eff = n (1 - r)/(1 + r);
    // var(slope) = s_u^2 szz / ssz^2 (instrumental-variable form) times n / n_eff
    double ss = 0, s01 = 0, prev = 0;
    for (std::size_t k = 0; k < idx.size(); ++k) {
        const double r = b[idx[k]] - out.intercept - out.slope * s[idx[k]];
        ss += r * r;
        if (k > 0 && idx[k] == idx[k - 1] + 1) s01 += r * prev;  // adjacent samples only
        prev = r;
    }
    const double rho = ss > 0 ? std::clamp(s01 / ss, 0.0, 0.99) : 0.0;
    const double nEff = std::max(3.0, n * (1 - rho) / (1 + rho));
    out.se = std::sqrt(ss / (n - 2) * szz / (ssz * ssz) * n / nEff);
    out.residualSd = std::sqrt(ss / (n - 2));
    out.nEff = nEff;
    // blocked cross-validation over 4 contiguous parts of the samples
    const std::size_t parts = 4;
    if (idx.size() >= 5 * parts) {
        double eNo = 0, eFit = 0;
        for (std::size_t f = 0; f < parts; ++f) {
            const std::size_t lo = idx.size() * f / parts, hi = idx.size() * (f + 1) / parts;
            double m = 0, ts = 0, tb = 0, te = 0;
            for (std::size_t k = 0; k < idx.size(); ++k)
                if (k < lo || k >= hi) ts += s[idx[k]], tb += b[idx[k]], te += e[idx[k]], m += 1;
            ts /= m, tb /= m, te /= m;
            double z2 = 0, sz = 0, bz = 0;
            for (std::size_t k = 0; k < idx.size(); ++k)
                if (k < lo || k >= hi) {
                    const double z = e[idx[k]] - te;
                    z2 += z * z, sz += (s[idx[k]] - ts) * z, bz += (b[idx[k]] - tb) * z;
                }
            const double slope = std::abs(sz) > 0 ? bz / sz : 1.0, icpt = tb - slope * ts;
            const double slopeNo = std::clamp(slope, 1 - kMinWallLoss, 1.0), icptNo = tb - slopeNo * ts;
            for (std::size_t k = lo; k < hi; ++k) {
                const double rn = b[idx[k]] - icptNo - slopeNo * s[idx[k]], rf = b[idx[k]] - icpt - slope * s[idx[k]];
                eNo += rn * rn, eFit += rf * rf;
            }
        }
        out.heldoutNoLoss = std::sqrt(eNo / n);
        out.heldoutFitted = std::sqrt(eFit / n);
    }
    return out;
}

} // namespace pdpm::explain
