// pdpm-cg: coarse-grained continuum fields from PowderDPM output files.
// See Documentation/tools-coarse-graining.md.
#include "Cli.h"
#include "CoarseGraining.h"
#include "Core/Error.h"
#include "OutputFiles.h"
#include "SnapshotIO.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <omp.h>

using namespace pdpm;
using namespace pdpm::tools;

namespace {

int run(int argc, char** argv) {
    Cli cli("pdpm-cg",
            "Coarse-grains particle (.vtu/.pvd) and contact (.fstat) files onto a 1D/2D/3D Cartesian or a\n"
            "cylindrical (r,z) grid: density, momentum, velocity, kinetic and contact stress, fabric,\n"
            "coordination and the height profile (Eq. 5.11). Writes NAME.csv and/or NAME.vti to --output.");
    std::vector<std::string> inputs;
    std::string output, name, kernel, walls, format, axis, region, domain, centre;
    double width, rmax, tmin, tmax, hIni;
    int nx, ny, nz, nr, window, threads;
    bool cylindrical;
    cli.addList("input", &inputs, "input files: RUN_NNNN.vtu, RUN.pvd and/or RUN.fstat");
    cli.add("output", &output, ".", "output directory (created if needed)");
    cli.add("name", &name, "cg", "base name of the output files");
    cli.add("kernel", &kernel, "gaussian", "CG kernel (Gaussian cut at 3w, or Lucy of equal std. dev.)", {"gaussian", "lucy"});
    cli.add("width", &width, -1, "m", "kernel width w (default: mean particle diameter)", 0, Cli::inf, true);
    cli.add("nx", &nx, 0, "grid cells along x (0: average over x)", 0, 100000);
    cli.add("ny", &ny, 0, "grid cells along y (0: average over y)", 0, 100000);
    cli.add("nz", &nz, 0, "grid cells along z (0: average over z); axial cells if --cylindrical", 0, 100000);
    cli.add("cylindrical", &cylindrical, false, "cylindrical (r, axis) grid averaged over the azimuth");
    cli.add("axis", &axis, "z", "cylinder axis", {"x", "y", "z"});
    cli.add("nr", &nr, 20, "radial cells (cylindrical)", 1, 100000);
    cli.add("rmax", &rmax, 0, "m", "radial extent (0: half the smaller perpendicular box extent)", 0, Cli::inf);
    cli.add("centre", &centre, "", "cylinder axis position 'a,b' in the two other coordinates, in x, y, z order (axis x: y,z; y: x,z; z: x,y; default: box centre)");
    cli.add("region", &region, "", "grid extent 'xlo,xhi,ylo,yhi,zlo,zhi' (default: the box)");
    cli.add("domain", &domain, "", "domain (walls) 'xlo,xhi,ylo,yhi,zlo,zhi' (default: the box of the file)");
    cli.add("walls", &walls, "renormalize", "kernel at non-periodic boundaries: clip and renormalise, or clip only", {"renormalize", "cut"});
    cli.add("window", &window, 0, "snapshots averaged per output (0: all in one)", 0, 1000000000);
    cli.add("tmin", &tmin, -Cli::inf, "s", "ignore snapshots before this time");
    cli.add("tmax", &tmax, Cli::inf, "s", "ignore snapshots after this time");
    cli.add("h_ini", &hIni, 1, "m", "initial height h_ini of Eq. 5.11 (1D grids; 1: relative)", 0, Cli::inf, true);
    cli.add("format", &format, "both", "output format", {"csv", "vti", "both"});
    cli.add("threads", &threads, 0, "OpenMP threads (0: default)", 0, 4096);
    if (!cli.parse(argc, argv, std::cout)) return 0;
    if (inputs.empty()) inputError("--input: no input files given");
    requireNonEmpty("output", output);
    requireFileName("name", name);
    if (threads > 0) omp_set_num_threads(threads);

    CgConfig cfg;
    cfg.kernel = kernel == "lucy" ? CgKernel::Lucy : CgKernel::Gaussian;
    cfg.walls = walls == "cut" ? WallTreatment::Cut : WallTreatment::Renormalize;
    cfg.cylindrical = cylindrical;
    cfg.axis = axis[0] - 'x';
    cfg.n[0] = cylindrical ? nr : nx;
    cfg.n[1] = ny;
    cfg.n[2] = nz;
    cfg.rmax = rmax;
    auto box = [](const std::string& flag, const std::string& text, Vec3& lo, Vec3& hi) {
        const auto v = parseNumberList(flag, text);
        if (v.size() != 6) inputError(flag + ": expected 6 numbers 'xlo,xhi,ylo,yhi,zlo,zhi'");
        for (int a = 0; a < 3; ++a) {
            lo[a] = v[2 * a];
            hi[a] = v[2 * a + 1];
            if (!(hi[a] > lo[a])) inputError(flag + ": empty extent along " + std::string(1, "xyz"[a]));
        }
    };
    if (!region.empty()) { box("--region", region, cfg.regionLo, cfg.regionHi); cfg.regionSet = true; }
    if (!domain.empty()) { box("--domain", domain, cfg.domainLo, cfg.domainHi); cfg.domainSet = true; }
    if (!centre.empty()) {
        const auto v = parseNumberList("--centre", centre);
        if (v.size() != 2) inputError("--centre: expected 2 numbers 'a,b'");
        cfg.centre[0] = v[0];
        cfg.centre[1] = v[1];
        cfg.centreSet = true;
    }
    if (!cylindrical && nx == 0 && ny == 0 && nz == 0)
        inputError("empty grid: give at least one of --nx, --ny, --nz > 0");
    if (cgCells(cfg) > double(kCgMaxCells))
        inputError(std::string(cylindrical ? "--nr × --nz" : "--nx × --ny × --nz") + " = " + fmt(cgCells(cfg)) +
                   " cells: more than the limit of " + fmt(double(kCgMaxCells)) + " (about 1.5 kB of memory per cell)");

    std::vector<Frame> frames = loadFrames(inputs);
    std::vector<Frame> used;
    int contactOnly = 0;  // contact blocks without a particle snapshot (a .vtu with a whole run's .fstat)
    for (Frame& f : frames)
        if (f.time() >= tmin && f.time() <= tmax) {
            if (f.hasParticles) used.push_back(std::move(f));
            else ++contactOnly;
        }
    if (used.empty() && contactOnly > 0)
        inputError("no particle file (.vtu) for the contact block(s) between --tmin and --tmax (pdpm-cg needs "
                   "particles; pass the .vtu/.pvd files too)");
    if (used.empty()) inputError("no snapshots between --tmin and --tmax");
    // every contact must refer to a particle of its snapshot: checked for all snapshots before any
    // output is written, so that a bad block late in the list leaves no partial set of files
    for (const Frame& f : used)
        if (f.hasContacts)
            for (const ContactRecord& c : f.contacts.contacts)
                if (c.i < 0 || std::size_t(c.i) >= f.particles.size() || (c.j >= 0 && std::size_t(c.j) >= f.particles.size()))
                    inputError("contact (" + std::to_string(c.i) + ", " + std::to_string(c.j) + ") at time " +
                               fmt(f.time()) + " refers to a particle beyond N = " + std::to_string(f.particles.size()) +
                               " (contacts and particles from different runs?)");
    if (contactOnly > 0)
        std::cout << "pdpm-cg: " << contactOnly << " contact block(s) without a particle snapshot ignored\n";
    if (width <= 0) {
        double sum = 0;
        for (double r : used[0].particles.r) sum += 2 * r;
        if (used[0].particles.r.empty() || !(sum > 0)) inputError("--width: cannot default to the mean diameter (no particles)");
        width = sum / double(used[0].particles.r.size());
    }
    cfg.width = width;
    ensureDirectory(output);

    const int per = window > 0 ? window : int(used.size());
    const int nOut = (int(used.size()) + per - 1) / per;
    const bool oneD = !cylindrical && ((nx > 0) + (ny > 0) + (nz > 0)) == 1;
    CgResult initial;
    for (int o = 0; o < nOut; ++o) {
        CoarseGrainer cg(cfg);
        for (int k = o * per; k < std::min(int(used.size()), (o + 1) * per); ++k)
            cg.add(used[k].particles, used[k].hasContacts ? &used[k].contacts : nullptr);
        const CgResult r = cg.result();
        if (o == 0) initial = r;
        char suffix[32] = "";
        if (nOut > 1) std::snprintf(suffix, sizeof suffix, "_%04d", o);
        const std::string base = joinPath(output, name + suffix);
        if (format != "vti") writeCgCsv(base + ".csv", r, oneD ? heightProfile(r, initial, hIni) : std::vector<double>{});
        if (format != "csv") writeCgVti(base + ".vti", r);
        std::cout << "pdpm-cg: t = " << fmt(r.time) << " (" << r.snapshots << " snapshot(s)";
        if (r.contactSnapshots > 0 && r.contactSnapshots < r.snapshots)
            std::cout << ", " << r.contactSnapshots << " with contacts: contact stress and fabric average over these";
        std::cout << ") -> " << base
                  << (format == "both" ? ".{csv,vti}" : (format == "csv" ? ".csv" : ".vti")) << "\n";
    }
    return 0;
}

} // namespace

int main(int argc, char** argv) { return runTool("pdpm-cg", [&] { return run(argc, argv); }); }
