// pdpm-tools-example: writes small synthetic runs in the kernel's file formats for the worked
// examples of Documentation/tools-*.md and the self-tests:
//   DIR/column_0000.vtu, DIR/column.pvd, DIR/column.fstat  — a static 4x4x24 simple-cubic column
//     under gravity on a floor (every vertical contact carries the weight above it);
//   DIR/uniaxial.fstat — 6 blocks of 20000 contacts whose orientation distribution develops a
//     sixth-order anisotropy while the box is compressed along z.
#include "Cli.h"
#include "Polar.h"
#include "SnapshotIO.h"
#include "OutputFiles.h"

#include <cmath>
#include <fstream>
#include <iostream>
#include <numbers>
#include <random>

using namespace pdpm;
using namespace pdpm::tools;

int main(int argc, char** argv) {
    return runTool("pdpm-tools-example", [&] {
        Cli cli("pdpm-tools-example", "Writes synthetic example runs (column.*, uniaxial.fstat) into --output.");
        std::string out;
        cli.add("output", &out, ".", "output directory");
        if (!cli.parse(argc, argv, std::cout)) return 0;
        requireNonEmpty("output", out);
        ensureDirectory(out);
        // ---- static column
        const int nxy = 4, nz = 24;
        const double d = 1e-3, rho = 1500, g = 9.81;
        const double m = rho * std::numbers::pi / 6 * d * d * d;
        ParticleSnapshot s;
        ContactSnapshot c;
        s.time = c.time = 0;
        s.step = c.step = 0;
        s.boxLo = c.boxLo = {0, 0, 0};
        s.boxHi = c.boxHi = {nxy * d, nxy * d, 30 * d};
        for (int a = 0; a < nxy; ++a)
            for (int b = 0; b < nxy; ++b)
                for (int k = 0; k < nz; ++k) {
                    const int id = int(s.size());
                    s.x.push_back({(a + 0.5) * d, (b + 0.5) * d, (k + 0.5) * d});
                    s.v.push_back({});
                    s.r.push_back(0.5 * d);
                    s.m.push_back(m);
                    s.coordination.push_back(k == nz - 1 ? 1 : 2);
                    ContactRecord r;
                    r.i = id;
                    r.normal = {0, 0, 1};
                    r.fn = (nz - k) * m * g;
                    if (k == 0) {
                        r.j = -1;
                        r.contactPoint = {s.x.back().x, s.x.back().y, 0};
                        r.branch = s.x.back() - r.contactPoint;
                    } else {
                        r.j = id - 1;
                        r.branch = {0, 0, d};
                        r.contactPoint = s.x.back() - Vec3{0, 0, 0.5 * d};
                    }
                    c.contacts.push_back(r);
                }
        writeVtu(joinPath(out, "column_0000.vtu"), s);
        writeFstat(joinPath(out, "column.fstat"), {c});
        writeFileAtomically(joinPath(out, "column.pvd"), [](std::ostream& os) {
            os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n"
                  "    <DataSet timestep=\"0\" part=\"0\" file=\"column_0000.vtu\"/>\n  </Collection>\n</VTKFile>\n";
        });
        // ---- uniaxial compression: contacts only
        std::mt19937_64 rng(2024);
        std::uniform_real_distribution<double> U(0, 1);
        std::exponential_distribution<double> E(1.0);
        std::vector<ContactSnapshot> blocks;
        for (int t = 0; t < 6; ++t) {
            const double tau = t / 5.0;
            const std::array<double, 3> eps{0.12 * tau, -0.04 * tau, 0.01 * tau};
            const double bound = 1 + 2 * eps[0] + 8 * std::abs(eps[1]) + 16 * eps[2];
            ContactSnapshot b;
            b.time = tau;
            b.step = 1000 * t;
            b.boxLo = {0, 0, 0};
            b.boxHi = {0.01, 0.01, 0.01 * std::exp(-0.05 * tau)};
            b.periodic[0] = b.periodic[1] = b.periodic[2] = true;
            while (b.contacts.size() < 20000) {
                const double cz = 2 * U(rng) - 1;
                const double p = 1 + eps[0] * harmonicY(2, cz) + eps[1] * harmonicY(4, cz) + eps[2] * harmonicY(6, cz);
                if (U(rng) * bound > p) continue;
                const double phi = 2 * std::numbers::pi * U(rng), sn = std::sqrt(1 - cz * cz);
                ContactRecord r;
                r.i = int(b.contacts.size());
                r.j = r.i + 1;
                r.normal = {sn * std::cos(phi), sn * std::sin(phi), cz};
                r.fn = E(rng) * (1 + tau * (2 * cz * cz));  // stronger forces along the compression axis
                r.ft = 0.2 * r.fn * U(rng) * Vec3{-std::sin(phi), std::cos(phi), 0};
                r.sliding = false;
                r.branch = 1e-3 * r.normal;
                b.contacts.push_back(r);
            }
            blocks.push_back(std::move(b));
        }
        writeFstat(joinPath(out, "uniaxial.fstat"), blocks);
        std::cout << "pdpm-tools-example: wrote column_0000.vtu, column.pvd, column.fstat, uniaxial.fstat to " << out << "\n";
        return 0;
    });
}
