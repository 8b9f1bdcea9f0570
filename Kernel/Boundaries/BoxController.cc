#include "Boundaries/BoxController.h"

#include "IO/StateFields.h"

#include <array>
#include <cmath>
#include <numbers>

#include "Boundaries/PeriodicBox.h"
#include "Core/Error.h"
#include "IO/NumberFormat.h"
#include "Particles/ParticleData.h"

namespace pdpm {

std::string axisModeName(AxisMode m) {
    switch (m) {
    case AxisMode::Free: return "free";
    case AxisMode::Cosine: return "cosine";
    case AxisMode::StrainRate: return "strain_rate";
    case AxisMode::Stress: return "stress";
    }
    return "free";
}

namespace {
AxisMode modeFromName(const std::string& s) {
    if (s == "free") return AxisMode::Free;
    if (s == "cosine") return AxisMode::Cosine;
    if (s == "strain_rate") return AxisMode::StrainRate;
    if (s == "stress") return AxisMode::Stress;
    inputError("box controller: unknown axis mode '" + s + "'");
}
void checkAxis(int a) {
    if (a < 0 || a > 2) inputError("box controller: axis must be 0, 1 or 2");
}
} // namespace

double deviatoricMagnitude(const Vec3& d) {
    const double a = d.x - d.y, b = d.y - d.z, c = d.z - d.x;
    return std::sqrt(0.5 * (a * a + b * b + c * c));
}

void BoxController::setFree(int a) {
    checkAxis(a);
    axes_[a] = AxisControl{};
}

void BoxController::setCosine(int a, double l0, double lf, double period, double t0, bool affine) {
    checkAxis(a);
    if (!(l0 > 0) || !(lf > 0)) inputError("box controller: cosine lengths must be positive");
    if (!(period > 0)) inputError("box controller: cosine period must be positive");
    AxisControl c;
    c.mode = AxisMode::Cosine;
    c.lengthStart = l0;
    c.lengthFinal = lf;
    c.period = period;
    c.timeStart = t0;
    c.affine = affine;
    axes_[a] = c;
}

void BoxController::setStrainRate(int a, double rate) {
    checkAxis(a);
    if (!std::isfinite(rate)) inputError("box controller: strain rate must be finite");
    AxisControl c;
    c.mode = AxisMode::StrainRate;
    c.rate = rate;
    axes_[a] = c;
}

void BoxController::setStress(int a, double goal, double mass, double damping) {
    checkAxis(a);
    if (!(mass > 0)) inputError("box controller: virtual wall mass must be positive");
    if (!(damping >= 0)) inputError("box controller: wall damping must be non-negative");
    AxisControl c;
    c.mode = AxisMode::Stress;
    c.stressGoal = goal;
    c.wallMass = mass;
    c.wallDamping = damping;
    axes_[a] = c;
}

bool BoxController::needsStress() const {
    for (const auto& c : axes_)
        if (c.mode == AxisMode::Stress) return true;
    return false;
}

double BoxController::cosineLength(const AxisControl& c, double t) {
    const double tau = t - c.timeStart;
    if (tau <= 0) return c.lengthStart;
    return c.lengthFinal + 0.5 * (c.lengthStart - c.lengthFinal) * (1 + std::cos(2 * std::numbers::pi * tau / c.period));
}

double BoxController::cosineRate(const AxisControl& c, double t) {
    const double tau = t - c.timeStart;
    if (tau <= 0) return 0.0;
    const double w = 2 * std::numbers::pi / c.period;
    return -0.5 * (c.lengthStart - c.lengthFinal) * w * std::sin(w * tau);
}

void BoxController::step(PeriodicBox& box, ParticleData& P, double t, double dt, const Vec3& stress,
                         const std::vector<double>& density) {
    const Vec3 L = box.length();
    Vec3 newLo = box.lo(), newHi = box.hi();
    std::array<bool, 3> set{false, false, false}, remapAxis{false, false, false};
    for (int a = 0; a < 3; ++a) {
        AxisControl& c = axes_[a];
        double newLength = L[a];
        bool affine = true;
        switch (c.mode) {
        case AxisMode::Free: break;
        case AxisMode::Cosine:
            newLength = cosineLength(c, t + dt);
            affine = c.affine;
            break;
        case AxisMode::StrainRate: newLength = L[a] * std::exp(c.rate * dt); break;
        case AxisMode::Stress: {
            const double area = L[(a + 1) % 3] * L[(a + 2) % 3];
            const double force = (stress[a] - c.stressGoal) * area;
            // semi-implicit damping: unconditionally stable for any gamma_w dt / m_w
            c.wallVelocity = (c.wallVelocity + dt * force / c.wallMass) / (1 + dt * c.wallDamping / c.wallMass);
            newLength = L[a] + dt * c.wallVelocity;
            if (!(newLength > 0)) inputError("box controller: stress control collapsed the box along an axis");
            break;
        }
        }
        lastRate_[a] = std::log(newLength / L[a]) / dt;
        if (newLength != L[a]) {
            const double centre = 0.5 * (box.lo()[a] + box.hi()[a]);
            newLo[a] = centre - 0.5 * newLength;
            newHi[a] = centre + 0.5 * newLength;
            set[a] = true;
            remapAxis[a] = affine;
        }
    }
    // every changed axis in one pass over the particles (each axis reads only its own bounds)
    if (set[0] || set[1] || set[2]) box.setAxes(newLo, newHi, set, remapAxis, &P);
    applyRates(box, t + dt);
    if (swelling_ != 0) {
        const double s = std::exp(swelling_ * dt);
        // the largest radius grows most: its growth bounds every particle's (the neighbour list's skin)
        if (s > 1) P.radiusGrowth += P.maxRadius() * (s - 1);
        for (std::size_t i = 0; i < P.size(); ++i) {
            const auto sp = static_cast<std::size_t>(P.species[i]);
            if (sp >= density.size()) inputError("box controller: swelling needs the density of every species");
            const bool fixed = P.fixed[i] != 0;
            P.setRadius(i, P.r[i] * s, density[sp]);
            if (fixed) P.setFixed(i, true);
        }
    }
}

void BoxController::applyRates(PeriodicBox& box, double t) const {
    for (int a = 0; a < 3; ++a) {
        const AxisControl& c = axes_[a];
        double flow = 0, affine = 0;
        switch (c.mode) {
        case AxisMode::Free: break;
        case AxisMode::Cosine:
            if (c.affine) affine = cosineRate(c, t) / cosineLength(c, t);
            else flow = cosineRate(c, t);
            break;
        case AxisMode::StrainRate: affine = c.rate; break;
        case AxisMode::Stress: affine = c.wallVelocity / box.length()[a]; break;
        }
        box.setFlowRate(a, flow);
        box.setAffineRate(a, affine);
    }
}

void BoxController::setReference(const PeriodicBox& box) { ref_ = box.length(); }

StrainState BoxController::strain(const PeriodicBox& box) const {
    StrainState s;
    const Vec3 L = box.length();
    for (int a = 0; a < 3; ++a) {
        s.trueStrain[a] = std::log(L[a] / ref_[a]);
        s.engineeringStrain[a] = L[a] / ref_[a] - 1;
    }
    s.rate = lastRate_;
    s.volumetricTrue = s.trueStrain.x + s.trueStrain.y + s.trueStrain.z;
    s.volumetricEngineering = s.engineeringStrain.x + s.engineeringStrain.y + s.engineeringStrain.z;
    s.deviatoric = deviatoricMagnitude(s.trueStrain);
    s.deviatoricEngineering = deviatoricMagnitude(s.engineeringStrain);
    return s;
}

void BoxController::save(std::vector<std::pair<std::string, std::string>>& kv, const std::string& prefix) const {
    for (int a = 0; a < 3; ++a) {
        const AxisControl& c = axes_[a];
        const std::string p = prefix + std::to_string(a) + "_";
        kv.emplace_back(p + "mode", axisModeName(c.mode));
        kv.emplace_back(p + "l0", fmt(c.lengthStart));
        kv.emplace_back(p + "lf", fmt(c.lengthFinal));
        kv.emplace_back(p + "period", fmt(c.period));
        kv.emplace_back(p + "t0", fmt(c.timeStart));
        kv.emplace_back(p + "affine", c.affine ? "1" : "0");
        kv.emplace_back(p + "rate", fmt(c.rate));
        kv.emplace_back(p + "goal", fmt(c.stressGoal));
        kv.emplace_back(p + "mass", fmt(c.wallMass));
        kv.emplace_back(p + "damping", fmt(c.wallDamping));
        kv.emplace_back(p + "velocity", fmt(c.wallVelocity));
    }
    kv.emplace_back(prefix + "swelling", fmt(swelling_));
    kv.emplace_back(prefix + "ref", fmt(ref_.x) + "," + fmt(ref_.y) + "," + fmt(ref_.z));
}

void BoxController::load(const std::vector<std::pair<std::string, std::string>>& kv, const std::string& prefix) {
    auto num = [](const std::string& k, const std::string& v) {
        double x = 0;
        if (!parseDouble(v, x) || !std::isfinite(x)) inputError("restart: malformed box controller value for " + k);
        return x;
    };
    // every key save() writes (taken from save() itself, so a new field is required with it)
    std::vector<std::pair<std::string, std::string>> written;
    save(written, prefix);
    std::vector<std::string> keys;
    for (const auto& [k, v] : written) keys.push_back(k);
    requireDriverKeys(kv, keys);
    for (const auto& [k, v] : kv) {
        if (k.rfind(prefix, 0) != 0) continue;
        const std::string rest = k.substr(prefix.size());
        if (rest == "swelling") {
            swelling_ = num(k, v);
        } else if (rest == "ref") {
            const auto c1 = v.find(','), c2 = v.rfind(',');
            if (c1 == std::string::npos || c1 == c2) inputError("restart: malformed box reference");
            ref_ = {num(k, v.substr(0, c1)), num(k, v.substr(c1 + 1, c2 - c1 - 1)), num(k, v.substr(c2 + 1))};
        } else if (rest.size() > 2 && rest[0] >= '0' && rest[0] <= '2' && rest[1] == '_') {
            AxisControl& c = axes_[rest[0] - '0'];
            const std::string f = rest.substr(2);
            if (f == "mode") c.mode = modeFromName(v);
            else if (f == "affine") {
                if (v != "0" && v != "1") inputError("restart: malformed box controller value for " + k + " (0 or 1)");
                c.affine = v == "1";
            }
            else if (f == "l0") c.lengthStart = num(k, v);
            else if (f == "lf") c.lengthFinal = num(k, v);
            else if (f == "period") c.period = num(k, v);
            else if (f == "t0") c.timeStart = num(k, v);
            else if (f == "rate") c.rate = num(k, v);
            else if (f == "goal") c.stressGoal = num(k, v);
            else if (f == "mass") c.wallMass = num(k, v);
            else if (f == "damping") c.wallDamping = num(k, v);
            else if (f == "velocity") c.wallVelocity = num(k, v);
        }
    }
    // what the setters require of each mode, for a file edited after it was sealed
    for (int a = 0; a < 3; ++a) {
        const AxisControl& c = axes_[a];
        const std::string p = "restart: box controller axis " + std::to_string(a) + ": ";
        if (c.mode == AxisMode::Cosine && (!(c.lengthStart > 0) || !(c.lengthFinal > 0) || !(c.period > 0)))
            inputError(p + "cosine lengths and period must be positive");
        if (c.mode == AxisMode::Stress && (!(c.wallMass > 0) || !(c.wallDamping >= 0)))
            inputError(p + "virtual wall mass must be positive and damping non-negative");
    }
}

} // namespace pdpm
