#include "Core/RunMain.h"

#include "Core/Error.h"

#include <cstdio>
#include <exception>
#include <new>
#include <stdexcept>
#include <iostream>
#include <string>

namespace pdpm {

namespace {

/// The message on a single line: newlines become "; ", trailing whitespace is dropped.
std::string oneLine(const char* what) {
    std::string s = what ? what : "";
    std::string out;
    out.reserve(s.size());
    for (char c : s) {
        if (c == '\n' || c == '\r') {
            if (!out.empty() && out.back() != ' ') out += "; ";
        } else {
            out += c;
        }
    }
    while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
    return out;
}

void report(const char* programName, const char* what) {
    std::cout.flush();
    std::cerr << (programName ? programName : "program") << ": error: " << oneLine(what) << std::endl;
}

} // namespace

int runMain(const char* programName, const std::function<int()>& body) {
    try {
        return body();
    } catch (const InputError& e) {
        report(programName, e.what());
        return kExitBadInput;
    } catch (const std::bad_alloc&) {
        // sizes come from the input (particle counts, grids, file headers): too large for this machine
        report(programName, "out of memory: the input asks for more memory than this machine has");
        return kExitBadInput;
    } catch (const std::length_error&) {
        // a size computed from the input beyond what any container can hold
        report(programName, "out of memory: the input asks for a container larger than any this machine can hold");
        return kExitBadInput;
    } catch (const std::exception& e) {
        report(programName, e.what());
        return 1;
    }
}

} // namespace pdpm
