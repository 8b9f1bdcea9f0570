#include "CoarseGraining.h"

#include "Core/Error.h"
#include "OutputFiles.h"

#include <algorithm>
#include <new>
#include <cmath>
#include <numbers>
#include <ostream>

namespace pdpm::tools {

namespace {

// ---- channels ---------------------------------------------------------------------------------
enum PartChannel { RHO = 0, PX, PY, PZ, MVV0, NUM = MVV0 + 6, VOL, CDEN, FAB0, NPART = FAB0 + 6 };
constexpr int NCONT = 9;

// ---- 1D kernels ---------------------------------------------------------------------------------
struct Kernel1D {
    CgKernel kind;
    double w, c, gaussNorm;
    Kernel1D(CgKernel k, double width) : kind(k), w(width) {
        c = kind == CgKernel::Gaussian ? 3 * w : w * std::sqrt(10.5);
        gaussNorm = std::erf(3 / std::numbers::sqrt2);
    }
    /// Cumulative distribution of the normalised 1D kernel.
    double cdf(double t) const {
        if (t <= -c) return 0;
        if (t >= c) return 1;
        if (kind == CgKernel::Gaussian) return 0.5 + 0.5 * std::erf(t / (std::numbers::sqrt2 * w)) / gaussNorm;
        const double u = std::abs(t) / c;
        const double g = 1.25 * u * (1 + u * u * (-2 + u * (2 - 0.6 * u)));
        return t < 0 ? 0.5 - g : 0.5 + g;
    }
};

// ---- Gauss-Legendre on [0,1] ----------------------------------------------------------------------
struct GaussRule {
    std::vector<double> s, a;
};
GaussRule gaussLegendre(int n) {
    GaussRule r;
    r.s.resize(n);
    r.a.resize(n);
    for (int k = 0; k < n; ++k) {
        double x = std::cos(std::numbers::pi * (k + 0.75) / (n + 0.5)), dp = 1;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1, p1 = x;
            for (int l = 2; l <= n; ++l) {
                const double p2 = ((2 * l - 1) * x * p1 - (l - 1) * p0) / l;
                p0 = p1;
                p1 = p2;
            }
            if (n == 1) { p1 = x; p0 = 1; }
            dp = n * (x * p1 - p0) / (x * x - 1);
            const double dx = p1 / dp;
            x -= dx;
            if (std::abs(dx) < 1e-16) break;
        }
        double p0 = 1, p1 = x;
        for (int l = 2; l <= n; ++l) {
            const double p2 = ((2 * l - 1) * x * p1 - (l - 1) * p0) / l;
            p0 = p1;
            p1 = p2;
        }
        dp = n * (x * p1 - p0) / (x * x - 1);
        r.s[k] = 0.5 * (1 - x);
        r.a[k] = 1.0 / ((1 - x * x) * dp * dp);  // = (2/((1-x²)P'²)) / 2
    }
    return r;
}

// ---- grid axes ------------------------------------------------------------------------------------
struct Axis {
    enum Kind { Cart, Avg, Radial, Azim } kind = Cart;
    int n = 1;
    double lo = 0, h = 1;
    bool periodic = false;
    double domLo = 0, domHi = 1;
    int cap = 1;
};

struct Weights {
    std::vector<std::pair<int, double>> tmp;
};

/// Cell-averaged kernel weights (per unit cell measure) of a point at coordinate x on one axis.
void axisWeights(const Axis& ax, const Kernel1D& K, bool renorm, double x, int* idx, double* w, int& cnt,
                 std::vector<std::pair<int, double>>& tmp) {
    cnt = 0;
    switch (ax.kind) {
    case Axis::Azim: idx[0] = 0; w[0] = 1; cnt = 1; return;
    case Axis::Avg: idx[0] = 0; w[0] = 1 / (ax.domHi - ax.domLo); cnt = 1; return;
    case Axis::Radial: {
        const double R = x;
        double norm = 1;
        if (renorm) {
            const double F = K.cdf(ax.domHi - R) - K.cdf(-ax.domHi - R);
            if (!(F > 0)) return;
            norm = 1 / F;
        }
        // clamped in double before the conversion: a kernel far wider than a cell would overflow an int
        const int i0 = R < K.c ? 0 : int(std::max(0.0, std::floor((R - K.c) / ax.h)));
        const int i1 = int(std::min<double>(ax.n - 1, std::floor((R + K.c) / ax.h)));
        for (int i = i0; i <= i1; ++i) {
            const double ra = i * ax.h, rb = ra + ax.h;
            const double frac = K.cdf(rb - R) - K.cdf(ra - R) + K.cdf(-ra - R) - K.cdf(-rb - R);
            if (frac == 0) continue;
            idx[cnt] = i;
            w[cnt] = frac * norm / (std::numbers::pi * (rb * rb - ra * ra));
            ++cnt;
        }
        return;
    }
    case Axis::Cart: break;
    }
    double norm = 1;
    if (!ax.periodic && renorm) {
        const double F = K.cdf(ax.domHi - x) - K.cdf(ax.domLo - x);
        if (!(F > 0)) return;
        norm = 1 / F;
    }
    long kmin = 0, kmax = 0;
    const double L = ax.domHi - ax.domLo;
    const double hi = ax.lo + ax.n * ax.h;
    if (ax.periodic) {
        kmin = long(std::floor((ax.lo - K.c - x) / L));
        kmax = long(std::ceil((hi + K.c - x) / L));
    }
    tmp.clear();
    for (long k = kmin; k <= kmax; ++k) {
        const double xs = x + double(k) * L;
        if (xs + K.c <= ax.lo || xs - K.c >= hi) continue;
        const int i0 = int(std::max(0.0, std::floor((xs - K.c - ax.lo) / ax.h)));
        const int i1 = int(std::min<double>(ax.n - 1, std::floor((xs + K.c - ax.lo) / ax.h)));
        auto edge = [&](int i) {  // cell edge i, clipped to the domain in non-periodic directions
            const double e = ax.lo + i * ax.h;
            return ax.periodic ? e : std::clamp(e, ax.domLo, ax.domHi);
        };
        double Fa = K.cdf(edge(i0) - xs);  // each edge's CDF is evaluated once
        for (int i = i0; i <= i1; ++i) {
            const double Fb = K.cdf(edge(i + 1) - xs);
            const double f = Fb - Fa;
            Fa = Fb;
            if (f != 0) tmp.emplace_back(i, f * norm / ax.h);
        }
    }
    if (kmax - kmin > 1 && tmp.size() > 1) {
        std::stable_sort(tmp.begin(), tmp.end(), [](auto& p, auto& q) { return p.first < q.first; });
        std::size_t o = 0;
        for (std::size_t k = 1; k < tmp.size(); ++k) {
            if (tmp[k].first == tmp[o].first) tmp[o].second += tmp[k].second;
            else tmp[++o] = tmp[k];
        }
        tmp.resize(o + 1);
    }
    if (int(tmp.size()) > ax.cap) throw std::logic_error("CG stencil larger than its capacity");
    for (auto& [i, v] : tmp) {
        idx[cnt] = i;
        w[cnt] = v;
        ++cnt;
    }
}

/// Items: each has quadrature points (position, weight) sharing one vector of channel values.
struct ItemSet {
    int nch = 0;
    std::vector<int> qBegin{0};
    std::vector<double> qa;
    std::vector<Vec3> qpos;
    std::vector<double> vals;
    std::size_t size() const { return qBegin.size() - 1; }
    void addPoint(const Vec3& p, double a) { qpos.push_back(p); qa.push_back(a); }
    void close() { qBegin.push_back(int(qpos.size())); }
};

struct Frame3 {
    Vec3 e[3];  // rows: local axes
};

} // namespace

struct CoarseGrainer::Impl {
    static void coords(const CoarseGrainer& cg, const Vec3& p, double c[3]) {
        if (!cg.cfg_.cylindrical) {
            c[0] = p.x; c[1] = p.y; c[2] = p.z;
            return;
        }
        const int a = cg.cfg_.axis, b = a == 0 ? 1 : 0, d = a == 2 ? 1 : 2;  // the other two axes, in x, y, z order
        const double u = p[b] - cg.centre_[0], v = p[d] - cg.centre_[1];
        c[0] = std::sqrt(u * u + v * v);
        c[1] = 0;
        c[2] = p[a];
    }
    static Frame3 frame(const CoarseGrainer& cg, const Vec3& p) {
        Frame3 f;
        const int a = cg.cfg_.axis, b = a == 0 ? 1 : 0, d = a == 2 ? 1 : 2;  // the other two axes, in x, y, z order
        Vec3 ez, er;
        ez[a] = 1;
        const double u = p[b] - cg.centre_[0], v = p[d] - cg.centre_[1];
        const double R = std::sqrt(u * u + v * v);
        if (R > 0) { er[b] = u / R; er[d] = v / R; }
        else er[b] = 1;
        f.e[0] = er;
        f.e[1] = cross(ez, er);
        f.e[2] = ez;
        return f;
    }

    static void accumulate(const CoarseGrainer& cg, const std::vector<Axis>& axes, const ItemSet& items,
                           std::vector<double>& fields /* channel-major */) {
        const Kernel1D K(cg.cfg_.kernel, cg.cfg_.width);
        const bool renorm = cg.cfg_.walls == WallTreatment::Renormalize;
        const CgGeometry& g = cg.geom_;
        const std::size_t ncell = g.cells();
        const int nch = items.nch;
        // plane axis: the largest
        int P = 2;
        for (int a = 1; a >= 0; --a)
            if (g.n[a] > g.n[P]) P = a;
        const int A = P == 0 ? 1 : 0, B = P == 2 ? 1 : 2;
        const std::size_t stride[3] = {1, std::size_t(g.n[0]), std::size_t(g.n[0]) * g.n[1]};
        const int nA = g.n[A], nB = g.n[B], nP = g.n[P];
        int capMax = 1;
        for (const Axis& ax : axes) capMax = std::max(capMax, ax.cap);

        const std::size_t nItems = items.size();
        const std::size_t batch = 8192;
        std::vector<int> widx, wcnt;
        std::vector<double> wval;
        std::vector<std::vector<int>> bucket(nP);
        for (std::size_t b0 = 0; b0 < nItems; b0 += batch) {
            const std::size_t b1 = std::min(nItems, b0 + batch);
            const int q0 = items.qBegin[b0], q1 = items.qBegin[b1];
            const std::size_t nq = std::size_t(q1 - q0);
            widx.assign(nq * 3 * capMax, 0);
            wval.assign(nq * 3 * capMax, 0.0);
            wcnt.assign(nq * 3, 0);
#pragma omp parallel
            {
                std::vector<std::pair<int, double>> tmp;
#pragma omp for schedule(static)
                for (long q = 0; q < long(nq); ++q) {
                    double c[3];
                    coords(cg, items.qpos[q0 + q], c);
                    for (int a = 0; a < 3; ++a) {
                        const std::size_t o = (std::size_t(q) * 3 + a) * capMax;
                        axisWeights(axes[a], K, renorm, c[a], &widx[o], &wval[o], wcnt[q * 3 + a], tmp);
                    }
                }
            }
            for (auto& bk : bucket) bk.clear();
            std::vector<int> planes;
            for (std::size_t it = b0; it < b1; ++it) {
                planes.clear();
                for (int q = items.qBegin[it]; q < items.qBegin[it + 1]; ++q) {
                    const std::size_t qq = std::size_t(q - q0);
                    bool empty = false;
                    for (int a = 0; a < 3; ++a) empty = empty || wcnt[qq * 3 + a] == 0;
                    if (empty) continue;
                    const std::size_t o = (qq * 3 + P) * capMax;
                    for (int e = 0; e < wcnt[qq * 3 + P]; ++e) planes.push_back(widx[o + e]);
                }
                std::sort(planes.begin(), planes.end());
                planes.erase(std::unique(planes.begin(), planes.end()), planes.end());
                for (int k : planes) bucket[k].push_back(int(it));
            }
            bool outOfMemory = false;  // an exception must not leave a parallel region: thrown after it
#pragma omp parallel
            {
                std::vector<double> Wp;
                std::vector<char> mark;
                std::vector<int> touched;
                bool ok = true;
                try {
                    Wp.assign(std::size_t(nA) * nB, 0.0);
                    mark.assign(std::size_t(nA) * nB, 0);
                } catch (const std::bad_alloc&) {
                    ok = false;
#pragma omp atomic write
                    outOfMemory = true;
                }
#pragma omp for schedule(dynamic, 1)
                for (int k = 0; k < nP; ++k) {
                    if (!ok) continue;
                    for (int it : bucket[k]) {
                        touched.clear();
                        for (int q = items.qBegin[it]; q < items.qBegin[it + 1]; ++q) {
                            const std::size_t qq = std::size_t(q - q0);
                            const std::size_t oP = (qq * 3 + P) * capMax, oA = (qq * 3 + A) * capMax,
                                              oB = (qq * 3 + B) * capMax;
                            double wP = 0;
                            for (int e = 0; e < wcnt[qq * 3 + P]; ++e)
                                if (widx[oP + e] == k) wP = wval[oP + e];
                            if (wP == 0) continue;
                            wP *= items.qa[q];
                            for (int eb = 0; eb < wcnt[qq * 3 + B]; ++eb) {
                                const double wb = wP * wval[oB + eb];
                                const int rowOff = widx[oB + eb] * nA;
                                for (int ea = 0; ea < wcnt[qq * 3 + A]; ++ea) {
                                    const int id = rowOff + widx[oA + ea];
                                    if (!mark[id]) { mark[id] = 1; touched.push_back(id); }
                                    Wp[id] += wb * wval[oA + ea];
                                }
                            }
                        }
                        const double* v = &items.vals[std::size_t(it) * nch];
                        for (int id : touched) {
                            const double W = Wp[id];
                            Wp[id] = 0;
                            mark[id] = 0;
                            const std::size_t cell = std::size_t(k) * stride[P] + std::size_t(id % nA) * stride[A] +
                                                     std::size_t(id / nA) * stride[B];
                            for (int ch = 0; ch < nch; ++ch) fields[std::size_t(ch) * ncell + cell] += W * v[ch];
                        }
                    }
                }
            }
            if (outOfMemory) throw std::bad_alloc();
        }
    }

    static std::vector<Axis> axes(const CoarseGrainer& cg) {
        const Kernel1D K(cg.cfg_.kernel, cg.cfg_.width);
        std::vector<Axis> ax(3);
        const CgGeometry& g = cg.geom_;
        for (int a = 0; a < 3; ++a) {
            Axis& x = ax[a];
            x.n = g.n[a];
            x.h = g.spacing[a];
            x.lo = g.centres[a][0] - 0.5 * x.h;
            if (cg.cfg_.cylindrical) {
                if (a == 0) { x.kind = Axis::Radial; x.domLo = 0; x.domHi = cg.rmax_; }
                else if (a == 1) x.kind = Axis::Azim;
                else {
                    const int c = cg.cfg_.axis;
                    x.kind = g.averaged[2] ? Axis::Avg : Axis::Cart;
                    x.periodic = cg.periodic_[c];
                    x.domLo = cg.domLo_[c];
                    x.domHi = cg.domHi_[c];
                }
            } else {
                x.kind = g.averaged[a] ? Axis::Avg : Axis::Cart;
                x.periodic = cg.periodic_[a];
                x.domLo = cg.domLo_[a];
                x.domHi = cg.domHi_[a];
            }
            // (in double: a kernel far wider than a cell would overflow an int)
            x.cap = (x.kind == Axis::Avg || x.kind == Axis::Azim) ? 1
                                                                   : int(std::min<double>(x.n, std::ceil(2 * K.c / x.h) + 3));
            // Every periodic image within the kernel's reach is summed, per particle and quadrature
            // point: a kernel thousands of periods wide would run for hours to give a uniform field.
            if (x.kind == Axis::Cart && x.periodic && K.c > 1000 * (x.domHi - x.domLo))
                inputError("--width " + fmt(cg.cfg_.width) + " m: the kernel spans more than 1000 periods of the " +
                           std::string(1, "xyz"[cg.cfg_.cylindrical ? cg.cfg_.axis : a]) + " axis (length " +
                           fmt(x.domHi - x.domLo) + " m); the field would be uniform, use a smaller width");
        }
        return ax;
    }
};

// ---- CoarseGrainer ------------------------------------------------------------------------------

double cgCells(const CgConfig& cfg) {
    const auto n = [&](int a) { return double(std::max(cfg.n[a], 1)); };
    return cfg.cylindrical ? n(0) * n(2) : n(0) * n(1) * n(2);
}

CoarseGrainer::CoarseGrainer(const CgConfig& cfg) : cfg_(cfg) {
    if (!(cfg_.width > 0) || !std::isfinite(cfg_.width))
        inputError("kernel width must be finite and > 0 (got " + fmt(cfg_.width) + ")");
    for (int a = 0; a < 3; ++a)
        if (cfg_.n[a] < 0) inputError("grid sizes must be ≥ 0");
    if (cgCells(cfg_) > double(kCgMaxCells))
        inputError("grid of " + fmt(cgCells(cfg_)) + " cells: more than the limit of " + fmt(double(kCgMaxCells)) +
                   " cells (about 1.5 kB each)");
    if (cfg_.cylindrical) {
        if (cfg_.n[0] <= 0) inputError("empty grid: the cylindrical grid needs at least one radial cell");
        if (cfg_.axis < 0 || cfg_.axis > 2) inputError("cylinder axis must be x, y or z");
        if (cfg_.rmax < 0) inputError("rmax must be ≥ 0");
    } else if (cfg_.n[0] == 0 && cfg_.n[1] == 0 && cfg_.n[2] == 0) {
        inputError("empty grid: give at least one of the grid sizes (nx, ny, nz) > 0");
    }
    if (cfg_.quadratureMax < 1) inputError("quadratureMax must be ≥ 1");
}

double CoarseGrainer::cutoff() const { return Kernel1D(cfg_.kernel, cfg_.width).c; }

void CoarseGrainer::reset() {
    count_ = 0;
    timeSum_ = 0;
    anyContacts_ = false;
    std::fill(partSum_.begin(), partSum_.end(), 0.0);
    std::fill(contSum_.begin(), contSum_.end(), 0.0);
}

void CoarseGrainer::setupGeometry(const ParticleSnapshot& s) {
    Vec3 lo = cfg_.domainSet ? cfg_.domainLo : s.boxLo, hi = cfg_.domainSet ? cfg_.domainHi : s.boxHi;
    for (int a = 0; a < 3; ++a) {
        if (!(hi[a] > lo[a])) inputError("the domain has non-positive extent along " + std::string(1, "xyz"[a]));
        domLo_[a] = lo[a];
        domHi_[a] = hi[a];
        periodic_[a] = s.periodic[a];
    }
    CgGeometry& g = geom_;
    g = CgGeometry{};
    g.cylindrical = cfg_.cylindrical;
    g.axis = cfg_.axis;
    auto cartesian = [&](int gridAxis, int coord, int n) {
        double a = domLo_[coord], b = domHi_[coord];
        if (cfg_.regionSet && n > 0) {
            a = cfg_.regionLo[coord];
            b = cfg_.regionHi[coord];
            if (!(b > a)) inputError(std::string("empty grid: region along ") + "xyz"[coord] + " has hi ≤ lo");
        }
        if (n == 0) {
            g.averaged[gridAxis] = true;
            g.n[gridAxis] = 1;
            g.spacing[gridAxis] = b - a;
            g.centres[gridAxis] = {0.5 * (a + b)};
            return;
        }
        g.n[gridAxis] = n;
        g.spacing[gridAxis] = (b - a) / n;
        g.centres[gridAxis].resize(n);
        for (int i = 0; i < n; ++i) g.centres[gridAxis][i] = a + (i + 0.5) * g.spacing[gridAxis];
    };
    if (!cfg_.cylindrical) {
        g.names = {"x", "y", "z"};
        for (int a = 0; a < 3; ++a) cartesian(a, a, cfg_.n[a]);
    } else {
        g.names = {"r", "theta", std::string(1, "xyz"[cfg_.axis])};
        const int a = cfg_.axis, b = a == 0 ? 1 : 0, d = a == 2 ? 1 : 2;  // the other two axes, in x, y, z order
        centre_[0] = cfg_.centreSet ? cfg_.centre[0] : 0.5 * (domLo_[b] + domHi_[b]);
        centre_[1] = cfg_.centreSet ? cfg_.centre[1] : 0.5 * (domLo_[d] + domHi_[d]);
        rmax_ = cfg_.rmax > 0 ? cfg_.rmax : 0.5 * std::min(domHi_[b] - domLo_[b], domHi_[d] - domLo_[d]);
        g.n[0] = cfg_.n[0];
        g.spacing[0] = rmax_ / cfg_.n[0];
        g.centres[0].resize(cfg_.n[0]);
        for (int i = 0; i < cfg_.n[0]; ++i) g.centres[0][i] = (i + 0.5) * g.spacing[0];
        g.averaged[1] = true;
        g.n[1] = 1;
        g.spacing[1] = 2 * std::numbers::pi;
        g.centres[1] = {0.0};
        cartesian(2, a, cfg_.n[2]);
    }
    partSum_.assign(std::size_t(NPART) * g.cells(), 0.0);
    contSum_.assign(std::size_t(NCONT) * g.cells(), 0.0);
    haveGeometry_ = true;
}

void CoarseGrainer::add(const ParticleSnapshot& s, const ContactSnapshot* contacts) {
    const std::size_t N = s.size();
    if (s.v.size() != N || s.r.size() != N || s.m.size() != N)
        inputError("particle snapshot arrays have inconsistent lengths");
    if (!haveGeometry_) setupGeometry(s);
    const bool cyl = cfg_.cylindrical;

    // per-particle contact sums (fabric Σ n n, contact count)
    std::vector<Sym6> nn;
    std::vector<double> ncont(N, 0.0);
    const bool useContacts = contacts != nullptr;
    if (useContacts) {
        nn.assign(N, Sym6{});
        auto addNN = [&](std::size_t p, const Vec3& n) {
            Sym6& t = nn[p];
            t[0] += n.x * n.x; t[1] += n.x * n.y; t[2] += n.x * n.z;
            t[3] += n.y * n.y; t[4] += n.y * n.z; t[5] += n.z * n.z;
            ncont[p] += 1;
        };
        for (const ContactRecord& c : contacts->contacts) {
            if (c.i < 0 || std::size_t(c.i) >= N || (c.j >= 0 && std::size_t(c.j) >= N))
                inputError("contact (" + std::to_string(c.i) + ", " + std::to_string(c.j) + ") refers to a particle beyond N = " +
                           std::to_string(N) + " (contacts and particles from different runs?)");
            addNN(std::size_t(c.i), c.normal);
            if (c.j >= 0) addNN(std::size_t(c.j), c.normal);
        }
    } else if (!s.coordination.empty()) {
        for (std::size_t p = 0; p < N; ++p) ncont[p] = s.coordination[p];
    }

    // particle items
    ItemSet items;
    items.nch = NPART;
    items.vals.resize(N * NPART);
    items.qpos.reserve(N);
    for (std::size_t p = 0; p < N; ++p) {
        items.addPoint(s.x[p], 1.0);
        items.close();
        double* v = &items.vals[p * NPART];
        const double m = s.m[p];
        Vec3 vel = s.v[p];
        Sym6 fab = useContacts ? nn[p] : Sym6{};
        if (cyl) {
            const Frame3 f = Impl::frame(*this, s.x[p]);
            vel = {dot(f.e[0], vel), dot(f.e[1], vel), dot(f.e[2], vel)};
            if (useContacts) {
                const Sym6& t = nn[p];
                auto T = [&](int a, int b) {
                    static const int map[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
                    return t[map[a][b]];
                };
                auto rot = [&](int a, int b) {
                    double sum = 0;
                    for (int k = 0; k < 3; ++k)
                        for (int l = 0; l < 3; ++l) sum += f.e[a][k] * T(k, l) * f.e[b][l];
                    return sum;
                };
                fab = {rot(0, 0), rot(0, 1), rot(0, 2), rot(1, 1), rot(1, 2), rot(2, 2)};
            }
        }
        const double vol = 4.0 / 3.0 * std::numbers::pi * s.r[p] * s.r[p] * s.r[p];
        v[RHO] = m;
        v[PX] = m * vel.x; v[PY] = m * vel.y; v[PZ] = m * vel.z;
        v[MVV0 + 0] = m * vel.x * vel.x; v[MVV0 + 1] = m * vel.x * vel.y; v[MVV0 + 2] = m * vel.x * vel.z;
        v[MVV0 + 3] = m * vel.y * vel.y; v[MVV0 + 4] = m * vel.y * vel.z; v[MVV0 + 5] = m * vel.z * vel.z;
        v[NUM] = 1;
        v[VOL] = vol;
        v[CDEN] = ncont[p];
        for (int k = 0; k < 6; ++k) v[FAB0 + k] = vol * fab[k];
    }
    const std::vector<Axis> axes = Impl::axes(*this);
    Impl::accumulate(*this, axes, items, partSum_);

    if (useContacts) {
        anyContacts_ = true;
        ItemSet ci;
        ci.nch = NCONT;
        std::vector<GaussRule> rules(cfg_.quadratureMax + 1);
        for (int q = 1; q <= cfg_.quadratureMax; ++q) rules[q] = gaussLegendre(q);
        // Gauss points along the branch: resolve both the kernel width and the grid spacing (the
        // cut-off makes the kernel discontinuous; cell averaging smooths it on the scale of a cell).
        double hmin = cfg_.width;
        for (int a = 0; a < 3; ++a)
            if (!geom_.averaged[a]) hmin = std::min(hmin, geom_.spacing[a]);
        for (const ContactRecord& c : contacts->contacts) {
            const Vec3 f = c.force(), l = c.branch, xi = s.x[std::size_t(c.i)];
            const int nq = std::clamp(1 + int(std::ceil(1.5 * norm(l) / hmin)), 1, cfg_.quadratureMax);
            const GaussRule& gr = rules[nq];
            auto push = [&](const Vec3& F, const Vec3& Lv) {
                const double vals[9] = {F.x * Lv.x, F.x * Lv.y, F.x * Lv.z, F.y * Lv.x, F.y * Lv.y,
                                        F.y * Lv.z, F.z * Lv.x, F.z * Lv.y, F.z * Lv.z};
                ci.vals.insert(ci.vals.end(), vals, vals + 9);
            };
            if (!cyl) {
                for (int q = 0; q < nq; ++q) ci.addPoint(xi - gr.s[q] * l, gr.a[q]);
                ci.close();
                push(f, l);
            } else {
                for (int q = 0; q < nq; ++q) {
                    const Vec3 pos = xi - gr.s[q] * l;
                    const Frame3 fr = Impl::frame(*this, pos);
                    ci.addPoint(pos, gr.a[q]);
                    ci.close();
                    push({dot(fr.e[0], f), dot(fr.e[1], f), dot(fr.e[2], f)},
                         {dot(fr.e[0], l), dot(fr.e[1], l), dot(fr.e[2], l)});
                }
            }
        }
        Impl::accumulate(*this, axes, ci, contSum_);
    }
    ++count_;
    if (useContacts) ++contactCount_;
    timeSum_ += s.time;
}

CgResult CoarseGrainer::result() const {
    if (count_ == 0) inputError("no snapshots to coarse-grain");
    CgResult r;
    r.geom = geom_;
    r.snapshots = count_;
    r.contactSnapshots = contactCount_;
    r.time = timeSum_ / count_;
    r.hasContacts = anyContacts_;
    r.averagedMeasure = 1;
    for (int a = 0; a < 3; ++a)
        if (geom_.averaged[a] && !(geom_.cylindrical && a == 1)) r.averagedMeasure *= geom_.spacing[a];
    const std::size_t nc = geom_.cells();
    const double inv = 1.0 / count_;
    // contact stress and fabric: over the snapshots that came with contacts (a window may hold
    // particle snapshots without a contact block; zeros from those would dilute the average)
    const double invC = contactCount_ > 0 ? 1.0 / contactCount_ : 0.0;
    auto P = [&](int ch, std::size_t c) { return partSum_[std::size_t(ch) * nc + c] * inv; };
    r.rho.resize(nc); r.momentum.resize(nc); r.velocity.resize(nc); r.kineticStress.resize(nc);
    r.contactStress.assign(nc, Tensor9{}); r.fabric.resize(nc); r.numberDensity.resize(nc);
    r.volumeFraction.resize(nc); r.contactDensity.resize(nc); r.coordination.resize(nc);
    for (std::size_t c = 0; c < nc; ++c) {
        const double rho = P(RHO, c);
        const Vec3 p{P(PX, c), P(PY, c), P(PZ, c)};
        r.rho[c] = rho;
        r.momentum[c] = p;
        r.velocity[c] = rho > 0 ? p / rho : Vec3{};
        static const int ab[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
        for (int k = 0; k < 6; ++k) {
            const double mvv = P(MVV0 + k, c);
            r.kineticStress[c][k] = rho > 0 ? mvv - p[ab[k][0]] * p[ab[k][1]] / rho : 0.0;
            r.fabric[c][k] = partSum_[std::size_t(FAB0 + k) * nc + c] * invC;
        }
        r.numberDensity[c] = P(NUM, c);
        r.volumeFraction[c] = P(VOL, c);
        r.contactDensity[c] = P(CDEN, c);
        r.coordination[c] = r.numberDensity[c] > 0 ? r.contactDensity[c] / r.numberDensity[c] : 0.0;
        for (int k = 0; k < 9; ++k) r.contactStress[c][k] = contSum_[std::size_t(k) * nc + c] * invC;
    }
    return r;
}

Tensor9 CgResult::stress(std::size_t c) const {
    Tensor9 t = contactStress[c];
    const Sym6& k = kineticStress[c];
    const int m[9] = {0, 1, 2, 1, 3, 4, 2, 4, 5};
    for (int i = 0; i < 9; ++i) t[i] += k[m[i]];
    return t;
}

double CgResult::pressure(std::size_t c) const {
    const Tensor9 t = stress(c);
    return (t[0] + t[4] + t[8]) / 3;
}

CgResult coarseGrain(const CgConfig& cfg, const ParticleSnapshot& particles, const ContactSnapshot* contacts) {
    CoarseGrainer cg(cfg);
    cg.add(particles, contacts);
    return cg.result();
}

std::vector<double> massPerLength(const CgResult& r) {
    std::vector<double> out(r.rho.size());
    for (std::size_t c = 0; c < out.size(); ++c) out[c] = r.rho[c] * r.averagedMeasure;
    return out;
}

std::vector<double> heightProfile(const CgResult& now, const CgResult& initial, double hIni) {
    if (now.rho.size() != initial.rho.size()) inputError("height profile: grids differ between snapshots");
    std::vector<double> h(now.rho.size(), 0.0);
    for (std::size_t c = 0; c < h.size(); ++c)
        if (initial.rho[c] > 0) h[c] = now.rho[c] / initial.rho[c] * hIni;
    return h;
}

// ---- output -------------------------------------------------------------------------------------

std::vector<std::string> cgCsvColumns(const CgResult& r) {
    std::vector<std::string> cols;
    for (int a = 0; a < 3; ++a)
        if (!r.geom.averaged[a]) cols.push_back(r.geom.names[a]);
    const std::string e[3] = {r.geom.names[0], r.geom.names[1], r.geom.names[2]};
    cols.push_back("rho");
    for (int a = 0; a < 3; ++a) cols.push_back("p_" + e[a]);
    for (int a = 0; a < 3; ++a) cols.push_back("V_" + e[a]);
    static const int ab[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
    for (auto& x : ab) cols.push_back("sk_" + e[x[0]] + e[x[1]]);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) cols.push_back("sc_" + e[a] + e[b]);
    cols.push_back("pressure");
    for (auto& x : ab) cols.push_back("F_" + e[x[0]] + e[x[1]]);
    cols.push_back("n");
    cols.push_back("nu");
    cols.push_back("contacts");
    cols.push_back("Z");
    cols.push_back("mass_per_length");
    return cols;
}

void writeCgCsv(const std::string& path, const CgResult& r, const std::vector<double>& height) {
    std::vector<std::string> cols = cgCsvColumns(r);
    if (!height.empty()) cols.push_back("h");
    const auto mpl = massPerLength(r);
    writeFileAtomically(path, [&](std::ostream& os) {
        os << "# pdpm-cg time " << fmt(r.time) << " snapshots " << r.snapshots << "\n";
        for (std::size_t k = 0; k < cols.size(); ++k) os << (k ? "," : "") << cols[k];
        os << "\n";
        const CgGeometry& g = r.geom;
        for (int k = 0; k < g.n[2]; ++k)
            for (int j = 0; j < g.n[1]; ++j)
                for (int i = 0; i < g.n[0]; ++i) {
                    const std::size_t c = g.index(i, j, k);
                    const int ijk[3] = {i, j, k};
                    bool first = true;
                    auto put = [&](double x) {
                        if (!first) os << ',';
                        os << fmt(x);
                        first = false;
                    };
                    for (int a = 0; a < 3; ++a)
                        if (!g.averaged[a]) put(g.centres[a][ijk[a]]);
                    put(r.rho[c]);
                    for (int a = 0; a < 3; ++a) put(r.momentum[c][a]);
                    for (int a = 0; a < 3; ++a) put(r.velocity[c][a]);
                    for (double x : r.kineticStress[c]) put(x);
                    for (double x : r.contactStress[c]) put(x);
                    put(r.pressure(c));
                    for (double x : r.fabric[c]) put(x);
                    put(r.numberDensity[c]);
                    put(r.volumeFraction[c]);
                    put(r.contactDensity[c]);
                    put(r.coordination[c]);
                    put(mpl[c]);
                    if (!height.empty()) put(height[c]);
                    os << '\n';
                }
    });
}

void writeCgVti(const std::string& path, const CgResult& r) {
    const CgGeometry& g = r.geom;
    const int dims[3] = {g.n[0], g.n[1], g.n[2]};
    const double origin[3] = {g.centres[0][0], g.centres[1][0], g.centres[2][0]};
    const double spacing[3] = {g.spacing[0], g.spacing[1], g.spacing[2]};
    const std::size_t nc = g.cells();
    std::vector<ImageField> f;
    auto scalar = [&](const std::string& name, const std::vector<double>& v) { f.push_back({name, 1, v}); };
    auto vec = [&](const std::string& name, const std::vector<Vec3>& v) {
        ImageField x{name, 3, std::vector<double>(3 * nc)};
        for (std::size_t c = 0; c < nc; ++c)
            for (int a = 0; a < 3; ++a) x.values[3 * c + a] = v[c][a];
        f.push_back(std::move(x));
    };
    auto sym = [&](const std::string& name, const std::vector<Sym6>& v) {
        ImageField x{name, 9, std::vector<double>(9 * nc)};
        const int m[9] = {0, 1, 2, 1, 3, 4, 2, 4, 5};
        for (std::size_t c = 0; c < nc; ++c)
            for (int k = 0; k < 9; ++k) x.values[9 * c + k] = v[c][m[k]];
        f.push_back(std::move(x));
    };
    scalar("density", r.rho);
    vec("momentum", r.momentum);
    vec("velocity", r.velocity);
    sym("kinetic_stress", r.kineticStress);
    {
        ImageField x{"contact_stress", 9, std::vector<double>(9 * nc)};
        ImageField t{"stress", 9, std::vector<double>(9 * nc)};
        std::vector<double> p(nc);
        for (std::size_t c = 0; c < nc; ++c) {
            const Tensor9 s = r.stress(c);
            for (int k = 0; k < 9; ++k) {
                x.values[9 * c + k] = r.contactStress[c][k];
                t.values[9 * c + k] = s[k];
            }
            p[c] = r.pressure(c);
        }
        f.push_back(std::move(x));
        f.push_back(std::move(t));
        scalar("pressure", p);
    }
    sym("fabric", r.fabric);
    scalar("number_density", r.numberDensity);
    scalar("volume_fraction", r.volumeFraction);
    scalar("contact_density", r.contactDensity);
    scalar("coordination", r.coordination);
    writeVti(path, dims, origin, spacing, f, r.time);
}

} // namespace pdpm::tools
