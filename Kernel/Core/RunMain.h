// Uniform error handling for the main() of every PowderDPM program:
//
//   int main(int argc, char** argv) {
//       return pdpm::runMain("MyDriver", [&] { ...; return 0; });
//   }
//
// pdpm::InputError -> one line "PROGRAM: error: MESSAGE" on stderr, exit code 2 (kExitBadInput).
// std::bad_alloc -> "PROGRAM: error: out of memory: ...", exit code 2 (the sizes come from the input).
// other std::exception -> one line "PROGRAM: error: MESSAGE" on stderr, exit code 1.
#pragma once
#include <functional>

namespace pdpm {

int runMain(const char* programName, const std::function<int()>& body);

} // namespace pdpm
