#include "Core/Error.h"
#include "IO/AtomicFile.h"

#include <gtest/gtest.h>

#include "TempDir.h"

#include <filesystem>
#include <stdexcept>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace pdpm;

namespace {

using pdpm::testing::TempDir;

} // namespace

TEST(AtomicFile, WritesTmpThenRenames) {
    TempDir dir;
    const std::string target = dir.file("out.txt");
    {
        AtomicOFStream out(target);
        out << "hello " << 42 << '\n';
        EXPECT_TRUE(fs::exists(target + ".tmp"));
        EXPECT_FALSE(fs::exists(target));
        EXPECT_EQ(out.tmpPath(), target + ".tmp");
        out.commit();
        EXPECT_TRUE(out.committed());
        EXPECT_FALSE(fs::exists(target + ".tmp"));
    }
    EXPECT_TRUE(fs::exists(target));
    EXPECT_EQ(readWholeFile(target), "hello 42\n");
}

TEST(AtomicFile, NoFileWithoutCommit) {
    TempDir dir;
    const std::string target = dir.file("aborted.txt");
    try {
        AtomicOFStream out(target);
        out << "partial";
        throw std::runtime_error("simulated crash");
    } catch (const std::runtime_error&) {
    }
    EXPECT_FALSE(fs::exists(target));
    EXPECT_FALSE(fs::exists(target + ".tmp"));
}

TEST(AtomicFile, AbortKeepsPreviousVersion) {
    TempDir dir;
    const std::string target = dir.file("keep.txt");
    writeWholeFile(target, "version 1");
    {
        AtomicOFStream out(target);
        out << "version 2, incomplete";
        out.abort();
        EXPECT_FALSE(fs::exists(target + ".tmp"));
    }
    EXPECT_EQ(readWholeFile(target), "version 1");
    {
        AtomicOFStream out(target);
        out << "version 2";
    }  // destructor without commit
    EXPECT_EQ(readWholeFile(target), "version 1");
    {
        AtomicOFStream out(target);
        out.setSync(true);
        out << "version 3";
        out.commit();
        EXPECT_THROW(out.commit(), std::logic_error);
    }
    EXPECT_EQ(readWholeFile(target), "version 3");
}

TEST(AtomicFile, BinaryContentRoundTrips) {
    TempDir dir;
    std::string data;
    for (int i = 0; i < 256; ++i) data += static_cast<char>(i);
    writeWholeFile(dir.file("bin"), data);
    EXPECT_EQ(readWholeFile(dir.file("bin")), data);
    writeWholeFile(dir.file("empty"), "");
    EXPECT_EQ(readWholeFile(dir.file("empty")), "");
}

TEST(AtomicFile, OpenFailsInMissingDirectory) {
    TempDir dir;
    try {
        AtomicOFStream out(dir.file("no/such/dir/file.txt"));
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("file.txt.tmp"), std::string::npos) << e.what();
    }
}

TEST(AtomicFile, EnsureDirectory) {
    TempDir dir;
    const std::string nested = dir.file("a/b/c");
    ensureDirectory(nested);
    EXPECT_TRUE(fs::is_directory(nested));
    ensureDirectory(nested);  // already there: fine
    writeWholeFile(dir.file("plain"), "x");
    EXPECT_THROW(ensureDirectory(dir.file("plain")), InputError);
    EXPECT_THROW(ensureDirectory(dir.file("plain/sub")), InputError);
    EXPECT_THROW(ensureDirectory(""), InputError);
}

TEST(AtomicFile, ReadWholeFileErrors) {
    TempDir dir;
    try {
        readWholeFile(dir.file("missing.txt"));
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("missing.txt"), std::string::npos) << e.what();
    }
    EXPECT_THROW(readWholeFile(dir.path.string()), InputError);
}
