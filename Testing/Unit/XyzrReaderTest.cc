// Start files of the benchmark decks (../shared/bench/README.md): "# box" and "# case ... density"
// header lines, then "id x y z r" rows. Malformed files are input errors naming the line.
#include <gtest/gtest.h>

#include <string>

#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "IO/XyzrReader.h"
#include "TempDir.h"

using namespace pdpm;

namespace {
const char* kHeader = "# case test  N 2  density 2500\n# box 0 1 0 2 0 3\n";
}

TEST(XyzrReader, ReadsBoxDensityAndParticles) {
    const pdpm::testing::TempDir tmp;
    writeWholeFile(tmp.file("ok.xyzr"), std::string(kHeader) + "0 0.5 1.0 1.5 0.1\n1 0 2 3 0.2\n");
    const XyzrFile f = readXyzr(tmp.file("ok.xyzr"));
    ASSERT_TRUE(f.hasBox);
    EXPECT_EQ(f.hi.y, 2.0);
    EXPECT_EQ(f.density, 2500.0);
    ASSERT_EQ(f.x.size(), 2u);
    EXPECT_EQ(f.x[0].z, 1.5);
    EXPECT_EQ(f.r[1], 0.2);  // a centre on the box face is inside
}

TEST(XyzrReader, MalformedFilesAreInputErrors) {
    const pdpm::testing::TempDir tmp;
    const std::pair<const char*, std::string> bad[] = {
        {"empty", ""},
        {"header only", kHeader},
        {"non-numeric", std::string(kHeader) + "0 0.5 x 1.5 0.1\n"},
        {"ragged", std::string(kHeader) + "0 0.5 1.0 1.5\n"},
        {"extra column", std::string(kHeader) + "0 0.5 1.0 1.5 0.1 7\n"},
        {"NaN position", std::string(kHeader) + "0 nan 1.0 1.5 0.1\n"},
        {"zero radius", std::string(kHeader) + "0 0.5 1.0 1.5 0\n"},
        {"box upside down", "# box 1 0 0 2 0 3\n0 0.5 1.0 1.5 0.1\n"},
        {"centre outside the box", std::string(kHeader) + "0 0.5 1.0 1.5 0.1\n1 5.0 1.0 1.5 0.1\n"},
        {"centre far outside the box", std::string(kHeader) + "0 1e300 1.0 1.5 0.1\n"},
    };
    for (const auto& [what, text] : bad) {
        writeWholeFile(tmp.file("bad.xyzr"), text);
        EXPECT_THROW(readXyzr(tmp.file("bad.xyzr")), InputError) << what;
    }
    EXPECT_THROW(readXyzr(tmp.file("missing.xyzr")), InputError);
}
