// Command lines the tools hand to /bin/sh (Tools/Common/Shell.h): text a user gives reaches the
// program as words, never as shell syntax.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "Shell.h"
#include "TempDir.h"

using pdpm::tools::shellQuote;
using pdpm::tools::shellWords;

namespace {
/// The words that sh passes to printf for `words` (one per line), run through std::system as the tools do.
std::vector<std::string> wordsSeenByTheProgram(const std::string& words, const std::string& outFile) {
    const int rc = std::system(("printf '%s\\n'" + words + " > " + shellQuote(outFile) + " 2>&1").c_str());
    EXPECT_EQ(rc, 0);
    std::ifstream in(outFile);
    std::vector<std::string> seen;
    for (std::string line; std::getline(in, line);) seen.push_back(line);
    return seen;
}
} // namespace

TEST(Shell, ExtraArgumentsAreWordsNotShellSyntax) {
    pdpm::testing::TempDir dir;
    const std::string marker = dir.file("INJECTED");
    // what a user may type into --driver_args, harmless or not
    const std::string text = "--width 4  --fill_height\t5 ; touch " + marker + " # $(touch " + marker + ") `id` \"x 'y' a>b |c &";
    const std::vector<std::string> seen = wordsSeenByTheProgram(shellWords(text), dir.file("out.txt"));
    std::istringstream split(text);
    std::vector<std::string> expected;
    for (std::string w; split >> w;) expected.push_back(w);
    EXPECT_EQ(seen, expected);
    EXPECT_FALSE(std::filesystem::exists(marker)) << "the shell ran part of the arguments";
    EXPECT_EQ(shellWords(""), "");
    EXPECT_EQ(shellWords("  \t "), "");
}

TEST(Shell, QuotedPathIsOneWord) {
    pdpm::testing::TempDir dir;
    const std::string path = "a b'c\"d$e`f;g";
    const std::vector<std::string> seen = wordsSeenByTheProgram(" " + shellQuote(path), dir.file("out.txt"));
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_EQ(seen[0], path);
}
