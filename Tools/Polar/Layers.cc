#include "Layers.h"

#include "Boundaries/FaceDistance.h"
#include "Core/Error.h"
#include "OutputFiles.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace pdpm::tools {

void checkLayerBox(const ContactSnapshot& snapshot) {
    const Vec3 L = snapshot.boxHi - snapshot.boxLo;
    if (!(L.x > 0) || !(L.y > 0) || !(L.z > 0) || !std::isfinite(L.x * L.y * L.z))
        inputError("layers: the box of the block at t = " + fmt(snapshot.time) + " s has no volume");
}

std::vector<LayerStats> analyseLayers(const ContactSnapshot& snapshot, int axis, int layers, double mu, bool includeWalls) {
    if (axis < 0 || axis > 2) inputError("layers: the axis must be x, y or z");
    if (layers < 1) inputError("layers: at least one layer is needed");
    if (!(mu > 0) || !std::isfinite(mu)) inputError("layers: mu must be positive for the mobilisation |f_t|/(mu f_n)");
    checkLayerBox(snapshot);
    const Vec3 L = snapshot.boxHi - snapshot.boxLo;
    const double volume = L.x * L.y * L.z;

    std::vector<LayerStats> out(static_cast<std::size_t>(layers));
    std::vector<double> psiSum(out.size(), 0.0);
    std::vector<int> slidingCount(out.size(), 0);
    for (std::size_t k = 0; k < out.size(); ++k) {
        out[k].lo = 0.5 * static_cast<double>(k) / layers;
        out[k].hi = 0.5 * static_cast<double>(k + 1) / layers;
    }
    for (const ContactRecord& c : snapshot.contacts) {
        if (c.isWallContact() && !includeWalls) continue;
        const double d = faceDistanceFraction(c.contactPoint[axis], snapshot.boxLo[axis], L[axis]);
        const std::size_t k = std::min(out.size() - 1, static_cast<std::size_t>(d * 2 * layers));
        LayerStats& layer = out[k];
        ++layer.contacts;
        if (c.fn > 0) {
            ++layer.loaded;
            psiSum[k] += norm(c.ft) / (mu * c.fn);
            slidingCount[k] += c.sliding ? 1 : 0;
        }
        const Vec3 f = c.force();
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
                layer.sigma[a][b] += f[a] * c.branch[b];
                layer.fabric[a][b] += c.normal[a] * c.normal[b];
            }
    }
    const double layerVolume = volume / layers;
    for (std::size_t k = 0; k < out.size(); ++k) {
        LayerStats& layer = out[k];
        const double nan = std::numeric_limits<double>::quiet_NaN();
        layer.psi = layer.loaded > 0 ? psiSum[k] / layer.loaded : nan;
        layer.sliding = layer.loaded > 0 ? static_cast<double>(slidingCount[k]) / layer.loaded : nan;
        if (layer.contacts == 0) {
            layer.sDev = layer.axialOverLateral = layer.fabricAxialStar = nan;
            continue;
        }
        for (auto& row : layer.fabric)
            for (double& x : row) x /= layer.contacts;
        const auto& F = layer.fabric;
        layer.fabricAxialStar = F[axis][axis] - 0.5 * (F[(axis + 1) % 3][(axis + 1) % 3] + F[(axis + 2) % 3][(axis + 2) % 3]);
        auto& S = layer.sigma;
        for (int a = 0; a < 3; ++a)
            for (int b = a; b < 3; ++b) {
                const double sym = 0.5 * (S[a][b] + S[b][a]) / layerVolume;
                S[a][b] = S[b][a] = sym;
            }
        layer.p = (S[0][0] + S[1][1] + S[2][2]) / 3;
        double j2 = 0;
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
                const double dev = S[a][b] - (a == b ? layer.p : 0.0);
                j2 += 0.5 * dev * dev;
            }
        layer.sDev = layer.p != 0 ? std::sqrt(3 * j2) / layer.p : nan;
        const double lateral = 0.5 * (S[(axis + 1) % 3][(axis + 1) % 3] + S[(axis + 2) % 3][(axis + 2) % 3]);
        layer.axialOverLateral = lateral != 0 ? S[axis][axis] / lateral : nan;
    }
    return out;
}

std::string layersHeader() {
    return "block,time,strain_axial,layer,d_lo,d_hi,contacts,loaded_contacts,psi,sliding_fraction,p,s_dev,axial_over_lateral,"
           "sigma_xx,sigma_yy,sigma_zz,sigma_xy,sigma_xz,sigma_yz,F_axial_star";
}

std::string layersRow(int block, double time, double axialStrain, int index, const LayerStats& s) {
    std::ostringstream os;
    os << block << ',' << fmt(time) << ',' << fmt(axialStrain) << ',' << index << ',' << fmt(s.lo) << ',' << fmt(s.hi) << ','
       << s.contacts << ',' << s.loaded << ',' << fmt(s.psi) << ',' << fmt(s.sliding) << ',' << fmt(s.p) << ',' << fmt(s.sDev) << ',' << fmt(s.axialOverLateral) << ','
       << fmt(s.sigma[0][0]) << ',' << fmt(s.sigma[1][1]) << ',' << fmt(s.sigma[2][2]) << ',' << fmt(s.sigma[0][1]) << ','
       << fmt(s.sigma[0][2]) << ',' << fmt(s.sigma[1][2]) << ',' << fmt(s.fabricAxialStar);
    return os.str();
}

} // namespace pdpm::tools
