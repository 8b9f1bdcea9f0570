#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "IO/Csv.h"

#include <gtest/gtest.h>

#include "TempDir.h"

#include <cmath>
#include <filesystem>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace pdpm;

namespace {

using pdpm::testing::TempDir;

std::string errorOf(const std::string& text) {
    try {
        parseCsv(text, "t.csv");
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected InputError for:\n" << text;
    return {};
}

} // namespace

TEST(Csv, ParsesCommentsBlankLinesAndSpaces) {
    const auto t = parseCsv("# a comment\n\nx, y ,z\r\n1,2,3\n  # indented comment\n-4.5e-3 , 5,6\n", "t.csv");
    ASSERT_EQ(t.columns, (std::vector<std::string>{"x", "y", "z"}));
    ASSERT_EQ(t.rows.size(), 2u);
    EXPECT_EQ(t.rows[1][0], -4.5e-3);
    EXPECT_EQ(t.column("z"), 2);
    EXPECT_TRUE(t.hasColumn("y"));
    EXPECT_FALSE(t.hasColumn("w"));
    EXPECT_EQ(t.columnValues("y"), (std::vector<double>{2, 5}));
    EXPECT_THROW(t.column("w"), InputError);
}

TEST(Csv, LabelColumn) {
    const auto t = parseCsv("# c\nparameter, a ,b\nbeta_s,1,2\ns_max , 3,4e-1\n", "t.csv", true);
    EXPECT_EQ(t.labelColumn, "parameter");
    ASSERT_EQ(t.columns, (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(t.labels, (std::vector<std::string>{"beta_s", "s_max"}));
    ASSERT_EQ(t.rows.size(), 2u);
    EXPECT_EQ(t.rows[1], (std::vector<double>{3, 0.4}));
    EXPECT_EQ(t.column("b"), 1);
    EXPECT_EQ(t.rowLines, (std::vector<long>{3, 4}));
    for (const auto& [text, msg] : std::vector<std::pair<std::string, std::string>>{
             {"p,a\n,1\n", "t.csv:2: empty label in column 'p'"},
             {"p,a\nx,1,2\n", "t.csv:2: expected 2 cells, found 3"},
             {"p,a\nx,y\n", "t.csv:2: column 'a': 'y' is not a finite number"}}) {
        try {
            parseCsv(text, "t.csv", true);
            ADD_FAILURE() << text;
        } catch (const InputError& e) {
            EXPECT_EQ(std::string(e.what()), msg);
        }
    }
    EXPECT_THROW(parseCsv("p,a\nx,1\n", "t.csv"), InputError);  // without the option: 'x' is no number
}

TEST(Csv, HeaderOnlyIsEmptyTable) {
    const auto t = parseCsv("a,b\n", "t.csv");
    EXPECT_EQ(t.columns.size(), 2u);
    EXPECT_TRUE(t.rows.empty());
}

TEST(Csv, ErrorsNameFileAndLine) {
    EXPECT_EQ(errorOf("a,b\n1,2\n3\n"), "t.csv:3: expected 2 cells, found 1");
    EXPECT_EQ(errorOf("# c\na,b\n1,2,3\n"), "t.csv:3: expected 2 cells, found 3");
    EXPECT_EQ(errorOf("a,b\n1,2\n\n1,abc\n"), "t.csv:4: column 'b': 'abc' is not a finite number");
    EXPECT_EQ(errorOf("a,b\n1,nan\n"), "t.csv:2: column 'b': NaN is not allowed");
    EXPECT_EQ(errorOf("a,b\nNaN,1\n"), "t.csv:2: column 'a': NaN is not allowed");
    EXPECT_EQ(errorOf("a,b\n1,inf\n"), "t.csv:2: column 'b': 'inf' is not a finite number");
    EXPECT_EQ(errorOf("a,b\n1,\n"), "t.csv:2: column 'b': '' is not a finite number");
    EXPECT_EQ(errorOf("a,a\n"), "t.csv:1: duplicate column name 'a'");
    EXPECT_EQ(errorOf("a,,c\n"), "t.csv:1: empty column name in header (column 2)");
    EXPECT_EQ(errorOf("\"a\",b\n"), "t.csv:1: quoted cells are not supported");
    EXPECT_EQ(errorOf("# only comments\n"), "t.csv: no header line");
}

TEST(Csv, ReadMissingFile) {
    TempDir dir;
    EXPECT_THROW(readCsv(dir.file("missing.csv")), InputError);
}

TEST(Csv, WriteReadRoundTripIsExact) {
    TempDir dir;
    const std::string path = dir.file("table.csv");
    std::vector<std::vector<double>> rows = {{0.1, 1.0 / 3.0, -1e-300},
                                             {6.02214076e23, std::nextafter(1.0, 0.0), 0.0},
                                             {-0.0, 1.7976931348623157e308, 4.9406564584124654e-324}};
    writeCsv(path, {"a", "b", "c"}, rows, {"written by a test", "two lines"});
    EXPECT_FALSE(fs::exists(path + ".tmp"));
    const auto t = readCsv(path);
    EXPECT_EQ(t.source, path);
    EXPECT_EQ(t.columns, (std::vector<std::string>{"a", "b", "c"}));
    ASSERT_EQ(t.rows.size(), rows.size());
    for (std::size_t r = 0; r < rows.size(); ++r)
        for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(t.rows[r][c], rows[r][c]) << r << "," << c;
    const std::string text = readWholeFile(path);
    EXPECT_EQ(text.rfind("# written by a test\n# two lines\na,b,c\n0.10000000000000001,", 0), 0u) << text;
}

TEST(Csv, WriteRefusesBadInputAndLeavesNoFile) {
    TempDir dir;
    const std::string path = dir.file("bad.csv");
    EXPECT_THROW(writeCsv(path, {"a", "b"}, {{1, 2}, {3}}), InputError);
    EXPECT_THROW(writeCsv(path, {"a", "b,c"}, {}), InputError);
    EXPECT_THROW(writeCsv(path, {}, {}), InputError);
    EXPECT_THROW(writeCsv(path, {"a"}, {{1}, {std::nan("")}}), InputError);
    EXPECT_FALSE(fs::exists(path));
    EXPECT_FALSE(fs::exists(path + ".tmp"));
}
