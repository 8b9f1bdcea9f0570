// Building /bin/sh command lines for the tools that run another program (a driver, gnuplot) through
// std::system: every word is quoted, so that no text a user gives (a path, extra arguments) is read
// as shell syntax.
#pragma once
#include <string>

namespace pdpm::tools {

/// `s` as one word for /bin/sh: in single quotes, an embedded single quote closed, escaped and reopened.
std::string shellQuote(const std::string& s);

/// Extra arguments given as one string (e.g. "--width 4 --fill_height 5"): split at white space and
/// each word quoted, so ';', '|', '&', '$', '`', quotes and redirections reach the program as text
/// (which refuses what it does not know) instead of the shell. Returns the words, each preceded by a
/// space ("" for none). No quoting of its own: a word cannot contain white space.
std::string shellWords(const std::string& s);

} // namespace pdpm::tools
