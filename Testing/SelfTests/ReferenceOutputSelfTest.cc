// Self-test (regression guard, after the analytic tests): a short run of a dense frictional gas for
// each of five registered contact laws, compared with small checked-in reference outputs
// (Testing/SelfTests/reference/ReferenceOutput_<law>.csv) at a relative tolerance of 1e-6.
//
// The analytic tests pin each law's equations; this test pins their composition in a many-particle
// run (neighbour list, periodic images, integration, histories, rolling and torsion torques), so
// that an unintended change to any of them shows up as a changed number. The references were made
// by this program (`ReferenceOutputSelfTest --update`) and must only be regenerated for a change that
// is meant to alter results, with the reason in the commit message. The tolerance is far above
// the last-bit differences of compilers and instruction sets over 3000 steps, and far below any
// change in the physics: the scalar pair loop of commit bb6deb0 (built without the SIMD batch and
// with other FP options) reproduces these references to 8.7e-12 at most (sum_abs_ft of luding);
// rounding differences grow by roughly x17 per 1000 steps in this gas (a 1-ulp change estimated
// to reach ~2e-11 in the velocities after 3000 steps), so do not lengthen the run
// much. The two counts (contacts, sliding_contacts) may differ by one (a contact exactly at its
// threshold), everything else is relative.
//
// Exit 0 on success, 1 on a mismatch, 2 if a reference file is missing or malformed.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "Contacts/ContactParameters.h"
#include "Core/DPMBase.h"
#include "IO/AtomicFile.h"
#include "Particles/Insertion.h"

using namespace pdpm;

namespace {

const char* const kLaws[] = {"linear", "linear-frictionless", "linear-rolling", "hertz-mindlin", "luding"};

ContactParameters parametersFor(const std::string& law) {
    ContactParameters p;
    p.k = 1e4;      // linear / Luding unloading stiffness (N/m)
    p.gamma = 0.01; // kg/s
    p.kt = 2.0 / 7.0 * p.k;
    p.gammaT = 0.002;
    p.muS = 0.5;
    p.muD = 0.4;
    p.kr = 0.2 * p.k; p.gammaR = 0.001; p.muR = 0.1;
    p.ko = 0.2 * p.k; p.gammaO = 0.001; p.muO = 0.1;
    p.k1 = 0.5 * p.k;  // Luding: plastic loading, adhesion, plasticity depth
    p.kc = 0.1 * p.k;
    p.phiF = 0.05;
    p.youngEff = 2e7;  // Hertz-Mindlin
    p.shearEff = 8e6;
    p.restitution = 0.8;
    if (law == "hertz-mindlin") p.muD = p.muS;
    return p;
}

/// 300 spheres (radii 0.8-1.2 mm) in a fully periodic box at volume fraction 0.3, random velocities
/// up to 2 m/s, no gravity, no background damping, dt from the law (t_c/50), 3000 steps.
class DenseGas : public DPMBase {
public:
    explicit DenseGas(const std::string& law) : DPMBase("ReferenceOutputSelfTest") {
        parameters().set("vtk", "0");
        parameters().set("ene", "0");
        parameters().set("restart_output", "0");
        setQuiet(true);
        setContactLaw(law);
        addSpecies("grains", 2000, parametersFor(law));
        const std::vector<double> radii = uniformRadii(300, 0.8e-3, 1.2e-3, random());
        double vs = 0;
        for (double a : radii) vs += 4.0 / 3.0 * std::numbers::pi * a * a * a;
        const double L = std::cbrt(vs / 0.3);
        setDomain({0, 0, 0}, {L, L, L}, true, true, true);
        insertRandom(*this, radii, {0, 0, 0}, {L, L, L}, 2.0);
        setTimeStep(suggestedTimeStep());
        setTimeMax(3000 * timeStep());
        setSaveEvery(timeMax());
    }

    /// The quantities compared: energies, contact statistics, and the state of three particles.
    std::vector<std::pair<std::string, double>> summary() {
        refreshContacts();
        std::vector<std::pair<std::string, double>> s;
        s.emplace_back("steps", static_cast<double>(step()));
        s.emplace_back("kinetic_energy", kineticEnergy());
        s.emplace_back("rotational_energy", rotationalEnergy());
        s.emplace_back("elastic_energy", elasticEnergy());
        double fn = 0, ft = 0, sliding = 0, overlap = 0;
        for (const ContactRecord& c : contacts()) {
            fn += c.fn;
            ft += norm(c.ft);
            sliding += c.sliding ? 1 : 0;
            overlap += c.overlap;
        }
        s.emplace_back("contacts", static_cast<double>(contacts().size()));
        s.emplace_back("sum_fn", fn);
        s.emplace_back("sum_abs_ft", ft);
        s.emplace_back("sliding_contacts", sliding);
        s.emplace_back("sum_overlap", overlap);
        for (std::size_t i : {0ul, 150ul, 299ul}) {
            std::string p = "p";
            p += std::to_string(i);
            p += '_';
            s.emplace_back(p + "x", particles().x[i].x);
            s.emplace_back(p + "y", particles().x[i].y);
            s.emplace_back(p + "z", particles().x[i].z);
            s.emplace_back(p + "vx", particles().v[i].x);
            s.emplace_back(p + "wz", particles().w[i].z);
        }
        return s;
    }
};

std::string referencePath(const std::string& law) {
    return std::string(PDPM_SOURCE_DIR) + "/Testing/SelfTests/reference/ReferenceOutput_" + law + ".csv";
}

bool readReference(const std::string& path, std::map<std::string, double>& ref) {
    std::ifstream in(path);
    if (!in) return false;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#' || line == "quantity,value") continue;
        const auto comma = line.find(',');
        if (comma == std::string::npos) return false;
        try {
            ref[line.substr(0, comma)] = std::stod(line.substr(comma + 1));
        } catch (...) {
            return false;
        }
    }
    return !ref.empty();
}

} // namespace

int main(int argc, char** argv) {
    const bool update = argc > 1 && std::string(argv[1]) == "--update";
    if (argc > 1 && !update) {
        std::fprintf(stderr, "ReferenceOutputSelfTest: unknown argument '%s' (only --update)\n", argv[1]);
        return 2;
    }
    bool ok = true;
    for (const char* law : kLaws) {
        DenseGas g(law);
        g.solve();
        const auto s = g.summary();
        const std::string path = referencePath(law);
        if (update) {
            std::ostringstream os;
            os << "# ReferenceOutputSelfTest, law " << law
               << ": 300 spheres, periodic box, volume fraction 0.3, 3000 steps (regression guard)\n"
               << "quantity,value\n";
            char buf[64];
            for (const auto& [name, value] : s) {
                std::snprintf(buf, sizeof buf, "%.17g", value);
                os << name << ',' << buf << '\n';
            }
            writeWholeFile(path, os.str());
            std::printf("%-20s reference written to %s\n", law, path.c_str());
            continue;
        }
        std::map<std::string, double> ref;
        if (!readReference(path, ref)) {
            std::fprintf(stderr, "ReferenceOutputSelfTest: missing or malformed reference file %s\n", path.c_str());
            return 2;
        }
        double worst = 0;
        std::string worstName;
        for (const auto& [name, value] : s) {
            const auto it = ref.find(name);
            if (it == ref.end()) {
                std::printf("%-20s %s: not in the reference\n", law, name.c_str());
                ok = false;
                continue;
            }
            const double scale = std::max(std::fabs(value), std::fabs(it->second));
            double rel = scale > 0 ? std::fabs(value - it->second) / scale : 0.0;
            const bool count = name == "contacts" || name == "sliding_contacts";
            if (count && std::fabs(value - it->second) <= 1.0) rel = 0.0;
            if (!(rel <= 1e-6)) {
                std::printf("%-20s %s = %.17g, reference %.17g (relative difference %.2e > 1e-6)\n", law,
                            name.c_str(), value, it->second, rel);
                ok = false;
            }
            if (rel > worst || std::isnan(rel)) {
                worst = rel;
                worstName = name;
            }
        }
        std::printf("%-20s %zu quantities, %.0f contacts at the end, largest relative difference %.2e (%s)\n", law,
                    s.size(), s[4].second, worst, worstName.c_str());
    }
    if (update) return 0;
    std::printf("%s\n", ok ? "PASS" : "FAIL");
    return ok ? 0 : 1;
}
