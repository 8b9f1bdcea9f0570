// Error types of PowderDPM.
//
// InputError: anything the user can fix (bad flag, out-of-range parameter, malformed or foreign
// file, NaN during a run). Programs catch it in pdpm::runMain (Core/RunMain.h), print ONE line
// "NAME: error: MESSAGE" on stderr and exit with code 2.
#pragma once
#include <stdexcept>
#include <string>

namespace pdpm {

struct InputError : std::runtime_error {
    explicit InputError(const std::string& what) : std::runtime_error(what) {}
};

/// Exit code of every PowderDPM program for bad input.
inline constexpr int kExitBadInput = 2;

[[noreturn]] inline void inputError(const std::string& message) { throw InputError(message); }

} // namespace pdpm
