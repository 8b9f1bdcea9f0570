// pdpm-fit: fits of thesis chapter 2 on RUN.macro.csv files (Documentation/tools-fitting.md).
//
//   pdpm-fit cstar|rattlers|pressure|sdev|fdev FILE [--branch B] [--vc X] [--c0 C0]
//   pdpm-fit table FILE... [--branch B]                 Table 2.2-style table, one row per file
//   pdpm-fit model --uni FILE [D2FILE...] [--table T23.csv] [--vc X] [--out PRED.csv]
//                                                       Sec. 2.7: calibrate on D2/D3 runs (and/or read Table 2.3
//                                                       coefficients), predict the UNI loading branch
//   pdpm-fit plot --out DIR FILE...                     PNG figures through gnuplot (test rows, tau >= 0)
//   pdpm-fit steady FILE... [--eps_min E] [--c1 X] [--alpha Y]
//                                                       steady state of deviatoric runs (rows with eps_dev >= E):
//                                                       one row per run, and Eq. 2.11 through the runs' mean C*
// B: auto (default: unloading if the run has it, else the whole test), loading, unloading, test.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "Core/Error.h"
#include "Core/Parameters.h"
#include "Core/RunMain.h"
#include "Fitting.h"
#include "IO/AtomicFile.h"
#include "IO/Csv.h"
#include "Shell.h"

using namespace pdpm;

namespace {
struct Args {
    std::string command, branch = "auto", out = ".", uni, table;
    bool outGiven = false;
    double vc = 0.6653, c0 = 6, epsMin = 0.08, c1 = 0, alpha = 0;
    bool vcGiven = false;
    std::vector<std::string> files;
};

Args parse(int argc, char** argv) {
    Args a;
    if (argc < 2) inputError("usage: pdpm-fit cstar|rattlers|pressure|sdev|fdev|table|model|plot|steady FILE... (see --help)");
    a.command = argv[1];
    for (int i = 2; i < argc; ++i) {
        const std::string s = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) inputError(s + ": missing value");
            return argv[++i];
        };
        auto number = [&](double& x) {
            const std::string v = value();
            if (!parseStrictDouble(v, x)) inputError(s + ": '" + v + "' is not a number");
        };
        if (s == "--branch") {
            a.branch = value();
            if (a.branch != "auto" && a.branch != "loading" && a.branch != "unloading" && a.branch != "test")
                inputError("--branch: '" + a.branch + "' is not one of auto, loading, unloading, test");
        } else if (s == "--vc") {
            number(a.vc);
            a.vcGiven = true;
            if (!(a.vc > 0 && a.vc < 1)) inputError("--vc: must be in (0, 1)");
        } else if (s == "--c0") number(a.c0);
        else if (s == "--eps_min") number(a.epsMin);
        else if (s == "--c1") {
            number(a.c1);
            if (!(a.c1 > 0)) inputError("--c1: must be > 0");
        } else if (s == "--alpha") {
            number(a.alpha);
            if (!(a.alpha > 0)) inputError("--alpha: must be > 0");
        }
        else if (s == "--out") {
            a.out = value();
            a.outGiven = true;
        } else if (s == "--uni") a.uni = value();
        else if (s == "--table") a.table = value();
        else if (s.rfind("--", 0) == 0) inputError("unknown option " + s);
        else a.files.push_back(s);
    }
    if (a.command == "model" && a.files.empty() && a.table.empty())
        inputError("model: no D2/D3 run file and no --table: nothing to calibrate the prediction on");
    if (a.files.empty() && a.command != "model") inputError(a.command + ": no input file");
    return a;
}

BranchSelect branchOf(const std::string& b) {
    if (b == "loading") return BranchSelect::Loading;
    if (b == "unloading") return BranchSelect::Unloading;
    if (b == "test") return BranchSelect::Test;
    return BranchSelect::Auto;
}

void print(const std::string& title, const FitResult& r) {
    std::printf("%s  (%d points, rms %.4g%s%s)\n", title.c_str(), r.points, r.rms, r.converged ? "" : ", NOT converged",
                r.determined ? "" : ", NOT determined: the data do not constrain every parameter");
    for (std::size_t k = 0; k < r.names.size(); ++k)
        std::printf("  %-8s = %-12.6g %s\n", r.names[k].c_str(), r.value[k],
                    r.fixed[k] ? "(fixed)"
                    : (k < r.undetermined.size() && r.undetermined[k]) ? "+- undetermined"
                                                : ("+- " + std::to_string(r.stderror[k])).c_str());
}

/// Fits against v need a spread of volume fractions: a test at constant volume (D2/D3) or a cycle cut
/// short leaves the selected rows within a narrow band, where Eq. 2.11, 2.12 and 2.14 are not defined
/// by the data.
void requireVolumeRange(const std::vector<double>& v, const std::string& source) {
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    if (!(*hi - *lo >= 0.01)) {
        char buf[160];
        std::snprintf(buf, sizeof buf, ": the selected rows span only v = %.4f-%.4f (< 0.01)", *lo, *hi);
        inputError(source + buf + "; fits against v need a loading or unloading branch (a constant-volume test or a "
                                  "cycle cut short: try --branch loading)");
    }
}

/// Eq. 2.12 describes jammed packings: rows in the jump to unjamming (C* below C0, a handful of
/// contacts left) would dominate the exponential fit of the rattler fraction.
std::pair<std::vector<double>, std::vector<double>> rattlerRows(const std::vector<double>& v, const std::vector<double>& phi,
                                                                const std::vector<double>& cstar, double c0) {
    std::pair<std::vector<double>, std::vector<double>> out;
    for (std::size_t i = 0; i < v.size(); ++i)
        if (cstar[i] >= c0) {
            out.first.push_back(v[i]);
            out.second.push_back(phi[i]);
        }
    return out;
}

struct Jammed {
    std::vector<double> v, cstar, phi, cm, p, eps, sdev, fdev;
};
Jammed jammedRows(const CsvTable& t, BranchSelect b) {
    const auto rows = selectRows(t, b, 1e-6);  // above jamming: some pressure
    if (rows.size() < 5) inputError(t.source + ": fewer than 5 jammed rows on the selected branch");
    Jammed j;
    j.v = column(t, rows, "volume_fraction");
    j.cstar = column(t, rows, "C_star");
    j.phi = column(t, rows, "phi_r");
    j.cm = column(t, rows, "C_m");
    j.p = column(t, rows, "p_nd");
    j.eps = column(t, rows, "eps_dev");
    j.sdev = column(t, rows, "s_dev");
    j.fdev = column(t, rows, "F_dev");
    return j;
}

std::string gnuplotQuote(const std::string& s) { return "'" + s + "'"; }
using tools::shellQuote;

int plot(const Args& a) {
    // Every input is read and checked before anything is written: gnuplot would plot a foreign or
    // malformed file as empty axes, or fail half-way with its own multi-line messages.
    for (const std::string& f : a.files) {
        if (f.find('\'') != std::string::npos) inputError(f + ": a file name with a quote cannot be passed to gnuplot");
        const CsvTable t = readCsv(f);
        for (const char* c : {"tau", "volume_fraction", "p_nd", "C_star", "eps_dev", "s_dev", "F_dev"})
            if (!t.hasColumn(c)) inputError(f + ": no column '" + c + "' (not a RUN.macro.csv file?)");
        const int tau = t.column("tau");
        bool any = false;
        for (const auto& r : t.rows) any = any || r[std::size_t(tau)] >= 0;
        if (!any) inputError(f + ": no rows of the test (tau >= 0)");
    }
    ensureDirectory(a.out);
    std::ostringstream gp;
    gp << "set terminal pngcairo size 800,600 noenhanced\nset datafile separator ','\nset key autotitle columnhead\n"
       << "set grid\n";
    auto series = [&](const std::string& x, const std::string& y) {
        std::string s;
        for (std::size_t k = 0; k < a.files.size(); ++k) {
            s += (k ? ", " : "") + gnuplotQuote(a.files[k]) + " using (column('tau') >= 0 ? column('" + x + "') : 1/0):'" + y +
                 "' with lines title " +
                 gnuplotQuote(std::filesystem::path(a.files[k]).stem().stem().string());
        }
        return s;
    };
    const std::string dir = a.out + "/";
    gp << "set output " << gnuplotQuote(dir + "p_vs_v.png") << "\nset xlabel 'volume fraction v'\nset ylabel 'p (Eq. 2.7)'\n"
       << "plot " << series("volume_fraction", "p_nd") << "\n";
    // C* with the fit of the first file
    std::string fitCurve;
    try {
        const CsvTable t = readCsv(a.files.front());
        const Jammed j = jammedRows(t, branchOf(a.branch));
        const FitResult f = fitCstar(j.v, j.cstar, a.c0);
        char buf[256];
        std::snprintf(buf, sizeof buf, ", (x > %.6g ? %.6g + %.6g*(x/%.6g-1)**%.6g : 1/0) with lines lw 2 title 'Eq. 2.11 fit'",
                      f.get("v_c"), f.get("C0"), f.get("C1"), f.get("v_c"), f.get("alpha"));
        fitCurve = buf;
    } catch (const InputError&) {
    }
    gp << "set output " << gnuplotQuote(dir + "cstar_vs_v.png") << "\nset ylabel 'C* (Sec. 2.4.1)'\nset yrange [0:*]\n"
       << "plot " << series("volume_fraction", "C_star") << fitCurve << "\nset yrange [*:*]\n";
    gp << "set output " << gnuplotQuote(dir + "sdev_vs_epsdev.png") << "\nset xlabel 'deviatoric strain eps_dev'\n"
       << "set ylabel 's_dev = sigma_dev / p'\nplot " << series("eps_dev", "s_dev") << "\n";
    gp << "set output " << gnuplotQuote(dir + "fdev_vs_epsdev.png") << "\nset ylabel 'F_dev (Eq. 2.10)'\nplot "
       << series("eps_dev", "F_dev") << "\n";
    const std::string script = dir + "plots.gp", log = dir + "plots.log";
    writeWholeFile(script, gp.str());
    // gnuplot's own messages go to a log; on failure no half set of figures is left
    const std::string cmd = "gnuplot " + shellQuote(script) + " > " + shellQuote(log) + " 2>&1";
    if (std::system(cmd.c_str()) != 0) {
        std::error_code ec;
        for (const char* png : {"p_vs_v.png", "cstar_vs_v.png", "sdev_vs_epsdev.png", "fdev_vs_epsdev.png"})
            std::filesystem::remove(dir + png, ec);
        inputError("gnuplot failed (is gnuplot installed?); its messages: " + log + ", script: " + script);
    }
    {
        std::error_code ec;
        if (std::filesystem::file_size(log, ec) == 0 && !ec) std::filesystem::remove(log, ec);
    }
    std::printf("plots written to %s (p_vs_v.png, cstar_vs_v.png, sdev_vs_epsdev.png, fdev_vs_epsdev.png)\n",
                a.out.c_str());
    return 0;
}
// Steady state of deviatoric (D2/D3) runs: mean of each quantity over the test rows with
// eps_dev >= epsMin, one row per run; then Eq. 2.11 (C0 fixed) through the runs' (v, C*) points,
// with C1 and alpha fixed when given (a few runs cannot fix three parameters).
int steady(const Args& a) {
    std::vector<double> v, cs, phi, cm, pnd;
    std::vector<std::string> skipped;  // reported when the fit succeeds: an error must be the only line on stderr
    const auto reportSkipped = [&] {
        for (const auto& f : skipped)
            std::fprintf(stderr, "pdpm-fit steady: %s skipped: fewer than 3 test rows with eps_dev >= %g\n", f.c_str(), a.epsMin);
    };
    std::printf("%-28s %5s %8s %8s %8s %9s %8s %8s %10s\n", "run", "rows", "v", "C*", "phi_r", "p_nd", "s_dev", "F_dev",
                "Ek/Ep");
    for (const auto& f : a.files) {
        const CsvTable t = readCsv(f);
        const auto all = selectRows(t, BranchSelect::Test);
        const auto eps = column(t, all, "eps_dev");
        std::vector<std::vector<double>> rows;
        for (std::size_t i = 0; i < all.size(); ++i)
            if (eps[i] >= a.epsMin) rows.push_back(all[i]);
        if (rows.size() < 3) {  // an unfinished run, or one that never reached the steady state: skipped
            skipped.push_back(f);
            continue;
        }
        auto mean = [&](const char* name) {
            double m = 0;
            for (double x : column(t, rows, name)) m += x;
            return m / double(rows.size());
        };
        v.push_back(mean("volume_fraction"));
        cs.push_back(mean("C_star"));
        phi.push_back(mean("phi_r"));
        cm.push_back(mean("C_m"));
        pnd.push_back(mean("p_nd"));
        std::printf("%-28s %5zu %8.4f %8.4f %8.4f %9.5f %8.4f %8.4f %10.3g\n",
                    std::filesystem::path(f).filename().string().c_str(), rows.size(), v.back(), cs.back(), mean("phi_r"),
                    mean("p_nd"), mean("s_dev"), mean("F_dev"), mean("Ek_over_Ep"));
    }
    if (v.empty()) inputError("steady: no run has 3 test rows with eps_dev >= " + std::to_string(a.epsMin));
    const bool fixC1 = a.c1 > 0, fixAlpha = a.alpha > 0;
    const std::size_t nFree = 1 + !fixC1 + !fixAlpha;
    // runs at the same volume fraction do not add to what a fit against v can determine
    std::vector<double> sorted = v;
    std::sort(sorted.begin(), sorted.end());
    std::size_t nv = 1;
    for (std::size_t k = 1; k < sorted.size(); ++k)
        if (sorted[k] - sorted[k - 1] > 1e-4) ++nv;
    if (nv <= nFree) {
        std::printf("Eq. 2.11 through the steady states: %zu distinct volume fractions (%zu runs) are too few for %zu "
                    "free parameters (give --c1 and/or --alpha)\n", nv, v.size(), nFree);
        reportSkipped();
        return 0;
    }
    double vmin = 1;
    for (double x : v) vmin = std::min(vmin, x);
    const FitResult r = levenbergMarquardt(
        cs, [&](std::size_t i, const std::vector<double>& p) { return cstarModel(v[i], p[0], p[1], p[2], p[3]); },
        {"C0", "C1", "alpha", "v_c"}, {a.c0, fixC1 ? a.c1 : 8.0, fixAlpha ? a.alpha : 0.6, 0.98 * vmin},
        {true, fixC1, fixAlpha, false});
    print("Eq. 2.11 C*(v) through the steady states", r);
    if (nv >= 3) print("Eq. 2.12 phi_r(v) through the steady states, v_c from Eq. 2.11", fitRattlers(v, phi, r.get("v_c")));
    if (nv >= 4) print("Eq. 2.14 p(v) through the steady states", fitPressure(v, cm, pnd));
    reportSkipped();
    return 0;
}
// Sec. 2.7: calibrate the reduced anisotropy model on D2/D3 runs (Eq. 2.17/2.18 per run, Eq. 2.20
// over the runs) and/or read a Table 2.3-style coefficient file, then predict the loading branch of
// a uniaxial run (Eq. 2.17/2.18 with v-dependent coefficients along its path, Fig. 2.12/2.14).
int model(const Args& a) {
    if (a.uni.empty()) inputError("model: --uni FILE (the uniaxial run to predict) is required");
    std::vector<std::pair<std::string, AnisotropyModel>> models;
    if (!a.files.empty()) {
        std::vector<CsvTable> runs;
        for (const auto& f : a.files) runs.push_back(readCsv(f));
        std::vector<std::pair<double, std::pair<FitResult, FitResult>>> per;
        models.push_back({"runs", calibrateAnisotropy(runs, a.vc, &per)});
        std::printf("per run (Eq. 2.17 / 2.18):\n%8s %10s %10s %10s %10s\n", "v", "s_max", "beta_s", "F_max", "beta_F");
        for (const auto& [v, fits] : per)
            std::printf("%8.4f %10.5f %10.4f %10.5f %10.4f\n", v, fits.first.get("q_max"), fits.first.get("beta"),
                        fits.second.get("q_max"), fits.second.get("beta"));
    }
    if (!a.table.empty()) models.push_back({"table", readAnisotropyTable(a.table, a.vc)});
    for (const auto& [name, m] : models) {
        if (name == "runs")
            std::printf("Eq. 2.20, v_c = %.4f (calibrated on the runs, Table 2.3 style; held constant below the "
                        "lowest run, v = %.4f):\n",
                        a.vc, m.vLo);
        else
            std::printf("Eq. 2.20, v_c = %.4f (%s):\n", a.vc, a.table.c_str());
        std::printf("%-10s %10s %10s %10s\n", "parameter", "Q_max", "Q_c", "alpha");
        auto row = [](const char* n, const FitResult& r) {
            std::printf("%-10s %10.5g %10.5g %10.5g\n", n, r.value[0], r.value[0] + r.value[1], r.value[2]);
        };
        row("s_dev_max", m.sMax);
        row("beta_s", m.betaS);
        if (m.stressQmaxFixed)
            std::printf("(s_dev_max and beta_s: Q_max fixed at 0, as for the fabric rows: three volume fractions "
                        "cannot fit three parameters)\n");
        row("F_dev_max", m.fMax);
        row("beta_F", m.betaF);
    }
    const CsvTable u = readCsv(a.uni);
    const auto rows = selectRows(u, BranchSelect::Loading);
    if (rows.size() < 3) inputError(a.uni + ": fewer than 3 loading rows");
    const auto v = column(u, rows, "volume_fraction"), e = column(u, rows, "eps_dev");
    const auto s = column(u, rows, "s_dev"), f = column(u, rows, "F_dev");
    std::vector<std::string> cols = {"eps_dev", "volume_fraction", "s_dev", "F_dev"};
    std::vector<std::vector<double>> pred;
    for (const auto& [name, m] : models) {
        const auto ps = m.predictS(v, e, s.front()), pf = m.predictF(v, e, f.front());
        for (std::size_t i = 0; i < ps.size(); ++i)
            if (!std::isfinite(ps[i]) || !std::isfinite(pf[i]))
                inputError("model: the " + name + " coefficients give a prediction that is not a finite number at v = " +
                           std::to_string(v[i]) + " (" + (name == "table" ? a.table : std::string("the runs' fits")) + ")");
        double es = 0, ef = 0, ns = 0, nf = 0;
        for (std::size_t i = 0; i < s.size(); ++i) {
            es += (ps[i] - s[i]) * (ps[i] - s[i]);
            ef += (pf[i] - f[i]) * (pf[i] - f[i]);
            ns += s[i] * s[i];
            nf += f[i] * f[i];
        }
        std::printf("prediction of %s (loading, %zu rows, v %.4f-%.4f) from the %s coefficients: relative rms error "
                    "s_dev %.3f, F_dev %.3f\n",
                    a.uni.c_str(), s.size(), v.front(), v.back(), name.c_str(), std::sqrt(es / ns), std::sqrt(ef / nf));
        cols.push_back("s_dev_pred_" + name);
        cols.push_back("F_dev_pred_" + name);
        pred.push_back(ps);
        pred.push_back(pf);
    }
    if (a.outGiven) {
        std::vector<std::vector<double>> out;
        for (std::size_t i = 0; i < s.size(); ++i) {
            std::vector<double> r = {e[i], v[i], s[i], f[i]};
            for (const auto& p : pred) r.push_back(p[i]);
            out.push_back(std::move(r));
        }
        writeCsv(a.out, cols, out, {"pdpm-fit model: loading branch of " + a.uni + " with the Eq. 2.17/2.18 predictions"});
        std::printf("prediction written to %s\n", a.out.c_str());
    }
    return 0;
}
} // namespace

int main(int argc, char** argv) {
    return runMain("pdpm-fit", [&]() -> int {
        if (argc >= 2 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
            std::cout << "pdpm-fit: fits of thesis chapter 2 on RUN.macro.csv files\n"
                         "  pdpm-fit cstar|rattlers|pressure|sdev|fdev FILE [--branch B] [--vc X] [--c0 C0]\n"
                         "  pdpm-fit table FILE... [--branch B]\n"
                         "  pdpm-fit model --uni FILE [D2FILE...] [--table T23.csv] [--vc X] [--out PRED.csv]\n"
                         "  pdpm-fit plot --out DIR FILE...\n"
                         "  pdpm-fit steady FILE... [--eps_min E] [--c1 X] [--alpha Y]   deviatoric steady state, Eq. 2.11 through it\n"
                         "B: auto (default), loading, unloading, test.\n";
            return 0;
        }
        const Args a = parse(argc, argv);
        const BranchSelect b = branchOf(a.branch);
        if (a.command == "plot") return plot(a);
        if (a.command == "steady") return steady(a);
        if (a.command == "table") {
            std::printf("%-28s %8s %8s %8s %8s %8s %8s %9s %8s %8s\n", "run", "C1", "alpha", "v_c", "phi_c", "phi_v",
                        "p0", "gamma_p", "v_c(p)", "C*max");
            for (const auto& f : a.files) {
                const CsvTable t = readCsv(f);
                const Jammed j = jammedRows(t, b);
                requireVolumeRange(j.v, f);
                const FitResult c = fitCstar(j.v, j.cstar, a.c0);
                const auto [rv, rphi] = rattlerRows(j.v, j.phi, j.cstar, a.c0);
                // too few jammed rows with C* >= C0 for Eq. 2.12: its columns are nan, the others stand
                FitResult r;
                r.names = {"phi_c", "phi_v"};
                r.value = {std::nan(""), std::nan("")};
                if (rv.size() >= 4) r = fitRattlers(rv, rphi, c.get("v_c"));
                const FitResult p = fitPressure(j.v, j.cm, j.p);
                double cmax = 0;
                for (double x : j.cstar) cmax = std::max(cmax, x);
                std::printf("%-28s %8.4f %8.4f %8.4f %8.4f %8.3f %8.5f %9.5f %8.4f %8.3f\n",
                            std::filesystem::path(f).filename().string().c_str(), c.get("C1"), c.get("alpha"),
                            c.get("v_c"), r.get("phi_c"), r.get("phi_v"), p.get("p0"), p.get("gamma_p"), p.get("v_c"), cmax);
            }
            return 0;
        }
        if (a.command == "model") return model(a);
        if (a.files.size() != 1) inputError(a.command + ": exactly one input file");
        const CsvTable t = readCsv(a.files.front());
        const Jammed j = jammedRows(t, b);
        if (a.command == "cstar" || a.command == "rattlers" || a.command == "pressure") requireVolumeRange(j.v, t.source);
        if (a.command == "cstar") print("Eq. 2.11 C*(v)", fitCstar(j.v, j.cstar, a.c0));
        else if (a.command == "rattlers") {
            const double vc = a.vcGiven ? a.vc : fitCstar(j.v, j.cstar, a.c0).get("v_c");
            const auto [rv, rphi] = rattlerRows(j.v, j.phi, j.cstar, a.c0);
            print("Eq. 2.12 phi_r(v), v_c = " + std::to_string(vc) + ", rows with C* >= C0", fitRattlers(rv, rphi, vc));
        } else if (a.command == "pressure") print("Eq. 2.14 p(v)", fitPressure(j.v, j.cm, j.p));
        else if (a.command == "sdev") print("Eq. 2.17 s_dev(eps_dev)", fitSaturation(j.eps, j.sdev));
        else if (a.command == "fdev") print("Eq. 2.18 F_dev(eps_dev)", fitSaturation(j.eps, j.fdev));
        else inputError("unknown command '" + a.command + "'");
        return 0;
    });
}
