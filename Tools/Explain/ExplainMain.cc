// pdpm-explain: see Documentation/tools-explain.md.
#include <string>
#include <vector>

#include "Explain.h"

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    return pdpm::explain::runExplainCommand(args);
}
