// StateFields (driver state in restart files) and the staggered pour column.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "Core/Error.h"
#include "IO/StateFields.h"
#include "Particles/Insertion.h"

using namespace pdpm;

TEST(StateFields, RoundTripIsExact) {
    double a = 0.1 + 0.2, tiny = std::numeric_limits<double>::denorm_min();
    bool flag = true;
    std::size_t index = 123456789012ULL;
    long neg = -42;
    int small = 7;
    StateFields out;
    out.add("a", a).add("tiny", tiny).add("flag", flag).add("index", index).add("neg", neg).add("small", small);
    StateFields::KeyValues kv;
    out.save(kv);
    ASSERT_EQ(kv.size(), 6u);

    double a2 = 0, tiny2 = 1;
    bool flag2 = false;
    std::size_t index2 = 0;
    long neg2 = 0;
    int small2 = 0;
    StateFields in;
    in.add("a", a2).add("tiny", tiny2).add("flag", flag2).add("index", index2).add("neg", neg2).add("small", small2);
    for (const auto& [k, v] : kv) EXPECT_TRUE(in.load(k, v)) << k;
    EXPECT_EQ(a2, a);  // bitwise: fmt() writes 17 significant digits
    EXPECT_EQ(tiny2, tiny);
    EXPECT_EQ(flag2, flag);
    EXPECT_EQ(index2, index);
    EXPECT_EQ(neg2, neg);
    EXPECT_EQ(small2, small);
}

TEST(StateFields, UnknownKeyIsLeftToTheCallerAndBadNumberIsAnInputError) {
    double x = 1;
    StateFields f;
    f.add("x", x);
    EXPECT_FALSE(f.load("y", "2"));
    EXPECT_EQ(x, 1);
    EXPECT_THROW(f.load("x", "2.0abc"), InputError);
    EXPECT_THROW(f.load("x", ""), InputError);
    EXPECT_THROW(f.load("x", "nan"), InputError);
}

// A restart file edited after it was sealed may drop a line of the driver state: the member would
// keep its set-up value, so a missing field is an input error naming it.
TEST(StateFields, EveryBoundFieldMustBeInTheFile) {
    double a = 1, b = 2;
    StateFields f;
    f.add("a", a).add("b", b);
    StateFields::KeyValues kv;
    f.save(kv);
    EXPECT_NO_THROW(f.requireAll(kv));
    kv.pop_back();
    try {
        f.requireAll(kv);
        ADD_FAILURE() << "a missing field was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("'b'"), std::string::npos) << e.what();
    }
    EXPECT_THROW(requireDriverKeys(kv, {"a", "stage"}), InputError);
    EXPECT_NO_THROW(requireDriverKeys(kv, {"a"}));
}

TEST(StateFields, IntegerAndBoolFieldsTakeOnlyTheirValues) {
    // an edited restart file must not reach the member through a silent conversion
    std::size_t index = 3;
    long neg = 0;
    int small = 0;
    bool flag = false;
    StateFields f;
    f.add("index", index).add("neg", neg).add("small", small).add("flag", flag);
    for (const char* bad : {"0.5", "-1", "1e300", "1e19"}) EXPECT_THROW(f.load("index", bad), InputError) << bad;
    EXPECT_THROW(f.load("neg", "2.5"), InputError);
    EXPECT_THROW(f.load("small", "3e9"), InputError);  // beyond int
    for (const char* bad : {"2", "-1", "0.5"}) EXPECT_THROW(f.load("flag", bad), InputError) << bad;
    EXPECT_EQ(index, 3u);  // untouched by the refused values
    EXPECT_TRUE(f.load("index", "7"));
    EXPECT_TRUE(f.load("neg", "-7"));
    EXPECT_TRUE(f.load("small", "-2147483648"));
    EXPECT_TRUE(f.load("flag", "1"));
    EXPECT_EQ(index, 7u);
    EXPECT_EQ(neg, -7);
    EXPECT_EQ(small, -2147483648);
    EXPECT_TRUE(flag);
}

TEST(StateFields, NumberListsRoundTrip) {
    const std::vector<double> v = {1.0 / 3.0, -2e-300, 0, 12345.678};
    EXPECT_EQ(splitNumbers(joinNumbers(v), "k"), v);
    EXPECT_EQ(joinNumbers({}), "-");
    EXPECT_TRUE(splitNumbers("-", "k").empty());
    EXPECT_THROW(splitNumbers("1 x 3", "k"), InputError);
}

TEST(StaggeredColumn, SpacingLayersAndDiscClearance) {
    const double s = 1.0, R = 4.0, clearance = 0.5;
    const auto pts = staggeredColumn(500, s, 2 * R, R, clearance);
    ASSERT_EQ(pts.size(), 500u);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        EXPECT_LE(std::hypot(pts[i].x, pts[i].y), R - clearance + 1e-12);
        for (std::size_t j = 0; j < i; ++j) {
            const double dx = pts[i].x - pts[j].x, dy = pts[i].y - pts[j].y, dz = pts[i].z - pts[j].z;
            EXPECT_GE(dx * dx + dy * dy + dz * dz, s * s - 1e-9);
        }
    }
    // odd layers are shifted by s/2 in x and y: no point has one straight above it in the next layer
    int layerPairs = 0;
    for (const auto& p : pts)
        for (const auto& q : pts)
            if (std::abs(q.z - p.z - s) < 1e-9) {
                ++layerPairs;
                EXPECT_FALSE(std::abs(q.x - p.x) < 1e-9 && std::abs(q.y - p.y) < 1e-9);
            }
    EXPECT_GT(layerPairs, 0);  // the layers are s apart, so the check above saw pairs of layers
    // square cross-section: all points inside [0, lx]^2
    const auto sq = staggeredColumn(100, s, 5.0, 0, 0);
    ASSERT_EQ(sq.size(), 100u);
    for (const auto& p : sq) {
        EXPECT_GT(p.x, 0);
        EXPECT_LT(p.x, 5.0);
        EXPECT_GT(p.y, 0);
        EXPECT_LT(p.y, 5.0);
    }
    EXPECT_THROW(staggeredColumn(10, s, 1.0, 0.5, 0.6), InputError);  // nothing fits the disc
}
