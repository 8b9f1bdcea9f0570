// Contacts and stress by distance from the faces of the box along one axis: the consistency check
// the thesis recommends for wall-driven element tests (Sec. 3.2.2 and the best-practice list of
// chapter 6): is friction mobilised more, and is the stress different, next to the (virtual periodic
// or real) walls that drive the deformation? See Documentation/tools-polar.md ("Layers").
#pragma once
#include "Snapshot.h"

#include <array>
#include <string>
#include <vector>

namespace pdpm::tools {

/// One layer: the contacts whose contact point lies at a distance d from the nearest face of the box
/// along the axis with lo <= d/L < hi (d/L in [0, 1/2]; the layer is the two slabs at both faces,
/// 1/n of the box volume each for n layers).
struct LayerStats {
    double lo = 0, hi = 0;         ///< distance range as a fraction of the box length L along the axis
    int contacts = 0;              ///< contacts in the layer (particle-particle unless walls are included), all in sigma
    int loaded = 0;                ///< of these, the contacts with f_n > 0 (psi and the sliding fraction are over these)
    double psi = 0;                ///< mean |f_t| / (mu f_n) (NaN without loaded contacts)
    double sliding = 0;            ///< fraction of the loaded contacts at the Coulomb limit (the fstat flag; NaN without)
    /// Stress of the layer, sigma = (1/V_layer) sum f (x) b over all its contacts, tensile ones included
    /// as in the whole-sample stress of Tools/MicroMacro (compression positive), symmetrised;
    /// V_layer = V / n, so that the mean of the layers' sigma is the whole sample's.
    std::array<std::array<double, 3>, 3> sigma{};
    double p = 0;                  ///< tr(sigma)/3 (Pa)
    double sDev = 0;               ///< sqrt(3 J2)/p (Eq. 3.14 over p, signed p as in Tools/MicroMacro; NaN without contacts)
    double axialOverLateral = 0;   ///< sigma_aa / mean of the other two normal stresses (NaN without contacts)
    /// Normalised fabric of the layer's contacts, F = (1/C) sum n (x) n (Eq. 3.16, trace 1), and its
    /// axial minus mean lateral diagonal component, F_aa - (F_bb + F_cc)/2 (Eq. 3.19 with the box axes
    /// as eigen-directions; positive when contacts favour the axis). NaN without contacts.
    std::array<std::array<double, 3>, 3> fabric{};
    double fabricAxialStar = 0;
};

/// Throws InputError unless the snapshot's box has a positive, finite extent along every axis.
void checkLayerBox(const ContactSnapshot& snapshot);

/// Layer statistics of one contact snapshot: `axis` 0, 1 or 2, `layers` >= 1 bins of equal width on
/// d/L in [0, 1/2], mu > 0 for psi; contact points outside the box (image contacts) are wrapped back.
/// Throws InputError for a bad axis, layer count, mu, or a box without volume (every extent must be positive).
std::vector<LayerStats> analyseLayers(const ContactSnapshot& snapshot, int axis, int layers, double mu, bool includeWalls);

/// CSV of several snapshots: header and one row per (snapshot, layer), columns documented in
/// tools-polar.md.
std::string layersHeader();
/// `block`: the index of the snapshot among those analysed (the plot shows the largest).
std::string layersRow(int block, double time, double axialStrain, int index, const LayerStats& s);

} // namespace pdpm::tools
