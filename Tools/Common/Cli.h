// A small command-line parser for the tools (pdpm-cg, pdpm-polar). Flags have the form
// `--name value`; list flags (`--input A B C`) take every following argument up to the next flag;
// bool flags may be given bare. Every error throws pdpm::InputError naming the flag.
// (Local to Tools/ because list-valued flags are needed; the drivers' ParameterSet does not have them.)
#pragma once
#include <functional>
#include <iosfwd>
#include <limits>
#include <string>
#include <vector>

namespace pdpm::tools {

class Cli {
public:
    static constexpr double inf = std::numeric_limits<double>::infinity();

    Cli(std::string program, std::string description);

    /// Numeric option with allowed range lo..hi (open ends when loOpen/hiOpen). NaN is refused, and
    /// ±inf too unless the default is infinite (e.g. --tmax inf, "no limit").
    void add(const std::string& name, double* target, double def, const std::string& unit, const std::string& help,
             double lo = -inf, double hi = inf, bool loOpen = false, bool hiOpen = false);
    void add(const std::string& name, int* target, int def, const std::string& help, int lo, int hi);
    void add(const std::string& name, bool* target, bool def, const std::string& help);
    /// String option; empty `choices` accepts anything.
    void add(const std::string& name, std::string* target, const std::string& def, const std::string& help,
             std::vector<std::string> choices = {});
    /// List option (one or more values).
    void addList(const std::string& name, std::vector<std::string>* target, const std::string& help);

    /// Parses argv[1..]; returns false when --help was given (help already printed to `out`).
    bool parse(int argc, char** argv, std::ostream& out);
    bool parse(const std::vector<std::string>& args, std::ostream& out);
    void printHelp(std::ostream& os) const;
    bool given(const std::string& name) const;

private:
    struct Opt {
        std::string name, help, unit, def;
        std::string kind;  // double int bool string list
        std::function<void(const std::string&)> set;
        bool given = false;
    };
    Opt& find(const std::string& name);
    std::string program_, description_;
    std::vector<Opt> opts_;
};

/// Runs `body` through pdpm::runMain (Core/RunMain.h): InputError → one line "PROGRAM: error:
/// MESSAGE" on stderr, exit code 2; std::bad_alloc → "PROGRAM: error: out of memory: …", exit code 2
/// (the sizes come from the input); any other exception → "PROGRAM: error: …", exit code 1.
int runTool(const std::string& program, const std::function<int()>& body);

/// Splits "a,b,c" (commas or spaces) into finite doubles; InputError naming `flag` ("name" or
/// "--name") if malformed, NaN or infinite.
std::vector<double> parseNumberList(const std::string& flag, const std::string& text);

/// InputError "--flag: must not be empty" for an empty value (output directories, file names).
void requireNonEmpty(const std::string& flag, const std::string& value);
/// A base name of output files (written as OUTPUT/NAME...): non-empty, not '.' or '..', and without
/// '/', quotes or control characters (it would leave the output directory, or end a quoted name in
/// the gnuplot script).
void requireFileName(const std::string& flag, const std::string& value);

} // namespace pdpm::tools
