#include "IO/AtomicFile.h"

#include "Core/Error.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace fs = std::filesystem;

namespace pdpm {

namespace {

std::string errnoText(int err) { return std::strerror(err); }

void removeQuietly(const std::string& p) {
    std::error_code ec;
    fs::remove(p, ec);
}

} // namespace

AtomicOFStream::AtomicOFStream(const std::string& path, bool binary)
    : std::ostream(nullptr), path_(path), tmpPath_(path + ".tmp") {
    if (path.empty()) throw InputError("cannot write a file with an empty name");
    std::ios::openmode mode = std::ios::out | std::ios::trunc;
    if (binary) mode |= std::ios::binary;
    errno = 0;
    if (!buf_.open(tmpPath_, mode)) {
        const int err = errno;
        throw InputError("cannot open '" + tmpPath_ + "' for writing" +
                         (err ? ": " + errnoText(err) : std::string()));
    }
    rdbuf(&buf_);
}

AtomicOFStream::~AtomicOFStream() {
    if (!committed_) {
        if (!closed_) buf_.close();
        removeQuietly(tmpPath_);
    }
}

void AtomicOFStream::abort() {
    if (committed_) return;
    if (!closed_) {
        buf_.close();
        closed_ = true;
    }
    removeQuietly(tmpPath_);
    setstate(std::ios::badbit);
}

void AtomicOFStream::commit() {
    if (committed_) throw std::logic_error("AtomicOFStream::commit called twice for '" + path_ + "'");
    if (closed_) throw InputError("cannot commit '" + path_ + "': the file was aborted");
    auto fail = [&](const std::string& what) {
        buf_.close();
        closed_ = true;
        removeQuietly(tmpPath_);
        throw InputError("error writing '" + path_ + "': " + what);
    };
    errno = 0;
    flush();
    if (!good()) fail(errno ? errnoText(errno) : std::string("write failed (disk full?)"));
    errno = 0;
    if (!buf_.close()) fail(errno ? errnoText(errno) : std::string("close failed"));
    closed_ = true;
    if (sync_) {
        const int fd = ::open(tmpPath_.c_str(), O_RDONLY);
        if (fd < 0) fail(errnoText(errno));
        const int rc = ::fsync(fd);
        const int err = errno;
        ::close(fd);
        if (rc != 0) fail("fsync: " + errnoText(err));
    }
    std::error_code ec;
    fs::rename(tmpPath_, path_, ec);
    if (ec) {
        removeQuietly(tmpPath_);
        throw InputError("cannot rename '" + tmpPath_ + "' to '" + path_ + "': " + ec.message());
    }
    committed_ = true;
}

void ensureDirectory(const std::string& dir) {
    if (dir.empty()) throw InputError("empty directory name");
    std::error_code ec;
    if (fs::is_directory(dir, ec)) return;
    fs::create_directories(dir, ec);
    if (ec) throw InputError("cannot create directory '" + dir + "': " + ec.message());
    if (!fs::is_directory(dir, ec)) throw InputError("cannot create directory '" + dir + "': not a directory");
}

std::string readWholeFile(const std::string& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw InputError("cannot read '" + path + "': no such file");
    if (fs::is_directory(path, ec)) throw InputError("cannot read '" + path + "': it is a directory");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot open '" + path + "' for reading: " + errnoText(errno));
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw InputError("error reading '" + path + "'");
    return ss.str();
}

void writeWholeFile(const std::string& path, const std::string& content) {
    AtomicOFStream out(path, true);
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.commit();
}

} // namespace pdpm
