#include "Recording.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include "Core/Error.h"
#include "Core/Parameters.h"
#include "IO/AtomicFile.h"
#include "IO/NumberFormat.h"

namespace pdpm::recording {

const std::vector<ChannelInfo>& knownChannels() {
    static const std::vector<ChannelInfo> c = {
        {"time_s", "lab time (s), strictly increasing", false},
        {"axial_stress_Pa", "axial (piston, top) stress (Pa), compression positive", true},
        {"axial_strain", "axial strain (L0 - L)/L0 (-), compression positive", true},
        {"piston_position_m", "piston height above the bottom (m)", true},
        {"lateral_stress_Pa", "lateral (wall) stress averaged over the mould wall (Pa)", true},
        {"bottom_stress_Pa", "stress on the bottom plate (Pa)", true},
        {"volume_fraction", "solid volume fraction (-), in (0, 1)", true},
        {"step", "protocol step index (0-based integer)", false},
        {"dem_time_s", "simulation (DEM) time (s), simulations only", false},
        {"Ek_over_Ep", "kinetic over elastic energy (-), simulations only", false},
        {"inertial_number", "inertial number of the piston motion (-), simulations only", false},
    };
    return c;
}

int Recording::column(const std::string& name) const {
    for (std::size_t k = 0; k < columns.size(); ++k)
        if (columns[k] == name) return static_cast<int>(k);
    return -1;
}

std::vector<double> Recording::values(const std::string& name) const {
    const int c = column(name);
    if (c < 0) inputError("recording has no column '" + name + "'");
    std::vector<double> v;
    v.reserve(rows.size());
    for (const auto& r : rows) v.push_back(r[static_cast<std::size_t>(c)]);
    return v;
}

namespace {

bool validName(const std::string& s) {
    if (s.empty() || !(std::islower(static_cast<unsigned char>(s[0])) || std::isupper(static_cast<unsigned char>(s[0]))))
        return false;
    for (char c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
    return true;
}

/// A known quantity spelled with another unit ("axial_stress_kPa", "time_ms", "piston_position_mm").
std::string wrongUnit(const std::string& name) {
    static const std::vector<std::pair<std::string, std::string>> bases = {
        {"time_", "time_s"},
        {"axial_stress_", "axial_stress_Pa"},
        {"lateral_stress_", "lateral_stress_Pa"},
        {"bottom_stress_", "bottom_stress_Pa"},
        {"piston_position_", "piston_position_m"},
        {"dem_time_", "dem_time_s"},
    };
    // only a unit after the base counts: "time_stamp" or "axial_stress_Pa_raw" are extra channels
    static const std::vector<std::string> units = {"s", "ms", "us", "ns", "min", "h", "hr", "Pa", "hPa", "kPa", "MPa", "GPa",
                                                   "bar", "mbar", "psi", "N", "kN", "m", "cm", "mm", "um", "percent", "pct"};
    for (const auto& [b, want] : bases)
        if (name.rfind(b, 0) == 0 && name != want &&
            std::find(units.begin(), units.end(), name.substr(b.size())) != units.end())
            return want;
    if (name == "axial_strain_percent" || name == "volume_fraction_percent" || name == "axial_strain_pct")
        return name.substr(0, name.find("_p"));
    if (name == "time" || name == "axial_stress" || name == "lateral_stress" || name == "bottom_stress" ||
        name == "piston_position")
        return name == "time" ? "time_s" : (name == "piston_position" ? "piston_position_m" : name + "_Pa");
    return "";
}

std::string trim(const std::string& s) {
    std::size_t a = 0, b = s.size();
    while (a < b && (s[a] == ' ' || s[a] == '\t')) ++a;
    while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t' || s[b - 1] == '\r')) --b;
    return s.substr(a, b - a);
}

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::string cur;
    for (char c : s) {
        if (c == ',') {
            out.push_back(trim(cur));
            cur.clear();
        } else {
            cur += c;
        }
    }
    out.push_back(trim(cur));
    return out;
}

} // namespace

std::vector<Problem> checkRecording(const std::string& text, Recording* out) {
    std::vector<Problem> problems;
    auto problem = [&](long line, const std::string& m) {
        if (problems.size() < 100) problems.push_back({line, m});
    };
    Recording rec;
    std::istringstream is(text);
    std::string line;
    long lineNo = 0;
    bool haveHeader = false;
    int timeCol = -1, stepCol = -1, vfCol = -1, strainCol = -1;
    std::vector<int> nonNegative;
    double lastTime = 0;
    long lastTimeLine = 0;
    while (std::getline(is, line)) {
        ++lineNo;
        const std::string t = trim(line);
        if (t.empty()) continue;
        if (t[0] == '#') {
            std::string c = t.substr(1);
            if (!c.empty() && c[0] == ' ') c = c.substr(1);
            rec.comments.push_back(c);
            continue;
        }
        if (!haveHeader) {
            haveHeader = true;
            rec.columns = split(t);
            bool measured = false;
            for (std::size_t k = 0; k < rec.columns.size(); ++k) {
                const std::string& n = rec.columns[k];
                if (!validName(n)) {
                    problem(lineNo, "column " + std::to_string(k + 1) + ": invalid name '" + n +
                                        "' (letters, digits, '_', starting with a letter)");
                    continue;
                }
                for (std::size_t q = 0; q < k; ++q)
                    if (rec.columns[q] == n) problem(lineNo, "duplicate column '" + n + "'");
                const std::string w = wrongUnit(n);
                if (!w.empty()) problem(lineNo, "column '" + n + "': wrong unit, use '" + w + "' (SI units)");
                for (const auto& ch : knownChannels())
                    if (n == ch.name && ch.measured) measured = true;
                if (n == "time_s") timeCol = static_cast<int>(k);
                if (n == "step") stepCol = static_cast<int>(k);
                if (n == "volume_fraction") vfCol = static_cast<int>(k);
                if (n == "axial_strain") strainCol = static_cast<int>(k);
                if (n == "Ek_over_Ep" || n == "inertial_number") nonNegative.push_back(static_cast<int>(k));
            }
            if (timeCol < 0) problem(lineNo, "missing required column 'time_s'");
            if (!measured)
                problem(lineNo, "no measured channel (need at least one of axial_stress_Pa, axial_strain, "
                                "piston_position_m, lateral_stress_Pa, bottom_stress_Pa, volume_fraction)");
            continue;
        }
        const std::vector<std::string> cells = split(t);
        if (cells.size() != rec.columns.size()) {
            problem(lineNo, "expected " + std::to_string(rec.columns.size()) + " values, found " +
                                std::to_string(cells.size()));
            continue;
        }
        std::vector<double> row(cells.size(), 0.0);
        bool ok = true;
        for (std::size_t k = 0; k < cells.size(); ++k) {
            double x = 0;
            if (!parseStrictDouble(cells[k], x)) {
                const std::string what = cells[k].empty() ? "empty value" : "'" + cells[k] + "' is not a finite number";
                problem(lineNo, "column '" + rec.columns[k] + "': " + what);
                ok = false;
                continue;
            }
            row[k] = x;
        }
        if (!ok) continue;
        if (timeCol >= 0) {
            const double tt = row[static_cast<std::size_t>(timeCol)];
            if (!rec.rows.empty() && !(tt > lastTime))
                problem(lineNo, "time_s not strictly increasing (" + fmt(tt) + " after " + fmt(lastTime) +
                                    " on line " + std::to_string(lastTimeLine) + ")");
            lastTime = tt;
            lastTimeLine = lineNo;
        }
        if (stepCol >= 0) {
            const double s = row[static_cast<std::size_t>(stepCol)];
            if (!(s >= 0) || s != std::floor(s)) problem(lineNo, "step must be a non-negative integer (got " + fmt(s) + ")");
        }
        if (vfCol >= 0) {
            const double v = row[static_cast<std::size_t>(vfCol)];
            if (!(v > 0 && v < 1)) problem(lineNo, "volume_fraction " + fmt(v) + " outside (0, 1) (a fraction, not percent)");
        }
        if (strainCol >= 0) {
            const double e = row[static_cast<std::size_t>(strainCol)];
            if (!(e > -1 && e < 1)) problem(lineNo, "axial_strain " + fmt(e) + " outside (-1, 1) (a fraction, not percent)");
        }
        for (int c : nonNegative)
            if (row[static_cast<std::size_t>(c)] < 0)
                problem(lineNo, "column '" + rec.columns[static_cast<std::size_t>(c)] + "' must be >= 0");
        rec.rows.push_back(std::move(row));
        rec.rowLines.push_back(lineNo);
    }
    if (!haveHeader) problem(0, "no header line (file empty or only comments)");
    else if (rec.rows.empty() && problems.empty()) problem(lineNo, "no data rows");
    if (problems.empty() && out) *out = std::move(rec);
    return problems;
}

Recording readRecording(const std::string& path) {
    Recording r;
    const auto p = checkRecording(readWholeFile(path), &r);
    if (!p.empty()) inputError(path + ":" + std::to_string(p[0].line) + ": " + p[0].message);
    return r;
}

void writeRecording(const std::string& path, const Recording& r) {
    std::string text;
    for (const auto& c : r.comments) text += "# " + c + "\n";
    for (std::size_t k = 0; k < r.columns.size(); ++k) {
        if (k) text += ',';
        text += r.columns[k];
    }
    text += '\n';
    for (const auto& row : r.rows) {
        if (row.size() != r.columns.size()) inputError(path + ": ragged recording row");
        for (std::size_t k = 0; k < row.size(); ++k) {
            if (k) text += ',';
            text += formatDouble(row[k]);
        }
        text += '\n';
    }
    const auto p = checkRecording(text);
    if (!p.empty()) inputError(path + ": refusing to write an invalid recording: line " + std::to_string(p[0].line) + ": " + p[0].message);
    writeWholeFile(path, text);
}

// ---- protocol ------------------------------------------------------------------------------------

const char* stepTypeName(Step::Kind k) {
    switch (k) {
        case Step::Kind::Ramp: return "ramp";
        case Step::Kind::HoldPosition: return "hold_position";
        case Step::Kind::Unload: return "unload";
        case Step::Kind::HoldStress: return "hold_stress";
    }
    return "?";
}

namespace {
void checkStep(const Step& s, const std::string& where) {
    auto pos = [&](double v, const std::string& key) {
        if (!(v > 0) || !std::isfinite(v)) inputError(where + "." + key + ": must be > 0 (got " + fmt(v) + ")");
    };
    switch (s.kind) {
        case Step::Kind::Ramp:
            pos(s.velocity, "velocity_m_s");
            if (!(s.targetStress >= 0) || !std::isfinite(s.targetStress))
                inputError(where + ".target_stress_Pa: must be >= 0 (got " + fmt(s.targetStress) + ")");
            break;
        case Step::Kind::Unload:  // a negative target is a tension (lift-off test of a cohesive bed)
            pos(s.velocity, "velocity_m_s");
            if (!std::isfinite(s.targetStress))
                inputError(where + ".target_stress_Pa: must be a finite number (got " + fmt(s.targetStress) + ")");
            break;
        case Step::Kind::HoldPosition: pos(s.duration, "duration_s"); break;
        case Step::Kind::HoldStress:
            pos(s.duration, "duration_s");
            if (s.stress >= 0 && !(s.stress > 0)) inputError(where + ".stress_Pa: must be > 0");
            break;
    }
}
} // namespace

Json protocolToJson(const Protocol& p) {
    Json j = Json::object();
    j.set("format", "pdpm-oedometer-protocol");
    j.set("version", 1);
    j.set("source", p.source);
    Json dev = Json::object();
    dev.set("name", p.device);
    dev.set("diameter_m", p.diameter);
    dev.set("height_m", p.height);
    dev.set("wall_friction", p.wallFriction);
    if (p.zeroBeforeContact) dev.set("zero_before_contact", true);
    j.set("device", dev);
    j.set("material", p.material);
    Json steps = Json::array();
    for (const Step& s : p.steps) {
        Json o = Json::object();
        o.set("type", stepTypeName(s.kind));
        switch (s.kind) {
            case Step::Kind::Ramp:
            case Step::Kind::Unload:
                o.set("velocity_m_s", s.velocity);
                o.set("target_stress_Pa", s.targetStress);
                break;
            case Step::Kind::HoldPosition: o.set("duration_s", s.duration); break;
            case Step::Kind::HoldStress:
                o.set("duration_s", s.duration);
                if (s.stress >= 0) o.set("stress_Pa", s.stress);
                break;
        }
        steps.push(o);
    }
    j.set("steps", steps);
    if (p.extra.size() > 0) j.set("extra", p.extra);
    return j;
}

Protocol protocolFromJson(const Json& j) {
    j.asObject("protocol");
    static const std::vector<std::string> topKeys = {"format", "version", "source", "device", "material", "steps", "extra"};
    for (const auto& [k, v] : j.asObject()) {
        if (std::find(topKeys.begin(), topKeys.end(), k) == topKeys.end()) inputError("protocol: unknown key '" + k + "'");
    }
    if (j.at("format").asString("format") != "pdpm-oedometer-protocol")
        inputError("format: expected 'pdpm-oedometer-protocol'");
    if (j.at("version").asNumber("version") != 1) inputError("version: only version 1 is known");
    Protocol p;
    if (const Json* s = j.find("source")) {
        p.source = s->asString("source");
        if (p.source != "simulation" && p.source != "experiment") inputError("source: must be 'simulation' or 'experiment'");
    }
    const Json& d = j.at("device");
    p.device = d.at("name").asString("device.name");
    if (const Json* x = d.find("diameter_m")) p.diameter = x->asNumber("device.diameter_m");
    if (const Json* x = d.find("height_m")) p.height = x->asNumber("device.height_m");
    if (const Json* x = d.find("wall_friction")) p.wallFriction = x->asNumber("device.wall_friction");
    if (const Json* x = d.find("zero_before_contact")) p.zeroBeforeContact = x->asBool("device.zero_before_contact");
    if (p.diameter < 0 || p.height < 0 || p.wallFriction < 0) inputError("device: dimensions and wall_friction must be >= 0");
    if (const Json* m = j.find("material")) {
        m->asObject("material");
        p.material = *m;
    }
    if (const Json* e = j.find("extra")) {
        e->asObject("extra");
        p.extra = *e;
    }
    const auto& steps = j.at("steps").asArray("steps");
    if (steps.empty()) inputError("steps: at least one step is needed");
    for (std::size_t k = 0; k < steps.size(); ++k) {
        const std::string where = "steps[" + std::to_string(k) + "]";
        const Json& o = steps[k];
        o.asObject(where);
        const std::string type = o.at("type").asString(where + ".type");
        Step s;
        std::vector<std::string> allowed;
        if (type == "ramp" || type == "unload") {
            s.kind = type == "ramp" ? Step::Kind::Ramp : Step::Kind::Unload;
            s.velocity = o.at("velocity_m_s").asNumber(where + ".velocity_m_s");
            s.targetStress = o.at("target_stress_Pa").asNumber(where + ".target_stress_Pa");
            allowed = {"type", "velocity_m_s", "target_stress_Pa"};
        } else if (type == "hold_position") {
            s.kind = Step::Kind::HoldPosition;
            s.duration = o.at("duration_s").asNumber(where + ".duration_s");
            allowed = {"type", "duration_s"};
        } else if (type == "hold_stress") {
            s.kind = Step::Kind::HoldStress;
            s.duration = o.at("duration_s").asNumber(where + ".duration_s");
            if (const Json* x = o.find("stress_Pa")) {
                s.stress = x->asNumber(where + ".stress_Pa");
                if (!(s.stress > 0)) inputError(where + ".stress_Pa: must be > 0 (got " + fmt(s.stress) + ")");
            }
            allowed = {"type", "duration_s", "stress_Pa"};
        } else {
            inputError(where + ".type: unknown step type '" + type + "' (ramp, hold_position, unload, hold_stress)");
        }
        for (const auto& [key, v] : o.asObject())
            if (std::find(allowed.begin(), allowed.end(), key) == allowed.end())
                inputError(where + ": unknown key '" + key + "' for a " + type + " step");
        checkStep(s, where);
        p.steps.push_back(s);
    }
    return p;
}

Protocol readProtocol(const std::string& path) {
    const Json j = readJsonFile(path);
    try {
        return protocolFromJson(j);
    } catch (const InputError& e) {
        inputError(path + ": " + e.what());
    }
}

void writeProtocol(const std::string& path, const Protocol& p) { writeJsonFile(path, protocolToJson(p)); }

std::vector<HoldSummary> protocolHolds(const Protocol& protocol) {
    std::vector<HoldSummary> out;
    const Json* holds = protocol.extra.isObject() ? protocol.extra.find("holds") : nullptr;
    if (!holds) return out;
    const auto& list = holds->asArray("extra.holds");
    for (std::size_t k = 0; k < list.size(); ++k) {
        const Json& h = list[k];
        const std::string where = "extra.holds[" + std::to_string(k) + "]";
        if (!h.isObject()) inputError(where + ": expected an object");
        HoldSummary s;
        const auto need = [&](const char* key) -> const Json& {
            const Json* v = h.find(key);
            if (!v) inputError(where + ": missing key '" + key + "'");
            return *v;
        };
        const std::string type = need("type").asString(where + ".type");
        if (type != "hold_position" && type != "hold_stress") inputError(where + ".type: expected hold_position or hold_stress, got '" + type + "'");
        s.position = type == "hold_position";
        const double step = need("step").asNumber(where + ".step");
        if (!(step >= 0) || step != std::floor(step)) inputError(where + ".step: expected a step index, got " + fmt(step));
        s.step = static_cast<int>(step);
        s.labStart = need("lab_start_s").asNumber(where + ".lab_start_s");
        s.stressStart = need("stress_start_Pa").asNumber(where + ".stress_start_Pa");
        const auto optional = [&](const char* key) {  // null or absent: no fit
            const Json* v = h.find(key);
            return v && v->isNumber() && v->asNumber() > 0 ? v->asNumber() : -1.0;
        };
        s.fitC = optional("fit_C");
        s.fitT0 = optional("fit_t0_s");
        out.push_back(s);
    }
    return out;
}

std::vector<Step> parseSteps(const std::string& text) {
    std::vector<Step> out;
    std::string item;
    std::istringstream is(text);
    int k = 0;
    while (std::getline(is, item, ',')) {
        item = trim(item);
        const std::string where = "step " + std::to_string(k) + " '" + item + "'";
        std::vector<std::string> f;
        std::string part;
        std::istringstream ps(item);
        while (std::getline(ps, part, ':')) f.push_back(trim(part));
        if (f.empty()) inputError("--steps: empty step");
        std::vector<double> v;
        for (std::size_t q = 1; q < f.size(); ++q) {
            double x = 0;
            if (!parseStrictDouble(f[q], x)) inputError("--steps: " + where + ": '" + f[q] + "' is not a number");
            v.push_back(x);
        }
        Step s;
        if ((f[0] == "ramp" || f[0] == "unload") && v.size() == 2) {
            s.kind = f[0] == "ramp" ? Step::Kind::Ramp : Step::Kind::Unload;
            s.velocity = v[0];
            s.targetStress = v[1];
        } else if (f[0] == "hold" && v.size() == 1) {
            s.kind = Step::Kind::HoldPosition;
            s.duration = v[0];
        } else if (f[0] == "creep" && (v.size() == 1 || v.size() == 2)) {
            s.kind = Step::Kind::HoldStress;
            s.duration = v[0];
            if (v.size() == 2) {
                s.stress = v[1];
                if (!(s.stress > 0)) inputError("--steps: " + where + ": the creep stress S must be > 0 (got " + fmt(s.stress) + ")");
            }
        } else {
            inputError("--steps: " + where +
                       ": expected ramp:V:S, hold:T, unload:V:S or creep:T[:S] (V m/s, S Pa, T lab seconds)");
        }
        try {
            checkStep(s, "--steps: " + where);
        } catch (const InputError& e) {
            inputError(e.what());
        }
        out.push_back(s);
        ++k;
    }
    if (out.empty()) inputError("--steps: no steps given");
    return out;
}

std::string formatSteps(const std::vector<Step>& steps) {
    std::string s;
    for (const Step& st : steps) {
        if (!s.empty()) s += ',';
        switch (st.kind) {
            case Step::Kind::Ramp: s += "ramp:" + fmt(st.velocity) + ":" + fmt(st.targetStress); break;
            case Step::Kind::Unload: s += "unload:" + fmt(st.velocity) + ":" + fmt(st.targetStress); break;
            case Step::Kind::HoldPosition: s += "hold:" + fmt(st.duration); break;
            case Step::Kind::HoldStress:
                s += "creep:" + fmt(st.duration);
                if (st.stress >= 0) s += ":" + fmt(st.stress);
                break;
        }
    }
    return s;
}

std::vector<Step> presetSteps(int n, double maxStress, double stressScale) {
    // Table 4.3: velocity (mm/s) and relaxation time (min) of protocols 1-9.
    static const double vel[9] = {0.05, 0.05, 0.05, 0.05, 0.01, 0.3, 0.7, 1.0, 1.3};
    static const double hold[9] = {5, 10, 20, 30, 10, 10, 10, 10, 10};
    if (n < 1 || n > 9) inputError("protocol preset must be 1..9 (Table 4.3), got " + std::to_string(n));
    std::vector<Step> out;
    for (int k = 1; k <= 5; ++k) {
        Step r;
        r.kind = Step::Kind::Ramp;
        r.velocity = vel[n - 1] * 1e-3;
        r.targetStress = std::min(5e3 * k, maxStress) * stressScale;
        out.push_back(r);
        Step h;
        h.kind = Step::Kind::HoldPosition;
        h.duration = hold[n - 1] * 60;
        out.push_back(h);
    }
    return out;
}

// ---- fitting -------------------------------------------------------------------------------------

RelaxationFit fitRelaxation(const std::vector<double>& t, const std::vector<double>& f, double t0Min, double t0Max) {
    RelaxationFit best;
    if (t.size() != f.size() || t.size() < 3 || !(f[0] > 0)) return best;
    const double t0s = t[0], f0 = f[0];
    // For fixed t0: y = ln(f/f0) = -C x with x = ln(1 + (t - t_start)/t0); C by least squares through 0.
    auto evalAt = [&](double t0, double& C) {
        double sxy = 0, sxx = 0;
        for (std::size_t k = 1; k < t.size(); ++k) {
            if (!(f[k] > 0)) continue;
            const double x = std::log1p((t[k] - t0s) / t0), y = std::log(f[k] / f0);
            sxy += x * y;
            sxx += x * x;
        }
        C = sxx > 0 ? -sxy / sxx : 0;
        double ss = 0;
        for (std::size_t k = 0; k < t.size(); ++k) {
            const double m = std::pow(1 + (t[k] - t0s) / t0, -C);
            ss += (f[k] / f0 - m) * (f[k] / f0 - m);
        }
        return std::sqrt(ss / static_cast<double>(t.size()));
    };
    // Coarse scan in log t0, then golden-section refinement around the best point.
    const int n = 121;
    double bestL = std::log(t0Min), bestR = 1e300;
    for (int k = 0; k < n; ++k) {
        const double L = std::log(t0Min) + (std::log(t0Max) - std::log(t0Min)) * k / (n - 1);
        double C = 0;
        const double r = evalAt(std::exp(L), C);
        if (r < bestR) { bestR = r; bestL = L; }
    }
    const double h = (std::log(t0Max) - std::log(t0Min)) / (n - 1);
    double a = bestL - h, b = bestL + h;
    const double g = 0.5 * (std::sqrt(5.0) - 1);
    for (int it = 0; it < 60; ++it) {
        const double c = b - g * (b - a), d = a + g * (b - a);
        double Cc = 0, Cd = 0;
        if (evalAt(std::exp(c), Cc) < evalAt(std::exp(d), Cd)) b = d; else a = c;
    }
    best.t0 = std::exp(0.5 * (a + b));
    best.rms = evalAt(best.t0, best.C);
    best.ok = std::isfinite(best.C) && std::isfinite(best.rms);
    return best;
}

} // namespace pdpm::recording
