// Run-time parameters of driver programs.
//
// A driver registers each of its parameters exactly once with a ParameterSet: name, target
// variable, default, unit, one-line meaning and the allowed range (or allowed choices). From that
// single registration come the command-line parser (parseCommandLine), the --help table and the
// validation of every value. Every flag has the form `--name value`; bool flags may be given bare.
//
// Errors (unknown flag, missing or malformed value, value out of range) throw pdpm::InputError with
// one line naming the flag, e.g. "--radius_min: value -1 out of range (0, inf)".
#pragma once
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace pdpm {

/// An interval of allowed values of a numeric parameter; open or closed at each end.
struct Range {
    double lo;
    double hi;
    bool loOpen;
    bool hiOpen;

    static Range any();                           ///< (-inf, inf)
    static Range positive();                      ///< (0, inf)
    static Range nonNegative();                   ///< [0, inf)
    static Range closed(double a, double b);      ///< [a, b]
    static Range open(double a, double b);        ///< (a, b)
    static Range openClosed(double a, double b);  ///< (a, b]
    static Range closedOpen(double a, double b);  ///< [a, b)
    static Range atLeast(double a);               ///< [a, inf)
    static Range greaterThan(double a);           ///< (a, inf)

    bool contains(double x) const;
    /// E.g. "(0, inf)", "[0, 1]", "any".
    std::string describe() const;
};

/// Formats a double with 17 significant digits, which round-trips exactly ("0.10000000000000001").
std::string formatDouble(double x);
/// Strict number parsing shared by the parameter parser and the file readers: the whole text must be
/// a finite decimal number (optional sign, digits, '.', exponent). "1e", "abc", " 1", "nan", "inf",
/// "0x10" and out-of-range values such as "1e400" are refused (returns false, `out` unchanged).
bool parseStrictDouble(const std::string& text, double& out);
/// Strict integer parsing (optional sign, decimal digits only, fits in long).
bool parseStrictLong(const std::string& text, long& out);

/// Formats a double in its shortest form that round-trips exactly ("0.1").
std::string formatDoubleShort(double x);

class ParameterSet {
public:
    ParameterSet();
    ~ParameterSet();
    ParameterSet(const ParameterSet&) = delete;
    ParameterSet& operator=(const ParameterSet&) = delete;

    // Registration. The target is set to the default immediately. A name may be registered once;
    // names must not start with '-' and must not clash with the built-in common flags.
    void add(const std::string& name, double* target, double def, const std::string& unit,
             const std::string& help, Range r = Range::any());
    void add(const std::string& name, long* target, long def, const std::string& unit,
             const std::string& help, Range r = Range::any());
    void add(const std::string& name, int* target, int def, const std::string& unit,
             const std::string& help, Range r = Range::any());
    /// Accepts 0/1/true/false (and bare `--name` on the command line, meaning true).
    void add(const std::string& name, bool* target, bool def, const std::string& help);
    /// Empty choices = any string.
    void add(const std::string& name, std::string* target, const std::string& def,
             const std::string& help, std::vector<std::string> choices = {});

    /// A named set of parameter values, applied with `--preset NAME` before explicit flags.
    /// The values are validated when the preset is applied.
    void addPreset(const std::string& preset, const std::string& help,
                   std::vector<std::pair<std::string, std::string>> values);
    bool hasPreset(const std::string& preset) const;
    /// Applies a preset (set() for each of its values); InputError if unknown.
    void applyPreset(const std::string& preset);

    /// Parses and validates `value`, then stores it in the target. Throws InputError naming the
    /// parameter, the value and the allowed range / choices.
    void set(const std::string& name, const std::string& value);
    /// set(), and `value` becomes the parameter's default: what --help shows and resetToDefaults()
    /// restores. For a driver's own default of a kernel parameter (call it in the constructor).
    void setDefault(const std::string& name, const std::string& value);
    /// Current value as text (doubles with 17 significant digits so they round-trip exactly).
    std::string get(const std::string& name) const;
    bool has(const std::string& name) const;
    /// All parameters with their current values, in registration order.
    std::vector<std::pair<std::string, std::string>> values() const;
    /// Names in registration order.
    std::vector<std::string> names() const;

    /// Aligned table of all parameters (name, default, unit, range, meaning), the common flags and
    /// the presets.
    void printHelp(std::ostream& os, const std::string& programName,
                   const std::string& description) const;

    bool wasSetOnCommandLine(const std::string& name) const;
    /// Used by parseCommandLine: marks a parameter as given explicitly.
    void markSetOnCommandLine(const std::string& name);
    /// Restores every parameter to its default and clears the command-line marks.
    void resetToDefaults();

    /// Whether `name` is a bool parameter (so that it may appear bare on the command line).
    bool isBool(const std::string& name) const;

    /// Description printed by --help under the usage line (optional; printHelp's argument wins).
    std::string description;

private:
    struct Entry;
    struct Preset;
    Entry& entry(const std::string& name);
    const Entry& entry(const std::string& name) const;
    void addEntry(std::unique_ptr<Entry> e);
    std::vector<std::unique_ptr<Entry>> entries_;
    std::vector<Preset> presets_;
};

/// The flags every driver understands.
struct CommonOptions {
    std::string output = ".";  ///< --output DIR
    std::string name;          ///< --name RUN (empty: the driver chooses, normally its own name)
    std::string preset;        ///< --preset NAME
    std::string restart;       ///< --restart FILE
    int threads = 0;           ///< --threads N (0: not given, use the OpenMP default)
    bool quiet = false;        ///< --quiet
    bool help = false;         ///< --help (the caller prints help and exits 0)
};

/// Names of the built-in common flags (without "--").
const std::vector<std::string>& commonFlagNames();

/// Parses argv. Presets are applied first, then explicit flags (explicit flags win regardless of
/// order). `--name=value` is accepted as well as `--name value`. If `--help` (or `-h`) appears
/// anywhere, nothing else is parsed or validated and the result has help == true: the caller prints
/// help and exits 0.
CommonOptions parseCommandLine(int argc, char** argv, ParameterSet& params);
/// Same, for a vector of arguments (argv[1..]) — convenient in tests.
CommonOptions parseCommandLine(const std::vector<std::string>& args, ParameterSet& params);

} // namespace pdpm
