// Kernel/IO/Json: strict parsing (every refused construct with its line:column), exact number
// round-trip, escapes, member order, typed access errors, atomic file writing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "Core/Error.h"
#include "IO/Json.h"

using namespace pdpm;

namespace {
std::string errorOf(const std::string& text) {
    try {
        parseJson(text, "t.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}
} // namespace

TEST(Json, ParsesAllTypes) {
    const Json j = parseJson(R"({"a": 1, "b": [true, false, null], "c": {"d": "x\ny\u00e9\ud83d\ude00"}, "e": -0.5e-3})");
    ASSERT_TRUE(j.isObject());
    EXPECT_EQ(j.at("a").asNumber(), 1.0);
    EXPECT_EQ(j.at("b").size(), 3u);
    EXPECT_TRUE(j.at("b").asArray()[0].asBool());
    EXPECT_TRUE(j.at("b").asArray()[2].isNull());
    EXPECT_EQ(j.at("c").at("d").asString(), "x\ny\xc3\xa9\xf0\x9f\x98\x80");
    EXPECT_EQ(j.at("e").asNumber(), -0.5e-3);
    // member order is file order
    EXPECT_EQ(j.asObject()[0].first, "a");
    EXPECT_EQ(j.asObject()[3].first, "e");
}

TEST(Json, RoundTripIsExact) {
    Json j = Json::object();
    j.set("pi", 3.141592653589793);
    j.set("tiny", 1e-300);
    j.set("third", 1.0 / 3.0);
    j.set("text", "quote \" backslash \\ tab \t ctrl \x01");
    j.set("list", Json::array({1.5, -2.0, 0.1}));
    Json steps = Json::array();
    steps.push(Json::object({{"type", "ramp"}, {"velocity_m_s", 5e-5}}));
    j.set("steps", steps);
    for (int indent : {0, 2}) {
        const Json back = parseJson(j.dump(indent));
        EXPECT_EQ(back, j) << j.dump(indent);
        EXPECT_EQ(back.at("third").asNumber(), 1.0 / 3.0);
    }
    // what is written reads back: UTF-8 text unchanged, a byte that is not UTF-8 (a Latin-1 file name)
    // as its Latin-1 character
    Json names = Json::object();
    names.set("utf8", "\xc2\xb5m \xe2\x80\x94");
    names.set("latin1", "caf\xe9.csv");
    const Json nb = parseJson(names.dump());
    EXPECT_EQ(nb.at("utf8").asString(), "\xc2\xb5m \xe2\x80\x94");
    EXPECT_EQ(nb.at("latin1").asString(), "caf\xc3\xa9.csv");
    // set() on an existing key replaces in place
    j.set("pi", 3.0);
    EXPECT_EQ(j.asObject()[0].first, "pi");
    EXPECT_EQ(j.at("pi").asNumber(), 3.0);
}

TEST(Json, RefusesMalformedWithPosition) {
    EXPECT_NE(errorOf("{\"a\": 1,}").find("t.json:1:"), std::string::npos);
    EXPECT_NE(errorOf("{\"a\": 1,}").find("trailing comma"), std::string::npos);
    EXPECT_NE(errorOf("{\n  \"a\": 01\n}").find("t.json:2:"), std::string::npos);
    EXPECT_NE(errorOf("{\"a\": 1, \"a\": 2}").find("duplicate key"), std::string::npos);
    EXPECT_NE(errorOf("[1, 2] x").find("after the JSON value"), std::string::npos);
    for (const char* bad : {"", "{", "[1,]", "NaN", "Infinity", "-", "1.", ".5", "1e", "1e400", "tru", "\"abc",
                            "\"a\tb\"", "\"\\x\"", "\"\\ud800\"", "// c\n1", "{'a': 1}", "{a: 1}", "[1 2]", "+1",
                            "{\"a\" 1}"}) {
        EXPECT_FALSE(errorOf(bad).empty()) << "accepted: " << bad;
    }
    // JSON text is UTF-8: a stray byte, a truncated or overlong sequence, an encoded surrogate are refused
    for (const char* bad : {"\"a\xff\"", "\"\x80\"", "\"\xc3\"", "\"\xc0\xaf\"", "\"\xed\xa0\x80\"",
                            "\"\xf4\x90\x80\x80\"", "\"\xe2\x82\""}) {
        EXPECT_NE(errorOf(bad).find("UTF-8"), std::string::npos) << "accepted: " << bad;
    }
    // well-formed multi-byte characters pass through unchanged
    EXPECT_EQ(parseJson("\"\xc2\xb5m \xe2\x80\x94 \xf0\x9f\x98\x80\"", "t.json").asString(),
              "\xc2\xb5m \xe2\x80\x94 \xf0\x9f\x98\x80");
    std::string deep(300, '[');
    deep += std::string(300, ']');
    EXPECT_NE(errorOf(deep).find("nesting"), std::string::npos);
}

TEST(Json, TypedAccessErrors) {
    const Json j = parseJson(R"({"n": "five"})");
    EXPECT_THROW(j.at("n").asNumber("n"), InputError);
    EXPECT_THROW(j.at("missing"), InputError);
    try {
        j.at("n").asNumber("steps[0].n");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("steps[0].n: expected a number (got a string)"), std::string::npos);
    }
    EXPECT_THROW(Json(std::nan("")), InputError);
}

TEST(Json, FileRoundTrip) {
    const std::string path = "json_test_file.json";
    Json j = Json::object({{"device", "ft4"}, {"D_m", 0.05}});
    writeJsonFile(path, j);
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
    EXPECT_EQ(readJsonFile(path), j);
    std::remove(path.c_str());
    EXPECT_THROW(readJsonFile("does_not_exist.json"), InputError);
}
