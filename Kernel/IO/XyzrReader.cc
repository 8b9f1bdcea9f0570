#include "IO/XyzrReader.h"

#include <fstream>
#include <sstream>

#include "Core/Error.h"
#include "IO/NumberFormat.h"

namespace pdpm {

XyzrFile readXyzr(const std::string& path) {
    std::ifstream in(path);
    if (!in) inputError("cannot open start file " + path);
    XyzrFile f;
    std::string line;
    long lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        if (line.empty()) continue;
        std::istringstream ls(line);
        if (line[0] == '#') {
            std::string hash, key;
            ls >> hash >> key;
            if (key == "box") {
                double b[6];
                for (double& v : b) v = readDouble(ls);
                if (!ls || !(b[1] > b[0] && b[3] > b[2] && b[5] > b[4]))
                    inputError(path + ":" + std::to_string(lineNo) + ": malformed box line");
                f.lo = {b[0], b[2], b[4]};
                f.hi = {b[1], b[3], b[5]};
                f.hasBox = true;
            } else if (key == "case") {
                std::string word;
                while (ls >> word)
                    if (word == "density") f.density = readDouble(ls);
            }
            continue;
        }
        long id = 0;
        ls >> id;
        const Vec3 x = readVec3(ls);
        const double r = readDouble(ls);
        std::string extra;
        if (!ls || (ls >> extra) || !isFinite(x) || !(r > 0))
            inputError(path + ":" + std::to_string(lineNo) + ": expected 'id x y z r' with r > 0");
        f.x.push_back(x);
        f.r.push_back(r);
    }
    if (f.x.empty()) inputError("start file " + path + " has no particles");
    // centres inside the declared box: a start file's particles are wrapped into it (periodic decks)
    // or held in it by walls; one far outside is a corrupt file, not a configuration
    if (f.hasBox)
        for (std::size_t i = 0; i < f.x.size(); ++i)
            for (int a = 0; a < 3; ++a)
                if (!(f.x[i][a] >= f.lo[a] && f.x[i][a] <= f.hi[a]))
                    inputError(path + ": particle " + std::to_string(i) + " (centre " + fmt(f.x[i]) +
                               ") lies outside the box of the '# box' line");
    return f;
}

} // namespace pdpm
