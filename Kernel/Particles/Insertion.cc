#include "Particles/Insertion.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include "Core/DPMBase.h"
#include "Core/Error.h"

namespace pdpm {

std::vector<double> uniformRadii(std::size_t n, double rMin, double rMax, std::mt19937_64& rng) {
    if (!(rMin > 0) || !(rMax >= rMin)) inputError("radii: need 0 < r_min <= r_max");
    std::uniform_real_distribution<double> u(rMin, rMax);
    std::vector<double> r(n);
    for (auto& x : r) x = rMin == rMax ? rMin : u(rng);
    std::sort(r.begin(), r.end(), std::greater<>());
    return r;
}

void insertRandom(DPMBase& d, const std::vector<double>& radii, const Vec3& lo, const Vec3& hi, double vMax,
                  int species, long maxAttempts) {
    if (radii.empty()) return;
    auto& rng = d.random();
    const PeriodicBox& box = d.box();
    const double rmax = *std::max_element(radii.begin(), radii.end());
    const double cell = 2 * rmax;
    int nc[3];
    for (int a = 0; a < 3; ++a) nc[a] = std::max(1, static_cast<int>((hi[a] - lo[a]) / cell));
    // Hash grid of already placed particles (including existing ones).
    std::unordered_multimap<long, std::size_t> grid;
    auto key = [&](const Vec3& x, int dx, int dy, int dz) {
        long c[3];
        const int dd[3] = {dx, dy, dz};
        for (int a = 0; a < 3; ++a) {
            long ci = static_cast<long>(std::floor((x[a] - lo[a]) / (hi[a] - lo[a]) * nc[a])) + dd[a];
            if (box.periodic(a)) ci = ((ci % nc[a]) + nc[a]) % nc[a];
            c[a] = ci;
        }
        return (c[0] * 1000003L + c[1]) * 1000033L + c[2];
    };
    const ParticleData& P = d.particles();
    for (std::size_t i = 0; i < P.size(); ++i) grid.emplace(key(P.x[i], 0, 0, 0), i);
    std::uniform_real_distribution<double> u01(0, 1);
    for (double r : radii) {
        bool placed = false;
        for (long attempt = 0; attempt < maxAttempts && !placed; ++attempt) {
            Vec3 x;
            for (int a = 0; a < 3; ++a) {
                const double margin = box.periodic(a) ? 0.0 : r;
                x[a] = lo[a] + margin + u01(rng) * (hi[a] - lo[a] - 2 * margin);
            }
            bool ok = true;
            for (int dx = -1; dx <= 1 && ok; ++dx)
                for (int dy = -1; dy <= 1 && ok; ++dy)
                    for (int dz = -1; dz <= 1 && ok; ++dz) {
                        auto range = grid.equal_range(key(x, dx, dy, dz));
                        for (auto it = range.first; it != range.second && ok; ++it) {
                            Vec3 dd = x - P.x[it->second];
                            box.minimumImage(dd);
                            const double s = r + P.r[it->second];
                            if (norm2(dd) < s * s) ok = false;
                        }
                    }
            if (!ok) continue;
            Vec3 v;
            if (vMax > 0) {
                // random direction, magnitude uniform in [0, vMax]
                const double cz = 2 * u01(rng) - 1, phi = 2 * std::numbers::pi * u01(rng);
                const double sz = std::sqrt(1 - cz * cz), mag = vMax * u01(rng);
                v = {mag * sz * std::cos(phi), mag * sz * std::sin(phi), mag * cz};
            }
            const std::size_t k = d.addParticle(x, r, species, v);
            grid.emplace(key(x, 0, 0, 0), k);
            placed = true;
        }
        if (!placed)
            inputError("random insertion failed: no free place for a sphere of radius " + std::to_string(r) +
                       " m (density too high; insert into a larger box and compress)");
    }
}

std::size_t insertOnGrid(DPMBase& d, const std::vector<double>& radii, const Vec3& lo, const Vec3& hi, double spacing,
                         int species) {
    if (!(spacing > 0)) inputError("grid insertion: spacing must be > 0");
    std::size_t k = 0;
    for (double z = lo.z + 0.5 * spacing; z <= hi.z - 0.5 * spacing + 1e-12 && k < radii.size(); z += spacing)
        for (double y = lo.y + 0.5 * spacing; y <= hi.y - 0.5 * spacing + 1e-12 && k < radii.size(); y += spacing)
            for (double x = lo.x + 0.5 * spacing; x <= hi.x - 0.5 * spacing + 1e-12 && k < radii.size(); x += spacing) {
                d.addParticle({x, y, z}, radii[k], species);
                ++k;
            }
    return k;
}

std::vector<Vec3> staggeredColumn(std::size_t n, double spacing, double lx, double radius, double clearance) {
    const bool disc = radius > 0;
    const double s = spacing, off = disc ? -radius : 0;
    const int nxy = std::max(1, static_cast<int>(std::floor(lx / s - (disc ? 0 : 0.5))));
    std::vector<Vec3> pts;
    pts.reserve(n);
    int emptyLayers = 0;  // an even and an odd layer without points: nothing will ever fit
    for (int layer = 0; pts.size() < n; ++layer) {
        const std::size_t before = pts.size();
        const double sh = (layer % 2) * 0.5 * s;
        for (int ix = 0; ix < nxy; ++ix)
            for (int iy = 0; iy < nxy && pts.size() < n; ++iy) {
                const Vec3 x{off + (ix + 0.5) * s + sh, off + (iy + 0.5) * s + sh, (layer + 0.5) * s};
                if (!disc || std::hypot(x.x, x.y) <= radius - clearance) pts.push_back(x);
            }
        emptyLayers = pts.size() == before ? emptyLayers + 1 : 0;
        if (emptyLayers >= 2) inputError("pour column: no sphere of spacing " + std::to_string(s) + " m fits the cross-section");
    }
    return pts;
}

} // namespace pdpm
