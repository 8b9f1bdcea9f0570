#include "Cli.h"

#include "Core/Error.h"
#include "IO/FileName.h"
#include "Core/RunMain.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace pdpm::tools {

namespace {

/// "--name" for a flag given as "name" or "--name".
std::string flagText(const std::string& flag) { return flag.rfind("--", 0) == 0 ? flag : "--" + flag; }

/// The number in `s`; strtod also reads "inf" and "nan", refused unless `allowInf` (then ±inf only).
double toDouble(const std::string& flag, const std::string& s, bool allowInf = false) {
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE)
        inputError(flagText(flag) + ": '" + s + "' is not a number");
    if (std::isnan(v) || (std::isinf(v) && !allowInf)) inputError(flagText(flag) + ": '" + s + "' is not a finite number");
    return v;
}

std::string rangeText(double lo, double hi, bool loOpen, bool hiOpen) {
    if (lo == -Cli::inf && hi == Cli::inf) return "any";
    std::ostringstream os;
    os << (loOpen || lo == -Cli::inf ? "(" : "[") << lo << ", " << hi << (hiOpen || hi == Cli::inf ? ")" : "]");
    return os.str();
}

} // namespace

Cli::Cli(std::string program, std::string description)
    : program_(std::move(program)), description_(std::move(description)) {}

void Cli::add(const std::string& name, double* target, double def, const std::string& unit, const std::string& help,
              double lo, double hi, bool loOpen, bool hiOpen) {
    *target = def;
    std::ostringstream d;
    d << def;
    Opt o{name, help + "  " + rangeText(lo, hi, loOpen, hiOpen), unit, d.str(), "double", {}, false};
    o.set = [=](const std::string& s) {
        const double v = toDouble(name, s, std::isinf(def));  // ±inf only where it is the default ("no limit")
        const bool ok = (loOpen ? v > lo : v >= lo) && (hiOpen ? v < hi : v <= hi);
        if (!ok) inputError("--" + name + ": value " + s + " out of range " + rangeText(lo, hi, loOpen, hiOpen));
        *target = v;
    };
    opts_.push_back(std::move(o));
}

void Cli::add(const std::string& name, int* target, int def, const std::string& help, int lo, int hi) {
    *target = def;
    Opt o{name, help + "  [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", "", std::to_string(def), "int", {}, false};
    o.set = [=](const std::string& s) {
        char* end = nullptr;
        errno = 0;
        const long v = std::strtol(s.c_str(), &end, 10);
        if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE)
            inputError("--" + name + ": '" + s + "' is not an integer");
        if (v < lo || v > hi)
            inputError("--" + name + ": value " + s + " out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
        *target = int(v);
    };
    opts_.push_back(std::move(o));
}

void Cli::add(const std::string& name, bool* target, bool def, const std::string& help) {
    *target = def;
    Opt o{name, help, "", def ? "1" : "0", "bool", {}, false};
    o.set = [=](const std::string& s) {
        if (s == "1" || s == "true" || s == "yes" || s == "on") *target = true;
        else if (s == "0" || s == "false" || s == "no" || s == "off") *target = false;
        else inputError("--" + name + ": '" + s + "' is not a bool (0/1/true/false)");
    };
    opts_.push_back(std::move(o));
}

void Cli::add(const std::string& name, std::string* target, const std::string& def, const std::string& help,
              std::vector<std::string> choices) {
    *target = def;
    std::string h = help;
    if (!choices.empty()) {
        h += "  {";
        for (std::size_t k = 0; k < choices.size(); ++k) h += (k ? "|" : "") + choices[k];
        h += "}";
    }
    Opt o{name, h, "", def, "string", {}, false};
    o.set = [=](const std::string& s) {
        if (!choices.empty()) {
            bool ok = false;
            for (const auto& c : choices) ok = ok || c == s;
            if (!ok) {
                std::string list;
                for (std::size_t k = 0; k < choices.size(); ++k) list += (k ? ", " : "") + choices[k];
                inputError("--" + name + ": '" + s + "' is not one of " + list);
            }
        }
        *target = s;
    };
    opts_.push_back(std::move(o));
}

void Cli::addList(const std::string& name, std::vector<std::string>* target, const std::string& help) {
    target->clear();
    Opt o{name, help, "", "", "list", {}, false};
    o.set = [=](const std::string& s) { target->push_back(s); };
    opts_.push_back(std::move(o));
}

Cli::Opt& Cli::find(const std::string& name) {
    for (Opt& o : opts_)
        if (o.name == name) return o;
    inputError("unknown flag --" + name + " (see --help)");
}

bool Cli::given(const std::string& name) const {
    for (const Opt& o : opts_)
        if (o.name == name) return o.given;
    return false;
}

bool Cli::parse(int argc, char** argv, std::ostream& out) {
    std::vector<std::string> args;
    for (int k = 1; k < argc; ++k) args.emplace_back(argv[k]);
    return parse(args, out);
}

bool Cli::parse(const std::vector<std::string>& args, std::ostream& out) {
    for (const std::string& a : args)
        if (a == "--help" || a == "-h") {
            printHelp(out);
            return false;
        }
    auto isFlag = [](const std::string& s) { return s.size() > 2 && s[0] == '-' && s[1] == '-'; };
    for (std::size_t k = 0; k < args.size();) {
        const std::string& a = args[k];
        if (!isFlag(a)) inputError("unexpected argument '" + a + "' (flags have the form --name value)");
        std::string name = a.substr(2), value;
        bool inlineValue = false;
        if (auto eq = name.find('='); eq != std::string::npos) {
            value = name.substr(eq + 1);
            name = name.substr(0, eq);
            inlineValue = true;
        }
        Opt& o = find(name);
        if (o.given && o.kind != "list") inputError("--" + name + " given twice");
        o.given = true;
        ++k;
        if (o.kind == "list") {
            std::size_t count = 0;
            if (inlineValue) { o.set(value); ++count; }
            while (k < args.size() && !isFlag(args[k])) { o.set(args[k++]); ++count; }
            if (count == 0) inputError("--" + name + ": needs at least one value");
            continue;
        }
        if (!inlineValue) {
            if (k >= args.size() || isFlag(args[k])) {
                if (o.kind == "bool") { o.set("1"); continue; }
                inputError("--" + name + ": missing value");
            }
            value = args[k++];
        }
        o.set(value);
    }
    return true;
}

void Cli::printHelp(std::ostream& os) const {
    os << "Usage: " << program_ << " [--flag value]…\n" << description_ << "\n\nOptions:\n";
    std::size_t w = 0;
    for (const Opt& o : opts_) w = std::max(w, o.name.size());
    for (const Opt& o : opts_) {
        os << "  --" << std::left << std::setw(int(w) + 2) << o.name;
        std::string def = o.kind == "list" ? "FILE…" : o.def;
        if (!o.unit.empty()) def += " " + o.unit;
        os << std::setw(16) << def << o.help << "\n";
    }
    os << "  --" << std::left << std::setw(int(w) + 2) << "help" << std::setw(16) << "" << "print this help and exit\n";
}

int runTool(const std::string& program, const std::function<int()>& body) {
    // the same error handling as the drivers' main(): one place for the messages and exit codes
    return runMain(program.c_str(), body);
}

std::vector<double> parseNumberList(const std::string& flag, const std::string& text) {
    std::vector<double> out;
    if (text.find_first_not_of(" \t") == std::string::npos) return out;
    // Comma-separated entries, each one or more space-separated numbers; an empty entry ("1,,2",
    // "1,", ",1") is a typo, not a shorter list.
    std::size_t pos = 0;
    while (true) {
        const std::size_t comma = text.find(',', pos);
        const std::string entry = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
        std::istringstream is(entry);
        std::string tok;
        bool any = false;
        while (is >> tok) {
            out.push_back(toDouble(flag, tok));
            any = true;
        }
        if (!any) inputError(flagText(flag) + ": empty entry in the list '" + text + "'");
        if (comma == std::string::npos) break;
        pos = comma + 1;
    }
    return out;
}

void requireNonEmpty(const std::string& flag, const std::string& value) {
    if (value.empty()) inputError(flagText(flag) + ": must not be empty");
}

void requireFileName(const std::string& flag, const std::string& value) {
    requireNonEmpty(flag, value);
    if (!isPlainFileName(value)) inputError(flagText(flag) + ": '" + printableFileName(value) + "' is not " + plainFileNameRule());
}

} // namespace pdpm::tools
