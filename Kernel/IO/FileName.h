// The one rule for a run or output name given on a command line (--name of the drivers and tools).
//
// The name becomes part of file names (DIR/NAME.macro.csv, ...), and the tools also write it into
// quoted strings of the gnuplot scripts next to their results, so it must stay inside --output and
// inside a quoted string: no '/', no quotes or back-quotes, no control characters, and not "." or
// "..". Everything else (spaces, non-ASCII bytes) is allowed.
#pragma once
#include <string>

namespace pdpm {

inline bool isPlainFileName(const std::string& name) {
    if (name.empty() || name == "." || name == "..") return false;
    for (unsigned char c : name)
        if (c < 0x20 || c == 0x7f || c == '/' || c == '\'' || c == '"' || c == '`') return false;
    return true;
}

/// The name as it may be quoted in a one-line message: control bytes as \xNN.
inline std::string printableFileName(const std::string& name) {
    static const char* hex = "0123456789abcdef";
    std::string out;
    for (unsigned char c : name) {
        if (c < 0x20 || c == 0x7f) { out += "\\x"; out += hex[c >> 4]; out += hex[c & 15]; }
        else out += static_cast<char>(c);
    }
    return out;
}

/// The rule in words, for error messages.
inline const char* plainFileNameRule() {
    return "a plain file name (not empty; no '/', quotes or control characters; not '.' or '..')";
}

} // namespace pdpm
