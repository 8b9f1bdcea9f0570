// Files that appear complete or not at all.
//
//   pdpm::AtomicOFStream out(dir + "/run.ene");   // writes dir/run.ene.tmp
//   out << "...";
//   out.commit();                                 // flush, check, (fsync), rename to dir/run.ene
//
// If the stream is destroyed without commit() (exception, early return), the .tmp file is removed
// and any previous version of the target file is left untouched.
#pragma once
#include <fstream>
#include <ostream>
#include <string>

namespace pdpm {

class AtomicOFStream : public std::ostream {
public:
    /// Opens `path + ".tmp"` for writing (truncating). Throws InputError if that is impossible.
    /// `binary` opens in binary mode (no difference on POSIX, documents intent).
    explicit AtomicOFStream(const std::string& path, bool binary = false);
    ~AtomicOFStream() override;
    AtomicOFStream(const AtomicOFStream&) = delete;
    AtomicOFStream& operator=(const AtomicOFStream&) = delete;

    /// Flushes, checks that every write succeeded, optionally fsyncs, closes and renames the
    /// temporary file over the target. Throws InputError (naming the file) on any failure, in which
    /// case the temporary file is removed. Calling commit() twice is an error (std::logic_error).
    void commit();
    /// Removes the temporary file without touching the target; the stream becomes unusable.
    void abort();

    /// fsync the file before the rename (default off: slower, only needed against power loss).
    void setSync(bool sync) { sync_ = sync; }

    const std::string& path() const { return path_; }
    const std::string& tmpPath() const { return tmpPath_; }
    bool committed() const { return committed_; }

private:
    std::filebuf buf_;
    std::string path_;
    std::string tmpPath_;
    bool committed_ = false;
    bool closed_ = false;
    bool sync_ = false;
};

/// Creates `dir` and its parents if needed. InputError if it cannot be created or exists but is not
/// a directory.
void ensureDirectory(const std::string& dir);

/// The whole content of a file. InputError if it does not exist or cannot be read.
std::string readWholeFile(const std::string& path);

/// Writes `content` to `path` atomically (through AtomicOFStream).
void writeWholeFile(const std::string& path, const std::string& content);

} // namespace pdpm
