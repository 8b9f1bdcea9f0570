// Directional micro-analysis of contacts (thesis Sec. 3.4.5, 3.5, Appendices I and II):
// contact probability density P(θ) relative to an axis by the constant-bin-width (b) and the
// constant-height (h) methods, polar distributions f_n(θ), f_t(θ), ψ_t(θ), harmonic fits of second
// and sixth order (Eq. 3.24, 3.25) by the methods M1-M3 with standard errors, the fabric check and the
// normal-force probability density in cones around x, y, z. See Documentation/tools-polar.md.
#pragma once
#include "Snapshot.h"

#include <array>
#include <string>
#include <vector>

namespace pdpm::tools {

struct PolarConfig {
    Vec3 axis{0, 0, 1};            ///< reference (axial) direction; normalised internally
    int binsTheta = 18;            ///< constant-bin-width bins on [0, π/2] (mirrored to [π/2, π])
    int binsHeight = 10;           ///< constant-height bins on |cos θ| ∈ [0, 1] (M_h = 20 on [-1, 1])
    bool cosNormalisation = false; ///< P(θ) = φ/(cos θ_i − cos θ_f) instead of φ/(Δθ sin θ)
    double mu = 0.5;               ///< friction coefficient for ψ_t = f_t/(μ f_n)
    bool includeWalls = false;     ///< include wall contacts (j < 0)
    double chi = 0.8;              ///< cone cut-off |n·e| > χ of the force pdf (Sec. 3.4.5)
    int pdfBins = 50;
    double pdfMax = 5;             ///< largest f/<f_all> in the pdf
};

/// One angular bin. θ values in rad; P normalised so that ∫_0^π P(θ) sin θ dθ = 1.
struct PolarBin {
    double theta = 0, lo = 0, hi = 0;   ///< centre and edges (θ for b-bins; θ = acos(h) for h-bins)
    double count = 0;                   ///< contacts in the bin (both mirror images together)
    double fraction = 0;                ///< φ = count / C_tot
    double P = 0;                       ///< probability density
    double fn = 0, ft = 0, psi = 0;     ///< mean f_n, mean |f_t|, mean |f_t|/(μ f_n) (f_n > 0 only)
};

/// Anisotropy descriptors of P_6 = a0 [1 + ε2 Y2 + ε4 Y4 + ε6 Y6] with standard errors.
struct HarmonicFit {
    std::string method;
    double a0 = 0, a0Se = 0;
    std::array<double, 3> eps{}, se{};  ///< ε2, ε4, ε6
    double eps2nd = 0, eps2ndSe = 0;    ///< ε of the second-order form (Eq. 3.24), same data
    int points = 0;
};

struct PolarResult {
    double time = 0;
    long step = -1;
    int contacts = 0;                   ///< C_tot used
    std::vector<PolarBin> binWidth;     ///< half range [0, π/2]
    std::vector<PolarBin> constHeight;  ///< half range, ordered by increasing θ
    HarmonicFit m1, m2, m3;
    std::array<std::array<double, 3>, 3> fabric{};  ///< F = (1/N_c) Σ n n (Eq. 3.16)
    double Fdev = 0;                    ///< Eq. 3.18
    double eps2Fabric = 0;              ///< 15/4 (a·F·a − 1/3): ε2 of an axisymmetric P_2 with this fabric
    double meanFn = 0;                  ///< <f_n> over all contacts
    std::vector<double> pdfCentres;     ///< f* = f_n/<f_n>
    std::array<std::vector<double>, 4> pdf;  ///< P(f*) for cones around x, y, z, and all contacts
    std::array<int, 4> pdfCounts{};
};

/// Y_l^0 as in the thesis: Y2 = 3c²−1, Y4 = 35c⁴−30c²+3, Y6 = 231c⁶−315c⁴+105c²−5.
double harmonicY(int l, double c);
/// P_6(θ) for given a0 and ε.
double harmonicP6(double a0, const std::array<double, 3>& eps, double theta);

PolarResult analysePolar(const ContactSnapshot& snapshot, const PolarConfig& cfg);

HarmonicFit fitM1(const std::vector<PolarBin>& binWidth);
HarmonicFit fitM2(const std::vector<PolarBin>& constHeight);
HarmonicFit fitM3(const std::vector<PolarBin>& binWidth);

/// Writes the bins of both methods mirrored to [0, π] (columns documented in tools-polar.md).
void writePolarBinsCsv(const std::string& path, const PolarResult& r);
void writePolarPdfCsv(const std::string& path, const PolarResult& r);
/// Header of the time series; `row` formats one snapshot (strain values given by the caller).
std::string polarSeriesHeader();
std::string polarSeriesRow(const PolarResult& r, double axialStrain, double devStrain);

} // namespace pdpm::tools
