#include "Shell.h"

#include <sstream>

namespace pdpm::tools {

std::string shellQuote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

std::string shellWords(const std::string& s) {
    std::istringstream is(s);
    std::string word, out;
    while (is >> word) {
        out += ' ';
        out += shellQuote(word);
    }
    return out;
}

} // namespace pdpm::tools
