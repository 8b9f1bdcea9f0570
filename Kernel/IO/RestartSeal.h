#pragma once
// The checksum line that closes a restart file (format in Documentation/restart.md): "end HEX",
// HEX the 64-bit FNV-1a hash of every byte before it. DPMBase writes and checks it; the bad-input
// probes use it to seal a deliberately edited file, so that the edit, not the checksum, is refused.
#include <string>

namespace pdpm {

/// The line "end %016x\n" for `body` (the file's text up to and including its last newline).
std::string restartChecksumLine(const std::string& body);

/// `text` (a restart file) with its checksum line, valid or not, replaced by the right one for the
/// rest; empty if `text` has no "\nend " line to replace.
std::string resealRestartText(const std::string& text);

/// `text` (a restart file) with the value of the first line "KEY VALUE" replaced by `value` and the
/// checksum resealed; empty if there is no such line (or no checksum line).
std::string withRestartValue(const std::string& text, const std::string& key, const std::string& value);
/// The value of the first line "KEY VALUE" of `text` (a restart file); empty if there is no such line.
std::string restartValue(const std::string& text, const std::string& key);

} // namespace pdpm
