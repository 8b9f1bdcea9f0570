// Coarse-graining (CG) of particle and contact data onto regular grids (thesis Sec. 5.3.3,
// Eq. 5.8-5.12, and the stress/fabric definitions of Sec. 2.4/3.3), usable in-situ (call
// CoarseGrainer::add from a driver hook) or through the pdpm-cg command.
//
// Choices (see Documentation/tools-coarse-graining.md):
//  - The kernel is a tensor product of 1D kernels of standard deviation w: a Gaussian cut off at
//    |Δx_a| = 3w in each direction (renormalised), or the Lucy polynomial with cut-off c = w·√(21/2).
//  - Grid values are cell averages of the CG field (the kernel is integrated exactly over each grid
//    cell), so Σ ρ ΔV equals the total mass to round-off, and the volume average of the contact
//    stress equals the global stress (Eq. 2.5) to round-off.
//  - Periodic directions: the kernel is summed over periodic images. Non-periodic directions: the
//    kernel is clipped at the domain boundary (walls) and by default renormalised to unit mass
//    inside the domain (WallTreatment::Renormalize); WallTreatment::Cut keeps the plain cut kernel.
//  - Averaged directions (grid size 0) use no kernel: the field is the average over the domain extent.
//  - Contact stress σ_αβ = Σ_c f_α l_β ∫_0^1 W(r − x_i + s l) ds with f the force on i and
//    l = x_i − x_j (or x_i − contact point for walls), compression positive; kinetic stress
//    Σ m v'v' W with v' = v − V(r).
#pragma once
#include "Snapshot.h"

#include <array>
#include <string>
#include <vector>

namespace pdpm::tools {

enum class CgKernel { Gaussian, Lucy };
enum class WallTreatment { Renormalize, Cut };

struct CgConfig {
    CgKernel kernel = CgKernel::Gaussian;
    double width = 0;                 ///< w (m), standard deviation of the 1D kernel; must be > 0
    WallTreatment walls = WallTreatment::Renormalize;
    /// Cartesian: number of grid cells along x, y, z; 0 = average over that direction.
    /// Cylindrical: n[0] radial cells, n[1] ignored (azimuthal average), n[2] cells along the axis.
    int n[3] = {0, 0, 0};
    bool cylindrical = false;
    int axis = 2;                     ///< cylinder axis (0 x, 1 y, 2 z)
    double centre[2] = {0, 0};        ///< cylinder axis position in the two other coordinates (ordered)
    bool centreSet = false;           ///< false: the centre of the domain
    double rmax = 0;                  ///< radial extent (0: half the smaller perpendicular domain extent)
    bool regionSet = false;           ///< false: the grid spans the domain (box)
    Vec3 regionLo, regionHi;          ///< grid extent along Cartesian axes (if regionSet)
    bool domainSet = false;           ///< false: the domain is the box of the snapshot
    Vec3 domainLo, domainHi;
    int quadratureMax = 32;           ///< max Gauss points along a branch vector
};

/// Largest grid (cells) a CoarseGrainer accepts: pdpm-cg needs about 1.5 kB per cell (the sums, two
/// results and the .vti copies of the fields), so 1e7 cells take about 15 GB.
inline constexpr long kCgMaxCells = 10'000'000;
/// Cells of the configured grid (averaged directions count as one cell; cylindrical: n[0] × n[2]).
double cgCells(const CgConfig& cfg);

/// Tensor components: symmetric 6 = xx xy xz yy yz zz; full 9 = xx xy xz yx yy yz zx zy zz.
using Sym6 = std::array<double, 6>;
using Tensor9 = std::array<double, 9>;

/// The grid: cell centres per grid axis (averaged axes have one cell at the domain centre).
struct CgGeometry {
    int n[3] = {1, 1, 1};                 ///< cells along each grid axis (≥ 1)
    bool averaged[3] = {false, false, false};
    bool cylindrical = false;
    int axis = 2;
    std::vector<double> centres[3];       ///< cell centre coordinates per grid axis
    double spacing[3] = {1, 1, 1};
    std::array<std::string, 3> names;     ///< "x","y","z" or "r","theta","z"
    std::size_t cells() const { return std::size_t(n[0]) * n[1] * n[2]; }
    std::size_t index(int i, int j, int k) const { return std::size_t(i) + std::size_t(n[0]) * (j + std::size_t(n[1]) * k); }
};

/// CG fields, cell-averaged. In cylindrical mode vectors/tensors are in the local (r, θ, z) frame.
struct CgResult {
    CgGeometry geom;
    double time = 0;           ///< mean time of the averaged snapshots
    int snapshots = 0;
    int contactSnapshots = 0;  ///< of them with contacts: the contact stress and fabric average over these
    bool hasContacts = false;
    std::vector<double> rho;               ///< mass density (kg/m³), Eq. 5.9
    std::vector<Vec3> momentum;            ///< momentum density, Eq. 5.10
    std::vector<Vec3> velocity;            ///< V = p/ρ (0 where ρ = 0)
    std::vector<Sym6> kineticStress;       ///< Σ m v'v' W (Pa)
    std::vector<Tensor9> contactStress;    ///< Σ f ⊗ l ∫W ds (Pa)
    std::vector<Sym6> fabric;              ///< Σ_p V_p Σ_c n n W (Eq. 3.15)
    std::vector<double> numberDensity;     ///< Σ W (1/m³)
    std::vector<double> volumeFraction;    ///< Σ V_p W
    std::vector<double> contactDensity;    ///< Σ C_p W (contacts per volume, each contact counted per particle)
    std::vector<double> coordination;      ///< contactDensity / numberDensity (0 where empty)
    double averagedMeasure = 1;            ///< product of the extents of the averaged directions (m^k)

    Tensor9 stress(std::size_t c) const;   ///< kinetic + contact
    double pressure(std::size_t c) const;  ///< tr(stress)/3
};

/// Accumulates snapshots (time average over a window) and produces the fields.
class CoarseGrainer {
public:
    /// Validates the configuration (InputError: width ≤ 0, empty grid, bad region…).
    explicit CoarseGrainer(const CgConfig& cfg);

    /// Adds one snapshot. `contacts` may be null (then no contact stress; fabric and coordination
    /// come from the particles' coordination numbers when present). The geometry is fixed by the
    /// first snapshot added (its box, unless the config sets domain/region).
    void add(const ParticleSnapshot& particles, const ContactSnapshot* contacts = nullptr);
    int count() const { return count_; }
    /// Time-averaged fields of everything added since construction or the last reset().
    CgResult result() const;
    void reset();

    /// Kernel cut-off distance for the configured kernel and width.
    double cutoff() const;

private:
    struct Impl;
    CgConfig cfg_;
    int count_ = 0;
    int contactCount_ = 0;  ///< snapshots added with contacts
    double timeSum_ = 0;
    bool haveGeometry_ = false;
    bool anyContacts_ = false;
    CgGeometry geom_;
    std::vector<double> partSum_, contSum_;  // channel-major sums over snapshots
    std::array<double, 3> domLo_{}, domHi_{};
    bool periodic_[3] = {false, false, false};
    double rmax_ = 0, centre_[2] = {0, 0};
    void setupGeometry(const ParticleSnapshot& s);
};

/// One-call convenience: coarse-grain a single snapshot.
CgResult coarseGrain(const CgConfig& cfg, const ParticleSnapshot& particles, const ContactSnapshot* contacts = nullptr);

/// Height profile of Eq. 5.11: h(z,t) = ρ(z,t)/ρ(z,0) · h_ini for a 1D grid (0 where ρ(z,0) = 0).
std::vector<double> heightProfile(const CgResult& now, const CgResult& initial, double hIni);
/// Mass per unit length along the single resolved axis of a 1D grid (Eq. 5.12 divided by Δz):
/// ρ times the cross-section of the averaged directions.
std::vector<double> massPerLength(const CgResult& r);

/// Column names of the CSV table written by writeCgCsv (documented in tools-coarse-graining.md).
std::vector<std::string> cgCsvColumns(const CgResult& r);
/// One row per grid point.
void writeCgCsv(const std::string& path, const CgResult& r, const std::vector<double>& height = {});
void writeCgVti(const std::string& path, const CgResult& r);

} // namespace pdpm::tools
