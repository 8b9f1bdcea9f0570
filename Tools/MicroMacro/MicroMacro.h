// Micro-macro analysis of a packing in a periodic box (thesis Sec. 2.4 and 3.3): stress (Eq. 2.5),
// pressure and its dimensionless form (Eq. 2.7), deviatoric stress (Eq. 2.8/3.14), fabric
// (Eq. 2.9 and the normalised Eq. 3.16), deviatoric fabric (Eq. 2.10/3.18, 3.19), coordination
// numbers and rattlers (Sec. 2.4.1), eigenvalues / eigenvector angles to z (Eq. 3.20) and shape
// factors for all, strong and weak contacts, and the friction mobilisation classes of Sec. 3.4.4.
//
// Works on the particle arrays and DPMBase::contacts() records, so a driver can call it in situ from
// its writeOutputFiles() override (see Tools/MicroMacro/ElementTest.h), and tests can feed it
// synthetic contact sets. All sums are serial, in record order: results do not depend on threads.
//
// Conventions: stress is compression positive, sigma = (1/V) (sum_p m v (x) v + sum_c f_c (x) l_c)
// with f_c the force on particle i and l_c = x_i - x_j (i.e. Eq. 2.5 with the thesis' l pointing from
// i to j); strains in the CSV are compression positive too (eps_v = ln(V0/V) = -varepsilon_v of the
// thesis). Deviatoric magnitudes use the eigenvalues (objective form, Eq. 3.14/3.18 = sqrt(3 J2)).
#pragma once
#include <Eigen/Dense>
#include <array>
#include <string>
#include <vector>

#include "Contacts/ContactRecord.h"
#include "Particles/ParticleData.h"

namespace pdpm {

/// Eigen-analysis of the deviator of a symmetric 3x3 tensor (Sec. 3.3.1).
struct TensorSummary {
    double lambda[3] = {0, 0, 0};  ///< deviatoric eigenvalues, lambda1 >= lambda2 >= lambda3
    double theta[3] = {0, 0, 0};   ///< angle (degrees, in [0, 90]) of each eigenvector to z (Eq. 3.20)
    double shape = 0;              ///< Lambda = lambda2 / lambda1 (0 if lambda1 = 0)
    double devMagnitude = 0;       ///< sqrt(((l1-l2)^2 + (l2-l3)^2 + (l3-l1)^2)/2) = sqrt(3 J2)
    double axialStar = 0;          ///< Eq. (3.19) in the box axes, signed: t_zz - (t_xx + t_yy)/2 (equal to
                                   ///< lambda_z - (other two)/2 when the principal axes are the box axes)
};
TensorSummary summariseTensor(const Eigen::Matrix3d& t);

/// Inputs that are not in the particle / contact data.
struct MacroInput {
    double volume = 0;         ///< box volume V (m^3)
    double time = 0;           ///< s
    double tau = 0;            ///< dimensionless time t/T of the test
    double stiffness = 0;      ///< k of Eq. (2.7) (N/m)
    double mu = 0;             ///< sliding friction (0: frictionless, friction columns are 0)
    Eigen::Vector3d strain = Eigen::Vector3d::Zero();  ///< true strains ln(L0/L) per axis, compression positive
    double epsV = 0;           ///< ln(V0/V), compression positive
    double epsDev = 0;         ///< Eq. (2.4) of the true strains
    /// Eq. (2.4) of the engineering strains 1 - L/L0 (chapter 3's Eq. 3.2 strain: its eps_dev^max =
    /// 0.1549 of the uniaxial cycle to v = 0.82 is this one; the true strain reaches about 0.170)
    double epsDevEngineering = 0;
    double kineticEnergy = 0;  ///< translational + rotational (J)
    double elasticEnergy = 0;  ///< J
    /// translational energy of the velocities relative to the box's affine flow plus the rotational
    /// energy (J; see fluctuationKineticEnergy); < 0: not given (Ek_fluct_over_Ep is then 0)
    double fluctuationKineticEnergy = -1;
    /// Axes whose faces move (wall-driven, or remapped: then the ratio is a null check of the contacts
    /// across the boundary): the contacts within kFaceLayer box lengths of a face of any of them (the
    /// union of the slabs) form the face layer of MacroResult::mobilisationFaceRatio. Needs boxLo/boxHi.
    std::array<bool, 3> faceAxes{false, false, false};
    Eigen::Vector3d boxLo = Eigen::Vector3d::Zero(), boxHi = Eigen::Vector3d::Zero();
};

/// Width of the face layer of MacroResult::mobilisationFaceRatio, in box lengths (the thesis' check,
/// Sec. 3.2.2; for one face axis the first layer of Tools/Polar's --layers 5).
inline constexpr double kFaceLayer = 0.1;

struct MacroResult {
    Eigen::Matrix3d stress = Eigen::Matrix3d::Zero();          ///< total (symmetrised), Pa
    Eigen::Matrix3d stressKinetic = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d fabric = Eigen::Matrix3d::Zero();          ///< Eq. (2.9)
    Eigen::Matrix3d fabricNormalised = Eigen::Matrix3d::Zero();///< Eq. (3.16), trace 1
    double volumeFraction = 0, meanRadius = 0;
    double p = 0, pNd = 0, sigmaDev = 0, sDev = 0, sDevStar = 0;
    double Fv = 0, Fdev = 0, FdevStar = 0, FnDev = 0, FnDevStar = 0;
    double Cr = 0, Cm = 0, Cstar = 0, phiR = 0;
    long contacts = 0;  ///< particle-particle contacts
    TensorSummary stressAll, stressStrong, stressWeak, fabricAll, fabricStrong, fabricWeak;
    double weakFraction = 0;              ///< weak contacts / all (f_n <= <f_n>)
    double wsl = 0, wst = 0, ssl = 0, sst = 0;  ///< fractions of all contacts (Sec. 3.4.4)
    double mobilisation = 0;              ///< mean |f_t| / (mu f_n) over contacts with f_n > 0
    /// mobilisation of the loaded contacts whose contact point lies in the face layer of a face axis
    /// (MacroInput::faceAxes) over that of the other loaded contacts: 1 within the scatter in a
    /// homogeneous sample; 0 when not defined (no friction, no face axis, or an empty part)
    double mobilisationFaceRatio = 0;
    double ekOverEp = 0;
    double ekFluctOverEp = 0;  ///< MacroInput::fluctuationKineticEnergy / elastic energy
};

/// Contacts with fewer than this many contacts make a particle a rattler (Sec. 2.4.1).
inline constexpr int kRattlerContacts = 4;

MacroResult computeMacro(const ParticleData& particles, const std::vector<ContactRecord>& contacts,
                         const MacroInput& in);

/// Translational kinetic energy of the particles' motion relative to a homogeneous (affine) flow
/// u_a(x) = rate[a] (x_a - c_a) along the axes with flowAxis[a] (J): sum of m |v - u(x) - <v - u>|^2 / 2,
/// <.> the mass-weighted mean (removes the flow's unknown fixed point and any drift of the whole
/// packing). For a box whose walls alone move (the particles feel the deformation through the
/// periodic images and take up the flow themselves); axes whose particles are remapped affinely carry
/// no flow in the velocities and are left out. Serial, in particle order.
double fluctuationKineticEnergy(const ParticleData& particles, const Vec3& rate, const Vec3& centre,
                                const std::array<bool, 3>& flowAxis);

/// Column names of RUN.macro.csv (the required columns first, then the extra ones).
const std::vector<std::string>& macroColumns();
/// Values in the order of macroColumns().
std::vector<double> macroRow(const MacroResult& r, const MacroInput& in);

/// Accumulates rows and rewrites DIR/RUN.macro.csv atomically after each row.
class MacroCsv {
public:
    explicit MacroCsv(std::string path = "") : path_(std::move(path)) {}
    void setPath(const std::string& p) { path_ = p; }
    void append(const std::vector<double>& row);
    /// Keep only rows with time <= t (after a restart).
    void truncateAfter(double t);
    /// Re-read rows of an existing file (restart); does nothing if it does not exist. A file of an
    /// earlier version (a subset of today's columns) keeps its rows, the new columns NaN; a file with
    /// other columns is renamed to PATH.old (a note on stderr in both cases).
    void reload();
    std::size_t rows() const { return rows_.size(); }
    const std::vector<std::vector<double>>& data() const { return rows_; }

private:
    void flush() const;
    std::string path_;
    std::vector<std::vector<double>> rows_;
};

} // namespace pdpm
