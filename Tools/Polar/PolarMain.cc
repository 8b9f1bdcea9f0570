// pdpm-polar: directional statistics of contacts and forces from RUN.fstat.
// See Documentation/tools-polar.md.
#include "Cli.h"
#include "Layers.h"
#include "Core/Error.h"
#include "OutputFiles.h"
#include "Polar.h"
#include "Shell.h"
#include "SnapshotIO.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

using namespace pdpm;
using namespace pdpm::tools;

namespace {

void writePlots(const std::string& dir, const std::string& name, const std::string& term, const std::string& xcol, bool layers) {
    const std::string ext = term == "svg" ? "svg" : "png";
    const std::string terminal = term == "svg" ? "svg size 640,480" : "pngcairo size 640,480 font ',10'";
    const std::string gp = joinPath(dir, name + "_plots.gp");
    writeFileAtomically(gp, [&](std::ostream& os) {
        os << "# gnuplot script written by pdpm-polar; run in the output directory: gnuplot " << name << "_plots.gp\n"
           << "set datafile separator ','\nset terminal " << terminal << "\n"
           << "bins = '" << name << "_bins.csv'\nseries = '" << name << "_series.csv'\npdf = '" << name << "_pdf.csv'\n"
           << "set output '" << name << "_P.' . '" << ext << "'\n"
           << "set polar\nset angles radians\nset size ratio -1\nunset border\nunset xtics\nunset ytics\nset grid polar\n"
           << "set title 'contact probability density P({/Symbol q}), axis at {/Symbol q} = 0 (right)'\n"
           << "plot bins using (strcol(1) eq 'b' ? $2 : NaN):8 with points pt 7 ps 0.6 title 'b (constant width)', \\\n"
           << "     bins using (strcol(1) eq 'b' ? 2*pi-$2 : NaN):8 with points pt 7 ps 0.6 lc 1 notitle, \\\n"
           << "     bins using (strcol(1) eq 'h' ? $2 : NaN):8 with points pt 6 ps 0.8 title 'h (constant height)', \\\n"
           << "     bins using (strcol(1) eq 'h' ? 2*pi-$2 : NaN):8 with points pt 6 ps 0.8 lc 2 notitle, \\\n"
           << "     bins using (strcol(1) eq 'b' ? $2 : NaN):12 with lines lw 2 lc 3 title 'P_6 fit (M1)', \\\n"
           << "     bins using (strcol(1) eq 'b' ? 2*pi-$2 : NaN):12 with lines lw 2 lc 3 notitle\n"
           << "set output '" << name << "_fn.' . '" << ext << "'\n"
           << "set title 'mean normal force f_n({/Symbol q})'\n"
           << "plot bins using (strcol(1) eq 'b' ? $2 : NaN):9 with linespoints pt 7 ps 0.6 title 'f_n', \\\n"
           << "     bins using (strcol(1) eq 'b' ? 2*pi-$2 : NaN):9 with linespoints pt 7 ps 0.6 lc 1 notitle\n"
           << "unset polar\nset border\nset xtics\nset ytics\nunset grid\nset size noratio\nset grid\n"
           << "set output '" << name << "_eps.' . '" << ext << "'\n"
           << "set title 'anisotropy descriptors (M1 solid, M2 dashed, M3 dotted)'\n"
           << "set xlabel '" << xcol << "'\nset ylabel '{/Symbol e}_l'\nset key outside right\n"
           << "plot series using '" << xcol << "':'M1_eps2' w lp lc 1 pt 7 ps 0.5 t '{/Symbol e}_2', \\\n"
           << "     series using '" << xcol << "':'M1_eps4' w lp lc 2 pt 7 ps 0.5 t '{/Symbol e}_4', \\\n"
           << "     series using '" << xcol << "':'M1_eps6' w lp lc 3 pt 7 ps 0.5 t '{/Symbol e}_6', \\\n"
           << "     series using '" << xcol << "':'M2_eps2' w l dt 2 lc 1 notitle, series using '" << xcol << "':'M2_eps4' w l dt 2 lc 2 notitle, \\\n"
           << "     series using '" << xcol << "':'M2_eps6' w l dt 2 lc 3 notitle, series using '" << xcol << "':'M3_eps2' w l dt 3 lc 1 notitle, \\\n"
           << "     series using '" << xcol << "':'M3_eps4' w l dt 3 lc 2 notitle, series using '" << xcol << "':'M3_eps6' w l dt 3 lc 3 notitle, \\\n"
           << "     series using '" << xcol << "':'eps2_fabric' w l lw 2 lc 0 t '15/4 (F_{aa}-1/3)'\n"
           << "set output '" << name << "_pdf.' . '" << ext << "'\n"
           << "set title 'normal force pdf in cones'\nset xlabel 'f/<f_{all}>'\nset ylabel 'P'\nset logscale y\n"
           << "plot for [c in 'P_x P_y P_z P_all'] pdf using 'fstar':c w lp ps 0.5 t c\n";
        if (layers)
            os << "unset logscale y\nset key inside top right\nlayers = '" << name << "_layers.csv'\nstats layers using 1 nooutput\nblast = STATS_max\n"
               << "set output '" << name << "_layers.' . '" << ext << "'\n"
               << "set title 'by distance from the nearest face along the axis (last analysed block)'\n"
               << "set xlabel 'distance from the nearest face / box length'\nset ylabel 'friction mobilisation, s_{dev}'\n"
               << "set y2label 'sliding fraction'\nset y2tics\nset yrange [0:*]\nset y2range [0:*]\n"
               << "plot layers using ($1 == blast ? ($5+$6)/2 : NaN):'psi' w lp pt 7 t '|f_t|/({/Symbol m} f_n)', \\\n"
               << "     layers using ($1 == blast ? ($5+$6)/2 : NaN):'s_dev' w lp pt 5 t 's_{dev} of the layer', \\\n"
               << "     layers using ($1 == blast ? ($5+$6)/2 : NaN):'sliding_fraction' axes x1y2 w lp pt 6 dt 2 t 'sliding fraction'\n";
    });
    const std::string cmd = "cd " + tools::shellQuote(dir.empty() ? std::string(".") : dir) + " && gnuplot " + tools::shellQuote(name + "_plots.gp") +
                            " 2>/dev/null";
    if (std::system(cmd.c_str()) != 0)
        std::cerr << "pdpm-polar: warning: gnuplot failed or is not installed; plots not made (script: " << gp << ")\n";
}

int run(int argc, char** argv) {
    Cli cli("pdpm-polar",
            "Directional analysis of contacts in RUN.fstat relative to an axis: P(theta) by the constant-bin-width\n"
            "and constant-height methods, f_n, f_t, psi_t(theta), sixth-order harmonic fits (M1-M3) with errors,\n"
            "the normal-force pdf in cones around x, y, z, a time series over all blocks, and gnuplot plots.");
    std::vector<std::string> inputs;
    std::string output, name, axis, normalisation, plot, xcol;
    int binsTheta, binsHeight, pdfBins;
    double mu, chi, pdfMax;
    bool walls, allBins;
    int layers;
    cli.addList("input", &inputs, "contact files RUN.fstat (all blocks are analysed)");
    cli.add("output", &output, ".", "output directory (created if needed)");
    cli.add("name", &name, "polar", "base name of the output files");
    cli.add("axis", &axis, "z", "reference axis: x, y, z or 'ax,ay,az'");
    cli.add("bins_theta", &binsTheta, 18, "constant-width bins on [0, pi/2]", 5, 100000);
    cli.add("bins_height", &binsHeight, 10, "constant-height bins on |cos theta| in [0, 1]", 5, 100000);
    cli.add("normalisation", &normalisation, "sin", "P(theta) = phi/(2 dtheta sin theta) or phi/(2 (cos_i - cos_f)) (2: the mirror bin)", {"sin", "cos"});
    cli.add("mu", &mu, 0.5, "", "friction coefficient for psi_t = f_t/(mu f_n)", 0, Cli::inf, true);
    cli.add("walls", &walls, false, "include wall contacts");
    cli.add("chi", &chi, 0.8, "", "cone cut-off |n.e| > chi for the force pdf", 0, 1, false, true);
    cli.add("pdf_bins", &pdfBins, 50, "bins of the force pdf", 1, 100000);
    cli.add("pdf_max", &pdfMax, 5, "", "largest f/<f_all> of the force pdf", 0, Cli::inf, true);
    cli.add("all_bins", &allBins, false, "write NAME_bins_NNNN.csv for every block (default: last block only)");
    cli.add("layers", &layers, 0, "layers by distance from the nearest face of the box along the axis (x, y or z): NAME_layers.csv (0: none)", 0, 100000);
    cli.add("plot", &plot, "png", "plots made with gnuplot", {"png", "svg", "none"});
    cli.add("x_column", &xcol, "strain_dev", "x axis of the epsilon plot", {"strain_dev", "strain_axial", "time"});
    if (!cli.parse(argc, argv, std::cout)) return 0;
    if (inputs.empty()) inputError("--input: no input files given");
    requireNonEmpty("output", output);
    requireFileName("name", name);

    PolarConfig cfg;
    if (axis == "x" || axis == "y" || axis == "z") {
        cfg.axis = {};
        cfg.axis[axis[0] - 'x'] = 1;
    } else {
        const auto v = parseNumberList("--axis", axis);
        if (v.size() != 3) inputError("--axis: expected x, y, z or three numbers 'ax,ay,az'");
        cfg.axis = {v[0], v[1], v[2]};
        const double length = norm(cfg.axis);  // the numbers are finite; their length may still overflow
        if (!(length > 0 && std::isfinite(length))) inputError("--axis: the axis must be non-zero and its length finite");
    }
    cfg.binsTheta = binsTheta;
    cfg.binsHeight = binsHeight;
    cfg.cosNormalisation = normalisation == "cos";
    cfg.mu = mu;
    cfg.includeWalls = walls;
    cfg.chi = chi;
    cfg.pdfBins = pdfBins;
    cfg.pdfMax = pdfMax;

    int layerAxis = -1;
    if (layers > 0) {
        if (axis != "x" && axis != "y" && axis != "z") inputError("--layers: needs --axis x, y or z (the layers are slabs of the box)");
        layerAxis = axis[0] - 'x';
    }

    std::vector<ContactSnapshot> blocks;
    for (const std::string& p : inputs) {
        for (auto& b : readFstat(p)) blocks.push_back(std::move(b));
    }
    if (layerAxis >= 0)  // refused before anything is written
        for (const auto& b : blocks) checkLayerBox(b);
    ensureDirectory(output);
    const Vec3 L0 = blocks[0].boxHi - blocks[0].boxLo;
    const Vec3 e = cfg.axis / norm(cfg.axis);
    std::vector<std::string> rows, layerRows;
    std::vector<LayerStats> lastLayers;
    PolarResult last;
    std::size_t analysed = 0;
    std::vector<std::string> notes;  // printed when the run succeeds: an error must be the only line
    for (std::size_t k = 0; k < blocks.size(); ++k) {
        // Snapshots without contacts (a packing before it touches, say) are skipped, not fatal.
        bool any = false;
        for (const auto& c : blocks[k].contacts) any = any || cfg.includeWalls || !c.isWallContact();
        if (!any) {
            notes.push_back("pdpm-polar: note: block at t = " + fmt(blocks[k].time) + " has no contacts; skipped");
            continue;
        }
        ++analysed;
        const PolarResult r = analysePolar(blocks[k], cfg);
        const Vec3 L = blocks[k].boxHi - blocks[k].boxLo;
        double ev[3];
        for (int a = 0; a < 3; ++a) ev[a] = (L[a] > 0 && L0[a] > 0) ? std::log(L[a] / L0[a]) : 0.0;
        const double axial = -(e.x * e.x * ev[0] + e.y * e.y * ev[1] + e.z * e.z * ev[2]);  // compression positive
        const double dev = std::sqrt((std::pow(ev[0] - ev[1], 2) + std::pow(ev[1] - ev[2], 2) + std::pow(ev[2] - ev[0], 2)) / 2);
        rows.push_back(polarSeriesRow(r, axial, dev));
        if (layerAxis >= 0) {
            lastLayers = analyseLayers(blocks[k], layerAxis, layers, mu, walls);
            for (std::size_t q = 0; q < lastLayers.size(); ++q)
                layerRows.push_back(layersRow(static_cast<int>(analysed - 1), blocks[k].time, axial, static_cast<int>(q), lastLayers[q]));
        }
        if (allBins) {
            char buf[32];
            std::snprintf(buf, sizeof buf, "_bins_%04zu.csv", k);
            writePolarBinsCsv(joinPath(output, name + buf), r);
        }
        last = r;
    }
    if (analysed == 0) inputError("no contacts in any block of the input");
    writeFileAtomically(joinPath(output, name + "_series.csv"), [&](std::ostream& os) {
        os << polarSeriesHeader() << "\n";
        for (const auto& row : rows) os << row << "\n";
    });
    if (layerAxis >= 0)
        writeFileAtomically(joinPath(output, name + "_layers.csv"), [&](std::ostream& os) {
            os << layersHeader() << "\n";
            for (const auto& row : layerRows) os << row << "\n";
        });
    writePolarBinsCsv(joinPath(output, name + "_bins.csv"), last);
    writePolarPdfCsv(joinPath(output, name + "_pdf.csv"), last);
    std::cout << "pdpm-polar: " << blocks.size() << " block(s); last t = " << fmt(last.time) << ", " << last.contacts
              << " contacts; eps2,4,6 (M1) = " << fmt(last.m1.eps[0]) << ", " << fmt(last.m1.eps[1]) << ", "
              << fmt(last.m1.eps[2]) << "\n";
    if (layerAxis >= 0) {
        std::cout << "pdpm-polar: last block by distance from the nearest " << axis << " face (layer: mobilisation, s_dev):";
        for (const LayerStats& l : lastLayers) std::cout << "  " << fmt(l.lo) << "-" << fmt(l.hi) << ": " << fmt(l.psi) << ", " << fmt(l.sDev);
        std::cout << "\n";
    }
    for (const std::string& n : notes) std::cerr << n << "\n";
    if (plot != "none") writePlots(output, name, plot, xcol, layerAxis >= 0);
    return 0;
}

} // namespace

int main(int argc, char** argv) { return runTool("pdpm-polar", [&] { return run(argc, argv); }); }
