#include "Core/Parameters.h"

#include "Core/Error.h"
#include "IO/FileName.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>
#include <sstream>

namespace pdpm {

// ---- Range -------------------------------------------------------------------------------------

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

Range Range::any() { return {-kInf, kInf, true, true}; }
Range Range::positive() { return {0.0, kInf, true, true}; }
Range Range::nonNegative() { return {0.0, kInf, false, true}; }
Range Range::closed(double a, double b) { return {a, b, false, false}; }
Range Range::open(double a, double b) { return {a, b, true, true}; }
Range Range::openClosed(double a, double b) { return {a, b, true, false}; }
Range Range::closedOpen(double a, double b) { return {a, b, false, true}; }
Range Range::atLeast(double a) { return {a, kInf, false, true}; }
Range Range::greaterThan(double a) { return {a, kInf, true, true}; }

bool Range::contains(double x) const {
    if (std::isnan(x)) return false;
    const bool aboveLo = loOpen ? x > lo : x >= lo;
    const bool belowHi = hiOpen ? x < hi : x <= hi;
    return aboveLo && belowHi;
}

std::string Range::describe() const {
    if (lo == -kInf && hi == kInf) return "any";
    std::string s = (loOpen || lo == -kInf) ? "(" : "[";
    s += formatDoubleShort(lo);
    s += ", ";
    s += formatDoubleShort(hi);
    s += (hiOpen || hi == kInf) ? ")" : "]";
    return s;
}

std::string formatDouble(double x) {
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    if (std::isnan(x)) return "nan";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
}

std::string formatDoubleShort(double x) {
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    if (std::isnan(x)) return "nan";
    char buf[64];
    if (x == std::floor(x) && std::fabs(x) < 1e16) {  // integers in full: "1000000", not "1e+06"
        std::snprintf(buf, sizeof buf, "%.0f", x);
        return buf;
    }
    auto res = std::to_chars(buf, buf + sizeof buf, x);
    return std::string(buf, res.ptr);
}

// ---- value parsing -----------------------------------------------------------------------------

namespace {

std::string flag(const std::string& name) { return "--" + name; }

std::string joined(const std::vector<std::string>& v, const char* sep = ", ") {
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (i) s += sep;
        s += v[i];
    }
    return s;
}

/// Strict: the whole text must be a finite decimal number; no spaces, no "nan"/"inf", no hex.
bool strictDouble(const std::string& text, double& out) {
    const char* b = text.data();
    const char* e = b + text.size();
    if (b != e && *b == '+') ++b;
    if (b == e) return false;
    // from_chars accepts "inf"/"nan"; only digits, '.', sign and exponent are allowed here.
    for (const char* p = b; p != e; ++p) {
        const char c = *p;
        if (!((c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E'))
            return false;
    }
    double v = 0;
    auto [ptr, ec] = std::from_chars(b, e, v, std::chars_format::general);
    if (ec != std::errc() || ptr != e || !std::isfinite(v)) return false;
    out = v;
    return true;
}

bool strictLong(const std::string& text, long& out) {
    const char* b = text.data();
    const char* e = b + text.size();
    if (b != e && *b == '+') ++b;
    if (b == e) return false;
    long v = 0;
    auto [ptr, ec] = std::from_chars(b, e, v, 10);
    if (ec != std::errc() || ptr != e) return false;
    out = v;
    return true;
}

bool parseBool(const std::string& text, bool& out) {
    if (text == "1" || text == "true") { out = true; return true; }
    if (text == "0" || text == "false") { out = false; return true; }
    return false;
}

} // namespace

bool parseStrictDouble(const std::string& text, double& out) { return strictDouble(text, out); }
bool parseStrictLong(const std::string& text, long& out) { return strictLong(text, out); }

// ---- ParameterSet ------------------------------------------------------------------------------

enum class Kind { Double, Long, Int, Bool, String };

struct ParameterSet::Entry {
    std::string name;
    std::string unit;
    std::string help;
    Kind kind = Kind::Double;
    void* target = nullptr;
    Range range = Range::any();
    std::vector<std::string> choices;
    std::string defaultText;   // for --help
    std::string defaultValue;  // exact, for resetToDefaults
    bool setOnCommandLine = false;
};

struct ParameterSet::Preset {
    std::string name;
    std::string help;
    std::vector<std::pair<std::string, std::string>> values;
};

ParameterSet::ParameterSet() = default;
ParameterSet::~ParameterSet() = default;

void ParameterSet::addEntry(std::unique_ptr<Entry> e) {
    if (e->name.empty() || e->name[0] == '-' || e->name.find('=') != std::string::npos ||
        e->name.find(' ') != std::string::npos)
        throw std::logic_error("ParameterSet: invalid parameter name '" + e->name + "'");
    if (has(e->name))
        throw std::logic_error("ParameterSet: parameter '" + e->name + "' registered twice");
    const auto& common = commonFlagNames();
    if (std::find(common.begin(), common.end(), e->name) != common.end())
        throw std::logic_error("ParameterSet: parameter '" + e->name + "' clashes with a common flag");
    if (e->target == nullptr)
        throw std::logic_error("ParameterSet: parameter '" + e->name + "' has no target");
    entries_.push_back(std::move(e));
}

void ParameterSet::add(const std::string& name, double* target, double def, const std::string& unit,
                       const std::string& help, Range r) {
    if (!std::isfinite(def) || !r.contains(def))
        throw std::logic_error("ParameterSet: default of '" + name + "' is outside its range");
    auto e = std::make_unique<Entry>();
    e->name = name; e->unit = unit; e->help = help; e->kind = Kind::Double; e->target = target;
    e->range = r; e->defaultText = formatDoubleShort(def); e->defaultValue = formatDouble(def);
    addEntry(std::move(e));
    *target = def;
}

void ParameterSet::add(const std::string& name, long* target, long def, const std::string& unit,
                       const std::string& help, Range r) {
    if (!r.contains(static_cast<double>(def)))
        throw std::logic_error("ParameterSet: default of '" + name + "' is outside its range");
    auto e = std::make_unique<Entry>();
    e->name = name; e->unit = unit; e->help = help; e->kind = Kind::Long; e->target = target;
    e->range = r; e->defaultText = e->defaultValue = std::to_string(def);
    addEntry(std::move(e));
    *target = def;
}

void ParameterSet::add(const std::string& name, int* target, int def, const std::string& unit,
                       const std::string& help, Range r) {
    if (!r.contains(static_cast<double>(def)))
        throw std::logic_error("ParameterSet: default of '" + name + "' is outside its range");
    auto e = std::make_unique<Entry>();
    e->name = name; e->unit = unit; e->help = help; e->kind = Kind::Int; e->target = target;
    e->range = r; e->defaultText = e->defaultValue = std::to_string(def);
    addEntry(std::move(e));
    *target = def;
}

void ParameterSet::add(const std::string& name, bool* target, bool def, const std::string& help) {
    auto e = std::make_unique<Entry>();
    e->name = name; e->help = help; e->kind = Kind::Bool; e->target = target;
    e->defaultValue = std::string(1, def ? '1' : '0');
    e->defaultText = e->defaultValue;
    addEntry(std::move(e));
    *target = def;
}

void ParameterSet::add(const std::string& name, std::string* target, const std::string& def,
                       const std::string& help, std::vector<std::string> choices) {
    if (!choices.empty() && std::find(choices.begin(), choices.end(), def) == choices.end())
        throw std::logic_error("ParameterSet: default of '" + name + "' is not one of its choices");
    auto e = std::make_unique<Entry>();
    e->name = name; e->help = help; e->kind = Kind::String; e->target = target;
    e->choices = std::move(choices);
    e->defaultText = def.empty() ? "\"\"" : def;
    e->defaultValue = def;
    addEntry(std::move(e));
    *target = def;
}

void ParameterSet::addPreset(const std::string& preset, const std::string& help,
                             std::vector<std::pair<std::string, std::string>> values) {
    if (preset.empty()) throw std::logic_error("ParameterSet: empty preset name");
    if (hasPreset(preset))
        throw std::logic_error("ParameterSet: preset '" + preset + "' registered twice");
    for (const auto& [n, v] : values)
        if (!has(n))
            throw std::logic_error("ParameterSet: preset '" + preset + "' sets unknown parameter '" +
                                   n + "'");
    presets_.push_back({preset, help, std::move(values)});
}

bool ParameterSet::hasPreset(const std::string& preset) const {
    return std::any_of(presets_.begin(), presets_.end(),
                       [&](const Preset& p) { return p.name == preset; });
}

void ParameterSet::applyPreset(const std::string& preset) {
    for (const auto& p : presets_) {
        if (p.name != preset) continue;
        for (const auto& [n, v] : p.values) {
            try {
                set(n, v);
            } catch (const InputError& err) {
                throw InputError("preset '" + preset + "': " + err.what());
            }
        }
        return;
    }
    std::vector<std::string> known;
    for (const auto& p : presets_) known.push_back(p.name);
    throw InputError("--preset: unknown preset '" + preset + "' (known: " +
                     (known.empty() ? std::string("none") : joined(known)) + ")");
}

bool ParameterSet::has(const std::string& name) const {
    return std::any_of(entries_.begin(), entries_.end(),
                       [&](const auto& e) { return e->name == name; });
}

ParameterSet::Entry& ParameterSet::entry(const std::string& name) {
    for (auto& e : entries_)
        if (e->name == name) return *e;
    throw InputError("unknown flag " + flag(name) + " (see --help)");
}

const ParameterSet::Entry& ParameterSet::entry(const std::string& name) const {
    for (const auto& e : entries_)
        if (e->name == name) return *e;
    throw InputError("unknown flag " + flag(name) + " (see --help)");
}

bool ParameterSet::isBool(const std::string& name) const {
    return has(name) && entry(name).kind == Kind::Bool;
}

void ParameterSet::set(const std::string& name, const std::string& value) {
    Entry& e = entry(name);
    const std::string f = flag(name);
    switch (e.kind) {
    case Kind::Double: {
        double v = 0;
        if (!strictDouble(value, v))
            throw InputError(f + ": value '" + value + "' is not a finite number");
        if (!e.range.contains(v))
            throw InputError(f + ": value " + value + " out of range " + e.range.describe());
        *static_cast<double*>(e.target) = v;
        break;
    }
    case Kind::Long:
    case Kind::Int: {
        long v = 0;
        if (!strictLong(value, v))
            throw InputError(f + ": value '" + value + "' is not an integer");
        const bool fitsInt = v >= std::numeric_limits<int>::min() && v <= std::numeric_limits<int>::max();
        if (!e.range.contains(static_cast<double>(v)) || (e.kind == Kind::Int && !fitsInt)) {
            const std::string r = e.range.describe();
            throw InputError(f + ": value " + value + " out of range " +
                             (r == "any" && e.kind == Kind::Int ? std::string("of int") : r));
        }
        if (e.kind == Kind::Int) *static_cast<int*>(e.target) = static_cast<int>(v);
        else *static_cast<long*>(e.target) = v;
        break;
    }
    case Kind::Bool: {
        bool v = false;
        if (!parseBool(value, v))
            throw InputError(f + ": value '" + value + "' is not a bool (use 0, 1, true or false)");
        *static_cast<bool*>(e.target) = v;
        break;
    }
    case Kind::String: {
        if (!e.choices.empty() && std::find(e.choices.begin(), e.choices.end(), value) == e.choices.end())
            throw InputError(f + ": value '" + value + "' is not one of: " + joined(e.choices));
        *static_cast<std::string*>(e.target) = value;
        break;
    }
    }
}

void ParameterSet::setDefault(const std::string& name, const std::string& value) {
    set(name, value);
    Entry& e = entry(name);
    e.defaultValue = get(name);
    switch (e.kind) {
    case Kind::Double: e.defaultText = formatDoubleShort(*static_cast<const double*>(e.target)); break;
    case Kind::String: e.defaultText = e.defaultValue.empty() ? "\"\"" : e.defaultValue; break;
    default: e.defaultText = e.defaultValue; break;
    }
}

std::string ParameterSet::get(const std::string& name) const {
    const Entry& e = entry(name);
    switch (e.kind) {
    case Kind::Double: return formatDouble(*static_cast<const double*>(e.target));
    case Kind::Long: return std::to_string(*static_cast<const long*>(e.target));
    case Kind::Int: return std::to_string(*static_cast<const int*>(e.target));
    case Kind::Bool: return *static_cast<const bool*>(e.target) ? "1" : "0";
    case Kind::String: return *static_cast<const std::string*>(e.target);
    }
    return {};
}

std::vector<std::pair<std::string, std::string>> ParameterSet::values() const {
    std::vector<std::pair<std::string, std::string>> v;
    v.reserve(entries_.size());
    for (const auto& e : entries_) v.emplace_back(e->name, get(e->name));
    return v;
}

std::vector<std::string> ParameterSet::names() const {
    std::vector<std::string> v;
    for (const auto& e : entries_) v.push_back(e->name);
    return v;
}

bool ParameterSet::wasSetOnCommandLine(const std::string& name) const {
    return entry(name).setOnCommandLine;
}

void ParameterSet::markSetOnCommandLine(const std::string& name) { entry(name).setOnCommandLine = true; }

void ParameterSet::resetToDefaults() {
    for (auto& e : entries_) {
        set(e->name, e->defaultValue);
        e->setOnCommandLine = false;
    }
}

namespace {

void printTable(std::ostream& os, const std::vector<std::vector<std::string>>& rows) {
    if (rows.empty()) return;
    std::vector<std::size_t> width(rows.front().size(), 0);
    for (const auto& r : rows)
        for (std::size_t c = 0; c < r.size(); ++c) width[c] = std::max(width[c], r[c].size());
    for (const auto& r : rows) {
        std::string line = "  ";
        for (std::size_t c = 0; c < r.size(); ++c) {
            line += r[c];
            if (c + 1 < r.size()) line += std::string(width[c] - r[c].size() + 2, ' ');
        }
        while (!line.empty() && line.back() == ' ') line.pop_back();
        os << line << '\n';
    }
}

} // namespace

void ParameterSet::printHelp(std::ostream& os, const std::string& programName,
                             const std::string& descriptionText) const {
    os << "Usage: " << programName << " [--flag value]...\n";
    const std::string& d = descriptionText.empty() ? description : descriptionText;
    if (!d.empty()) os << '\n' << d << '\n';

    if (!entries_.empty()) {
        os << "\nParameters:\n";
        std::vector<std::vector<std::string>> rows;
        rows.push_back({"flag", "default", "unit", "allowed", "meaning"});
        for (const auto& e : entries_) {
            std::string allowed;
            switch (e->kind) {
            case Kind::Double: allowed = e->range.describe(); break;
            case Kind::Long:
            case Kind::Int: allowed = "integer " + e->range.describe(); break;
            case Kind::Bool: allowed = "0|1"; break;
            case Kind::String: allowed = e->choices.empty() ? "text" : joined(e->choices, "|"); break;
            }
            rows.push_back({flag(e->name), e->defaultText, e->unit.empty() ? "-" : e->unit, allowed,
                            e->help});
        }
        printTable(os, rows);
    }

    os << "\nCommon flags:\n";
    printTable(os, {{"--help", "", "print this help and exit"},
                    {"--output DIR", ".", "output directory (created if missing)"},
                    {"--name RUN", programName, "run name: prefix of all output files (a plain file name: no /, quotes or control characters)"},
                    {"--preset NAME", "", "apply a preset (below) before the explicit flags"},
                    {"--threads N", "", "number of OpenMP threads (>= 1; default: OpenMP's choice)"},
                    {"--quiet [0|1]", "0", "no progress output"},
                    {"--restart FILE", "", "continue from a restart file"}});

    if (!presets_.empty()) {
        os << "\nPresets (explicit flags override preset values):\n";
        std::vector<std::vector<std::string>> rows;
        for (const auto& p : presets_) {
            std::string vals;
            for (const auto& [n, v] : p.values) {
                if (!vals.empty()) vals += ' ';
                vals += flag(n) + ' ' + v;
            }
            rows.push_back({p.name, p.help, vals});
        }
        printTable(os, rows);
    }
}

// ---- command line ------------------------------------------------------------------------------

const std::vector<std::string>& commonFlagNames() {
    static const std::vector<std::string> names = {"help", "output", "name", "preset",
                                                   "threads", "quiet", "restart"};
    return names;
}

CommonOptions parseCommandLine(int argc, char** argv, ParameterSet& params) {
    std::vector<std::string> args;
    for (int i = 1; i < argc; ++i) args.emplace_back(argv[i] ? argv[i] : "");
    return parseCommandLine(args, params);
}

CommonOptions parseCommandLine(const std::vector<std::string>& args, ParameterSet& params) {
    CommonOptions opts;
    for (const auto& a : args)
        if (a == "--help" || a == "-h") {
            opts.help = true;
            return opts;
        }

    // Pass 1: split into (name, value) pairs; check flags and presence of values.
    std::vector<std::pair<std::string, std::string>> given;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a.size() < 3 || a.compare(0, 2, "--") != 0)
            throw InputError("unexpected argument '" + a + "' (flags have the form --name value)");
        std::string name = a.substr(2);
        std::string value;
        bool haveValue = false;
        if (auto eq = name.find('='); eq != std::string::npos) {
            value = name.substr(eq + 1);
            name.resize(eq);
            haveValue = true;
        }
        const auto& common = commonFlagNames();
        const bool isCommon = std::find(common.begin(), common.end(), name) != common.end();
        if (!isCommon && !params.has(name)) throw InputError("unknown flag --" + name + " (see --help)");
        const bool isBoolFlag = name == "quiet" || (!isCommon && params.isBool(name));
        if (!haveValue) {
            if (isBoolFlag) {
                // a bare flag means 1; a following word that is not a flag is its value, checked
                // below ("--vtk 2" is an out-of-range value, not a stray argument)
                if (i + 1 < args.size() && args[i + 1].compare(0, 2, "--") != 0) value = args[++i];
                else value = "1";
            } else {
                if (i + 1 >= args.size() || args[i + 1].compare(0, 2, "--") == 0)
                    throw InputError("--" + name + ": missing value");
                value = args[++i];
            }
        }
        given.emplace_back(name, value);
    }

    // Pass 2: common flags (the last occurrence wins).
    for (const auto& [name, value] : given) {
        if (name == "output") {
            if (value.empty()) throw InputError("--output: empty directory name");
            opts.output = value;
        } else if (name == "name") {
            if (!isPlainFileName(value))
                throw InputError("--name: '" + printableFileName(value) + "' is not " + plainFileNameRule());
            opts.name = value;
        } else if (name == "preset") {
            if (value.empty()) throw InputError("--preset: empty preset name");
            opts.preset = value;
        } else if (name == "restart") {
            if (value.empty()) throw InputError("--restart: empty file name");
            opts.restart = value;
        } else if (name == "threads") {
            long n = 0;
            if (!strictLong(value, n)) throw InputError("--threads: value '" + value + "' is not an integer");
            if (n < 1 || n > 65536) throw InputError("--threads: value " + value + " out of range [1, 65536]");
            opts.threads = static_cast<int>(n);
        } else if (name == "quiet") {
            bool q = false;
            if (!parseBool(value, q))
                throw InputError("--quiet: value '" + value + "' is not a bool (use 0, 1, true or false)");
            opts.quiet = q;
        }
    }

    // Pass 3: the preset, then the explicit parameter flags.
    if (!opts.preset.empty()) params.applyPreset(opts.preset);
    for (const auto& [name, value] : given) {
        if (!params.has(name)) continue;
        params.set(name, value);
        params.markSetOnCommandLine(name);
    }
    return opts;
}

} // namespace pdpm
