#include "Core/Error.h"
#include "Core/Parameters.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

using namespace pdpm;

namespace {

struct Driver {
    double radiusMin = 0, density = 0, restitution = 0, gravity = 0;
    long steps = 0;
    int particles = 0;
    bool fstat = false;
    std::string mode, label;
    ParameterSet params;

    Driver() {
        params.add("radius_min", &radiusMin, 1e-3, "m", "smallest particle radius", Range::positive());
        params.add("density", &density, 2500, "kg/m^3", "particle density", Range::positive());
        params.add("restitution", &restitution, 0.5, "", "coefficient of restitution",
                   Range::openClosed(0, 1));
        params.add("gravity", &gravity, -9.81, "m/s^2", "gravity along z");
        params.add("steps", &steps, 1000, "", "number of time steps", Range::atLeast(1));
        params.add("particles", &particles, 100, "", "number of particles", Range::closed(1, 1000000));
        params.add("fstat", &fstat, false, "write contact files");
        params.add("mode", &mode, "shear", "loading mode", {"shear", "compress"});
        params.add("label", &label, "", "free text");
        params.addPreset("dense", "a dense packing", {{"density", "3000"}, {"particles", "5000"}});
        params.addPreset("elastic", "almost elastic", {{"restitution", "0.99"}, {"mode", "compress"}});
    }

    CommonOptions parse(const std::vector<std::string>& args) { return parseCommandLine(args, params); }

    std::string errorOf(const std::vector<std::string>& args) {
        try {
            parse(args);
        } catch (const InputError& e) {
            std::string msg = e.what();
            EXPECT_EQ(msg.find('\n'), std::string::npos) << "error message must be one line: " << msg;
            return msg;
        }
        ADD_FAILURE() << "expected InputError";
        return {};
    }
};

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

} // namespace

TEST(Range, ContainsAndDescribe) {
    EXPECT_TRUE(Range::any().contains(-1e300));
    EXPECT_FALSE(Range::any().contains(std::nan("")));
    EXPECT_FALSE(Range::positive().contains(0.0));
    EXPECT_TRUE(Range::positive().contains(1e-300));
    EXPECT_TRUE(Range::nonNegative().contains(0.0));
    EXPECT_FALSE(Range::nonNegative().contains(-1e-300));
    EXPECT_TRUE(Range::closed(0, 1).contains(1.0));
    EXPECT_FALSE(Range::openClosed(0, 1).contains(0.0));
    EXPECT_TRUE(Range::openClosed(0, 1).contains(1.0));
    EXPECT_TRUE(Range::atLeast(2).contains(2.0));
    EXPECT_FALSE(Range::atLeast(2).contains(1.5));
    EXPECT_EQ(Range::positive().describe(), "(0, inf)");
    EXPECT_EQ(Range::nonNegative().describe(), "[0, inf)");
    EXPECT_EQ(Range::closed(0, 1).describe(), "[0, 1]");
    EXPECT_EQ(Range::openClosed(0, 0.5).describe(), "(0, 0.5]");
    EXPECT_EQ(Range::atLeast(1).describe(), "[1, inf)");
    EXPECT_EQ(Range::any().describe(), "any");
}

TEST(Parameters, DefaultsAreAppliedAtRegistration) {
    Driver d;
    EXPECT_EQ(d.radiusMin, 1e-3);
    EXPECT_EQ(d.steps, 1000);
    EXPECT_EQ(d.particles, 100);
    EXPECT_FALSE(d.fstat);
    EXPECT_EQ(d.mode, "shear");
    EXPECT_TRUE(d.params.has("density"));
    EXPECT_FALSE(d.params.has("output"));
}

TEST(Parameters, ParsesValidArguments) {
    Driver d;
    auto o = d.parse({"--radius_min", "2.5e-4", "--steps", "42", "--particles", "+7", "--fstat", "1",
                      "--mode", "compress", "--gravity", "-1", "--output", "out/dir", "--name", "run1",
                      "--threads", "3", "--label", "hello world", "--restart", "x.restart"});
    EXPECT_EQ(d.radiusMin, 2.5e-4);
    EXPECT_EQ(d.steps, 42);
    EXPECT_EQ(d.particles, 7);
    EXPECT_TRUE(d.fstat);
    EXPECT_EQ(d.mode, "compress");
    EXPECT_EQ(d.gravity, -1.0);
    EXPECT_EQ(d.label, "hello world");
    EXPECT_EQ(o.output, "out/dir");
    EXPECT_EQ(o.name, "run1");
    EXPECT_EQ(o.threads, 3);
    EXPECT_EQ(o.restart, "x.restart");
    EXPECT_FALSE(o.quiet);
    EXPECT_FALSE(o.help);
    EXPECT_TRUE(d.params.wasSetOnCommandLine("steps"));
    EXPECT_FALSE(d.params.wasSetOnCommandLine("density"));
}

TEST(Parameters, ArgcArgvOverload) {
    Driver d;
    const char* argv[] = {"prog", "--density", "1000", "--quiet"};
    char* args[4];
    for (int i = 0; i < 4; ++i) args[i] = const_cast<char*>(argv[i]);
    auto o = parseCommandLine(4, args, d.params);
    EXPECT_EQ(d.density, 1000.0);
    EXPECT_TRUE(o.quiet);
}

TEST(Parameters, BoolFlagsBareOrWithValue) {
    Driver d;
    auto o = d.parse({"--quiet", "--fstat", "--density", "1"});
    EXPECT_TRUE(o.quiet);
    EXPECT_TRUE(d.fstat);
    Driver e;
    o = e.parse({"--quiet", "0", "--fstat", "true"});
    EXPECT_FALSE(o.quiet);
    EXPECT_TRUE(e.fstat);
    Driver f;
    o = f.parse({"--fstat", "false", "--quiet", "true"});
    EXPECT_FALSE(f.fstat);
    EXPECT_TRUE(o.quiet);
    Driver g;
    g.parse({"--fstat=1"});
    EXPECT_TRUE(g.fstat);
    // the word after a bool flag is its value: a wrong one is named as such, not as a stray argument
    EXPECT_TRUE(contains(g.errorOf({"--fstat", "yes"}), "--fstat: value 'yes' is not a bool"));
    EXPECT_TRUE(contains(g.errorOf({"--fstat", "2"}), "--fstat: value '2' is not a bool"));
    EXPECT_TRUE(contains(g.errorOf({"--quiet", "2"}), "--quiet: value '2' is not a bool"));
    EXPECT_TRUE(contains(g.errorOf({"--fstat=yes"}), "--fstat: value 'yes' is not a bool"));
}

TEST(Parameters, EqualsSyntax) {
    Driver d;
    d.parse({"--density=1200", "--mode=compress"});
    EXPECT_EQ(d.density, 1200.0);
    EXPECT_EQ(d.mode, "compress");
}

TEST(Parameters, HelpStopsParsing) {
    Driver d;
    auto o = d.parse({"--density", "-5", "--help", "--foo"});
    EXPECT_TRUE(o.help);
    EXPECT_EQ(d.density, 2500.0);
}

TEST(Parameters, RefusesUnknownFlag) {
    Driver d;
    EXPECT_EQ(d.errorOf({"--foo", "1"}), "unknown flag --foo (see --help)");
    EXPECT_TRUE(contains(d.errorOf({"density", "1"}), "unexpected argument 'density'"));
    EXPECT_TRUE(contains(d.errorOf({"-density", "1"}), "unexpected argument"));
}

TEST(Parameters, RefusesMissingValue) {
    Driver d;
    EXPECT_EQ(d.errorOf({"--density"}), "--density: missing value");
    EXPECT_EQ(d.errorOf({"--density", "--steps", "3"}), "--density: missing value");
    EXPECT_EQ(d.errorOf({"--output"}), "--output: missing value");
}

TEST(Parameters, RefusesMalformedNumbers) {
    for (const char* bad : {"1e", "abc", "nan", "NaN", "inf", "-inf", "Infinity", "", " 1", "1 ", "0x10",
                            "1.0.0", "1e400", "1,5", "--1"}) {
        Driver d;
        std::string msg = d.errorOf({"--density=" + std::string(bad)});
        EXPECT_TRUE(contains(msg, "--density")) << msg;
        EXPECT_TRUE(contains(msg, std::string("'") + bad + "'")) << msg;
        EXPECT_TRUE(contains(msg, "not a finite number")) << msg;
    }
    for (const char* bad : {"1.5", "1e3", "abc", "", "99999999999999999999"}) {
        Driver d;
        std::string msg = d.errorOf({"--steps=" + std::string(bad)});
        EXPECT_TRUE(contains(msg, "--steps: value '" + std::string(bad) + "' is not an integer")) << msg;
    }
    Driver d;
    EXPECT_TRUE(contains(d.errorOf({"--threads", "two"}), "--threads: value 'two' is not an integer"));
}

TEST(Parameters, RefusesOutOfRange) {
    Driver d;
    EXPECT_EQ(d.errorOf({"--radius_min", "-1"}), "--radius_min: value -1 out of range (0, inf)");
    EXPECT_EQ(d.errorOf({"--radius_min", "0"}), "--radius_min: value 0 out of range (0, inf)");
    EXPECT_EQ(d.errorOf({"--restitution", "0"}), "--restitution: value 0 out of range (0, 1]");
    EXPECT_EQ(d.errorOf({"--restitution", "1.5"}), "--restitution: value 1.5 out of range (0, 1]");
    EXPECT_EQ(d.errorOf({"--steps", "0"}), "--steps: value 0 out of range [1, inf)");
    EXPECT_EQ(d.errorOf({"--particles", "2000000"}), "--particles: value 2000000 out of range [1, 1000000]");
    EXPECT_TRUE(contains(d.errorOf({"--threads", "0"}), "--threads: value 0 out of range [1"));
    EXPECT_EQ(d.errorOf({"--mode", "twist"}), "--mode: value 'twist' is not one of: shear, compress");
    EXPECT_TRUE(contains(d.errorOf({"--name", "a/b"}), "--name"));
    // the drivers' --name follows the tools' rule (IO/FileName.h; the tools put the name into the
    // quoted strings of their gnuplot scripts)
    for (const char* bad : {"..", ".", "a'b", "a\"b", "a`b", "a\tb", "a\nb", ""})
        EXPECT_TRUE(contains(d.errorOf({"--name", bad}), "is not a plain file name")) << bad;
    EXPECT_NO_THROW(d.parse({"--name", "run 1.\xc3\xa9"}));
    // nothing was changed by the failed parses
    EXPECT_EQ(d.radiusMin, 1e-3);
    EXPECT_EQ(d.restitution, 0.5);
}

TEST(Parameters, IntRangeOfIntTarget) {
    int n = 0;
    ParameterSet p;
    p.add("n", &n, 1, "", "an int");
    EXPECT_THROW(p.set("n", "3000000000"), InputError);
    p.set("n", "-2147483648");
    EXPECT_EQ(n, std::numeric_limits<int>::min());
}

// setDefault: a driver's own default of a registered parameter is its value, what --help shows and
// what resetToDefaults() restores; a plain set() changes only the value; range checks still apply.
TEST(Parameters, SetDefaultChangesValueHelpAndReset) {
    double t = 0;
    std::string law;
    ParameterSet p;
    p.add("time_max", &t, 0.0, "s", "end time", Range::nonNegative());
    p.add("law", &law, "linear", "contact law", {"linear", "luding"});
    p.setDefault("time_max", "0.3");
    p.setDefault("law", "luding");
    p.set("time_max", "7");  // a later set() is a value, not a default
    EXPECT_EQ(t, 7.0);
    std::ostringstream os;
    p.printHelp(os, "P", "");
    // the default column of each row: "--time_max  0.3", "--law  luding"
    const auto defaultOf = [&](const std::string& flag) {
        std::istringstream rows(os.str());
        std::string line;
        while (std::getline(rows, line)) {
            std::istringstream w(line);
            std::string f, d;
            if (w >> f >> d && f == flag) return d;
        }
        return std::string();
    };
    EXPECT_EQ(defaultOf("--time_max"), "0.3") << os.str();
    EXPECT_EQ(defaultOf("--law"), "luding") << os.str();
    EXPECT_FALSE(contains(os.str(), " 7 ")) << os.str();
    p.resetToDefaults();
    EXPECT_EQ(t, 0.3);
    EXPECT_EQ(law, "luding");
    EXPECT_THROW(p.setDefault("time_max", "-1"), InputError);
    EXPECT_THROW(p.setDefault("no_such", "1"), InputError);
}

TEST(Parameters, PresetAppliedFirstExplicitFlagsWin) {
    {
        Driver d;
        d.parse({"--preset", "dense"});
        EXPECT_EQ(d.density, 3000.0);
        EXPECT_EQ(d.particles, 5000);
        EXPECT_FALSE(d.params.wasSetOnCommandLine("density"));
    }
    {   // explicit flag before the preset still wins
        Driver d;
        auto o = d.parse({"--density", "1234", "--preset", "dense"});
        EXPECT_EQ(o.preset, "dense");
        EXPECT_EQ(d.density, 1234.0);
        EXPECT_EQ(d.particles, 5000);
    }
    {   // and after it
        Driver d;
        d.parse({"--preset", "elastic", "--mode", "shear"});
        EXPECT_EQ(d.restitution, 0.99);
        EXPECT_EQ(d.mode, "shear");
    }
    Driver d;
    std::string msg = d.errorOf({"--preset", "loose"});
    EXPECT_TRUE(contains(msg, "--preset: unknown preset 'loose'")) << msg;
    EXPECT_TRUE(contains(msg, "dense")) << msg;
}

TEST(Parameters, InvalidPresetValueIsReportedWhenApplied) {
    double x = 0;
    ParameterSet p;
    p.add("x", &x, 1, "m", "x", Range::positive());
    p.addPreset("bad", "broken", {{"x", "-3"}});
    try {
        parseCommandLine(std::vector<std::string>{"--preset", "bad"}, p);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_TRUE(contains(e.what(), "preset 'bad'")) << e.what();
        EXPECT_TRUE(contains(e.what(), "--x: value -3 out of range (0, inf)")) << e.what();
    }
}

TEST(Parameters, RegistrationErrorsAreLogicErrors) {
    double x = 0, y = 0;
    ParameterSet p;
    p.add("x", &x, 1, "", "x");
    EXPECT_THROW(p.add("x", &y, 1, "", "again"), std::logic_error);
    EXPECT_THROW(p.add("output", &y, 1, "", "clash"), std::logic_error);
    EXPECT_THROW(p.add("y", &y, -1, "", "bad default", Range::positive()), std::logic_error);
    EXPECT_THROW(p.addPreset("p", "", {{"nope", "1"}}), std::logic_error);
}

TEST(Parameters, HelpListsEveryParameterAndPreset) {
    Driver d;
    std::ostringstream os;
    d.params.printHelp(os, "MyDriver", "Shears a box of particles.");
    const std::string h = os.str();
    EXPECT_TRUE(contains(h, "MyDriver"));
    EXPECT_TRUE(contains(h, "Shears a box of particles."));
    for (const auto& [name, value] : d.params.values()) EXPECT_TRUE(contains(h, "--" + name)) << name;
    for (const auto& common : commonFlagNames()) EXPECT_TRUE(contains(h, "--" + common)) << common;
    EXPECT_TRUE(contains(h, "(0, inf)"));
    EXPECT_TRUE(contains(h, "kg/m^3"));
    EXPECT_TRUE(contains(h, "particle density"));
    EXPECT_TRUE(contains(h, "shear|compress"));
    EXPECT_TRUE(contains(h, "0.001"));
    EXPECT_TRUE(contains(h, "dense"));
    EXPECT_TRUE(contains(h, "a dense packing"));
    EXPECT_TRUE(contains(h, "almost elastic"));
    // aligned: the meaning column starts at the same offset for every parameter line
    std::istringstream in(h);
    std::string line;
    std::size_t col = std::string::npos;
    int rows = 0;
    while (std::getline(in, line)) {
        for (const char* key : {"smallest particle radius", "particle density", "number of time steps"}) {
            auto p = line.find(key);
            if (p == std::string::npos) continue;
            if (col == std::string::npos) col = p;
            EXPECT_EQ(p, col) << line;
            ++rows;
        }
    }
    EXPECT_EQ(rows, 3);
}

TEST(Parameters, GetSetRoundTripsDoublesExactly) {
    double x = 0;
    ParameterSet p;
    p.add("x", &x, 0.1, "", "x");
    EXPECT_EQ(p.get("x"), "0.10000000000000001");
    const double samples[] = {0.1, 1.0 / 3.0, 2.0 / 3.0, 1e-300, 4.9406564584124654e-324, 1.7976931348623157e308,
                              -123456.789, 6.02214076e23, std::nextafter(1.0, 2.0), 0.0, -0.0};
    for (double v : samples) {
        x = v;
        const std::string text = p.get("x");
        x = 42;
        p.set("x", text);
        EXPECT_EQ(std::memcmp(&x, &v, sizeof v), 0) << text;
    }
    // values() lists all, in registration order, with the same text as get()
    Driver d;
    auto vals = d.params.values();
    ASSERT_EQ(vals.size(), 9u);
    EXPECT_EQ(vals[0].first, "radius_min");
    EXPECT_EQ(vals[8].first, "label");
    EXPECT_EQ(vals[0].second, d.params.get("radius_min"));
    EXPECT_EQ(d.params.get("steps"), "1000");
    EXPECT_EQ(d.params.get("fstat"), "0");
    EXPECT_EQ(d.params.get("mode"), "shear");
    EXPECT_THROW(d.params.get("nope"), InputError);
    EXPECT_THROW(d.params.set("nope", "1"), InputError);
}

TEST(Parameters, ResetToDefaults) {
    Driver d;
    d.parse({"--density", "10", "--mode", "compress"});
    d.params.resetToDefaults();
    EXPECT_EQ(d.density, 2500.0);
    EXPECT_EQ(d.mode, "shear");
    EXPECT_FALSE(d.params.wasSetOnCommandLine("density"));
}

TEST(Parameters, StrictNumberHelpers) {
    double v = 7;
    EXPECT_TRUE(parseStrictDouble("-1.5e-3", v));
    EXPECT_EQ(v, -1.5e-3);
    EXPECT_TRUE(parseStrictDouble("+2", v));
    EXPECT_EQ(v, 2.0);
    EXPECT_FALSE(parseStrictDouble("nan", v));
    EXPECT_FALSE(parseStrictDouble("1e", v));
    EXPECT_EQ(v, 2.0);
    long n = 0;
    EXPECT_TRUE(parseStrictLong("-12", n));
    EXPECT_EQ(n, -12);
    EXPECT_FALSE(parseStrictLong("12a", n));
    EXPECT_EQ(formatDoubleShort(0.1), "0.1");
    EXPECT_EQ(formatDouble(0.5), "0.5");
}
