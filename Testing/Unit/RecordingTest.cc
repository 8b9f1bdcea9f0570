// Recording format (Tools/Recording): validation of time series with line numbers, protocol JSON
// round-trip and strictness, command-line step syntax, Table 4.3 presets, and the Eq. (4.3) fit.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "Core/Error.h"
#include "Recording.h"
#include "TempDir.h"

using namespace pdpm;
using namespace pdpm::recording;

namespace {
const char* kValid =
    "# source: test\n"
    "time_s,axial_stress_Pa,axial_strain,volume_fraction,step\n"
    "0,0,0,0.4,0\n"
    "0.5,100.5,0.001,0.401,0\n"
    "1.0,200,0.002,0.402,1\n";

/// Line of the first problem whose message contains `needle` (-1 if none).
long lineOf(const std::string& text, const std::string& needle) {
    for (const auto& p : checkRecording(text))
        if (p.message.find(needle) != std::string::npos) return p.line;
    return -1;
}
} // namespace

TEST(Recording, ValidFileParses) {
    Recording r;
    const auto p = checkRecording(kValid, &r);
    ASSERT_TRUE(p.empty()) << p[0].message;
    EXPECT_EQ(r.rows.size(), 3u);
    EXPECT_EQ(r.values("axial_stress_Pa")[1], 100.5);
    EXPECT_EQ(r.comments.at(0), "source: test");
}

TEST(Recording, ProblemsCarryLineNumbers) {
    EXPECT_EQ(lineOf("axial_stress_Pa\n1\n", "missing required column 'time_s'"), 1);
    EXPECT_EQ(lineOf("time_s,step\n0,0\n", "no measured channel"), 1);
    EXPECT_EQ(lineOf("# c\ntime_s,axial_stress_kPa\n0,1\n", "wrong unit"), 2);
    EXPECT_EQ(lineOf("time_ms,axial_stress_Pa\n0,1\n", "wrong unit"), 1);
    // a base name followed by something that is not a unit is an extra channel, not a wrong unit
    EXPECT_TRUE(checkRecording("time_s,time_stamp,axial_stress_Pa,axial_stress_Pa_raw\n0,5,1,1\n").empty());
    EXPECT_EQ(lineOf("time_s,axial_stress_Pa\n0,1\n1,nan\n", "not a finite number"), 3);
    EXPECT_EQ(lineOf("time_s,axial_stress_Pa\n0,1\n1,\n", "empty value"), 3);
    EXPECT_EQ(lineOf("time_s,axial_stress_Pa\n0,1\n2,1\n\n1,1\n", "not strictly increasing"), 5);
    EXPECT_EQ(lineOf("time_s,axial_stress_Pa\n0,1\n1,1\n1,2\n", "not strictly increasing"), 4);
    EXPECT_EQ(lineOf("time_s,axial_stress_Pa\n0,1\n1,1,3\n", "expected 2 values"), 3);
    EXPECT_EQ(lineOf("time_s,volume_fraction\n0,0.5\n1,55\n", "volume_fraction"), 3);
    EXPECT_EQ(lineOf("time_s,axial_strain\n0,0\n1,12\n", "axial_strain"), 3);
    EXPECT_EQ(lineOf("time_s,axial_stress_Pa,time_s\n0,1,0\n", "duplicate column"), 1);
    EXPECT_EQ(lineOf("time_s,step,axial_stress_Pa\n0,0.5,1\n", "step must be"), 2);
    EXPECT_EQ(lineOf("", "no header"), 0);
    EXPECT_NE(lineOf("time_s,axial_stress_Pa\n", "no data rows"), -1);
    // several problems are all reported
    EXPECT_GE(checkRecording("time_s,axial_stress_Pa\n0,nan\n1,inf\n2,1\n1.5,1\n").size(), 3u);
}

TEST(Recording, WriterRefusesInvalidAndRoundTrips) {
    Recording r;
    r.columns = {"time_s", "axial_stress_Pa"};
    r.rows = {{0, 1.0 / 3}, {1, 2}};
    const pdpm::testing::TempDir tmp;
    writeRecording(tmp.file("recording_test.csv"), r);
    const Recording back = readRecording(tmp.file("recording_test.csv"));
    EXPECT_EQ(back.rows, r.rows);
    r.rows.push_back({0.5, 3});
    EXPECT_THROW(writeRecording(tmp.file("recording_test_bad.csv"), r), InputError);
    EXPECT_THROW(readRecording("does_not_exist.csv"), InputError);
}

TEST(Recording, ProtocolRoundTripAndStrictness) {
    Protocol p;
    p.device = "ft4";
    p.diameter = 0.05;
    p.height = 0.05;
    p.wallFriction = 0.2;
    p.material = Json::object({{"name", "cocoa"}});
    p.steps = parseSteps("ramp:5e-5:5000, hold:300, unload:1e-4:1000, creep:60:2000, creep:30");
    ASSERT_EQ(p.steps.size(), 5u);
    EXPECT_EQ(p.steps[3].stress, 2000);
    EXPECT_LT(p.steps[4].stress, 0);
    const Json j = protocolToJson(p);
    const Protocol q = protocolFromJson(parseJson(j.dump()));
    EXPECT_EQ(formatSteps(q.steps), formatSteps(p.steps));
    EXPECT_EQ(q.device, "ft4");
    EXPECT_EQ(q.wallFriction, 0.2);
    EXPECT_EQ(parseSteps(formatSteps(p.steps)).size(), 5u);

    Json bad = j;
    Json steps = Json::array({Json::object({{"type", "ramp"}, {"velocity_m_s", -1.0}, {"target_stress_Pa", 5.0}})});
    bad.set("steps", steps);
    try {
        protocolFromJson(bad);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("steps[0].velocity_m_s"), std::string::npos) << e.what();
    }
    bad.set("steps", Json::array({Json::object({{"type", "twist"}})}));
    EXPECT_THROW(protocolFromJson(bad), InputError);
    bad.set("steps", Json::array({Json::object({{"type", "hold_position"}, {"duration_s", 5.0}, {"speed", 1.0}})}));
    EXPECT_THROW(protocolFromJson(bad), InputError);
    for (const char* s : {"", "ramp:1", "hold:-3", "hold:x", "spin:3", "ramp:1:2:3", "creep:0"})
        EXPECT_THROW(parseSteps(s), InputError) << s;
}

// The driver's per-hold results (extra.holds): read back as written, fits that failed (null) as -1,
// a malformed entry named.
TEST(Recording, ProtocolHoldsReadTheDriversHoldResults) {
    Protocol p;
    p.steps = parseSteps("ramp:5e-5:5000, hold:300, ramp:5e-5:9000, creep:60");
    EXPECT_TRUE(protocolHolds(p).empty());
    p.extra.set("holds", parseJson(R"([
      {"step": 1, "type": "hold_position", "lab_start_s": 12.5, "stress_start_Pa": 5000, "fit_C": 0.04, "fit_t0_s": 0.3},
      {"step": 3, "type": "hold_stress", "lab_start_s": 40, "stress_start_Pa": 9000, "fit_C": null, "fit_t0_s": null}])"));
    const Protocol q = protocolFromJson(parseJson(protocolToJson(p).dump()));  // through the file format
    const std::vector<HoldSummary> h = protocolHolds(q);
    ASSERT_EQ(h.size(), 2u);
    EXPECT_TRUE(h[0].position);
    EXPECT_EQ(h[0].step, 1);
    EXPECT_EQ(h[0].labStart, 12.5);
    EXPECT_EQ(h[0].stressStart, 5000);
    EXPECT_EQ(h[0].fitC, 0.04);
    EXPECT_EQ(h[0].fitT0, 0.3);
    EXPECT_FALSE(h[1].position);
    EXPECT_EQ(h[1].fitC, -1);
    for (const char* bad : {R"([{"step": 1, "type": "hold", "lab_start_s": 0, "stress_start_Pa": 1}])",
                            R"([{"step": 1.5, "type": "hold_position", "lab_start_s": 0, "stress_start_Pa": 1}])",
                            R"([{"step": 1, "type": "hold_position", "stress_start_Pa": 1}])", R"([3])"}) {
        Protocol r;
        r.extra.set("holds", parseJson(bad));
        try {
            protocolHolds(r);
            ADD_FAILURE() << bad;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("extra.holds[0]"), std::string::npos) << e.what();
        }
    }
}

TEST(Recording, Table43Presets) {
    const auto p1 = presetSteps(1, 22e3);
    ASSERT_EQ(p1.size(), 10u);
    EXPECT_DOUBLE_EQ(p1[0].velocity, 0.05e-3);
    EXPECT_EQ(p1[1].duration, 300);
    EXPECT_EQ(p1[8].targetStress, 22e3);  // FT4 maximum
    EXPECT_EQ(presetSteps(4)[1].duration, 1800);
    EXPECT_DOUBLE_EQ(presetSteps(9)[0].velocity, 1.3e-3);
    EXPECT_EQ(presetSteps(1)[8].targetStress, 25e3);
    EXPECT_THROW(presetSteps(10), InputError);
}

TEST(Recording, FitRecoversEq43) {
    for (const auto& [C, t0] : {std::pair{0.0792, 0.2894}, std::pair{0.0178, 0.3614}, std::pair{0.03, 0.00082}}) {
        std::vector<double> t, f;
        for (int k = 0; k <= 3000; ++k) {
            t.push_back(100 + 0.1 * k);  // hold starting at lab time 100 s
            f.push_back(5000 * std::pow(1 + 0.1 * k / t0, -C));
        }
        const RelaxationFit fit = fitRelaxation(t, f);
        ASSERT_TRUE(fit.ok);
        EXPECT_NEAR(fit.C, C, 1e-6 * C);  // noise-free: the fit converges to round-off
        EXPECT_NEAR(fit.t0, t0, 1e-6 * t0);
        EXPECT_LT(fit.rms, 1e-6);
    }
}
