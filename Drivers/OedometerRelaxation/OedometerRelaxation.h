// OedometerRelaxation (thesis chapter 4): confined (oedometric) compression of a cohesive powder
// in the FT4 rheometer or the lambdameter, loading in steps and holding the piston still while the
// stress relaxes (Eq. 4.1-4.3, Table 4.3 protocols), or in a laterally periodic bed for the bulk.
// Documentation/driver-oedometer-relaxation.md describes geometry, protocol, time scaling, output
// and the measured results.
//
// This file is the experiment: the mould or periodic box, the material (OedometerMaterial.h), the
// pour and the levelling (the FT4 "split"). The test machine that runs the protocol on the piston,
// keeps the lab clock and writes the recording is ConfinedCompression.h. Header-only so that the
// self-tests can run the driver in-process.
#pragma once
#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "ConfinedCompression.h"
#include "OedometerMaterial.h"
#include "Particles/Insertion.h"
#include "Particles/PourSimulation.h"

namespace pdpm {

class OedometerRelaxation : public ConfinedCompression {
public:
    OedometerRelaxation()
        : ConfinedCompression("OedometerRelaxation", "Oedometric compression with relaxation (constant position) and creep (constant stress) holds") {
        auto& p = parameters();
        p.add("geometry", &geometry_, "periodic", "periodic: laterally periodic box; cylinder: mould of diameter D", {"periodic", "cylinder"});
        p.add("device", &device_, "periodic", "device name written to the protocol file (ft4, lambdameter, periodic, ...)");
        p.add("diameter", &diameter_, 0.05, "m", "mould diameter D (cylinder)", Range::positive());
        p.add("width", &width_, 6, "d_mean", "lateral period of the periodic box in mean diameters", Range::atLeast(3));
        p.add("fill_height", &fillHeight_, 6, "d_mean", "height of the levelled bed (periodic: in mean diameters)", Range::positive());
        p.add("fill_height_m", &fillHeightM_, 0, "m", "height of the levelled bed in metres (0: use fill_height)", Range::nonNegative());
        p.add("wall_friction", &k_.muWall, 0.2, "-", "wall friction mu_w (bottom, piston, mould)", Range::nonNegative());
        p.add("fill_wall_friction", &k_.fillMuWall, -1, "-", "wall friction while the bed is poured (-1: the same as --wall_friction)", Range::atLeast(-1));
        p.add("material", &k_.material, "cocoa", "material preset", {"cocoa", "frictional"});
        p.add("k_over_k1", &k_.kOverK1, 0, "-", "Luding plasticity: unloading (maximal) over loading stiffness k/k1 (1: elastic; 0: the material's value, cocoa 5)", Range::nonNegative());
        p.add("kc_over_k", &k_.kcOverK, -1, "-", "Luding adhesion: adhesive stiffness kc/k of particle pairs (0: no adhesion; -1: the material's value, cocoa 0.873)", Range::atLeast(-1));
        p.add("wall_kc_over_k", &k_.wallKcOverK, 0, "-", "Luding adhesion of the particle-wall pairs (bottom, piston, mould): kc/k (0: walls are not sticky; an unload into tension, unload:V:S with S < 0, pulls on the bed only with sticky walls and adhesive, plastic contacts, else it ends at lift-off)", Range::nonNegative());
        p.add("hertz_modulus", &k_.hertzModulus, 0, "Pa", "Hertz contacts: effective Young's modulus E* of a Hertzian normal force in place of Luding's (0: Luding; needs --k_over_k1 1 --kc_over_k 0; the other parts of the law stay)", Range::nonNegative());
        p.add("contact_viscous_time", &k_.viscTime, 0, "s", "contact viscosity on the lab clock: viscous time tau_v of a Maxwell branch, contact force k tau_v d(delta)/dt_lab at a steady lab rate (0: off; switches luding-relax to luding-relax-viscous)", Range::nonNegative());
        p.add("viscous_stiffness_ratio", &k_.viscRatio, 4, "-", "stiffness of the viscous branch's spring over k: its lag is tau_v / ratio lab seconds, and the time step falls by sqrt(1 + ratio)", Range::positive());
        p.add("normal_stiffness_scale", &k_.normalScale, 1, "-", "multiplies the material's normal contact stiffnesses k, k1, kc (the normal dashpot by its square root: the same restitution); tangential, rolling, torsion springs stay", Range::positive());
        p.add("d_mean", &k_.dMean, 2.5e-3, "m", "mean particle diameter", Range::positive());
        p.add("pour_drag_time", &pourDragTime_, 0.1, "s", "drag time of the particles falling while filling (mass-proportional drag; terminal speed g x this)", Range::positive());
        p.add("dt_fraction", &dtFraction_, 25, "-", "time step = t_c / dt_fraction", Range::atLeast(10));
        p.add("gravity", &gravityOn_, true, "gravity along -z");
        // The mould presets hold thousands of particles: they also take the faster numerical settings
        // whose effect on a hold was measured to be small (driver documentation, "Geometry").
        p.addPreset("ft4", "FT4 rheometer: cylinder D = H = 50 mm, protocol 1 capped at 22 kPa, relaxation clock memory 0.1 (faster numerical settings)",
                    {{"geometry", "cylinder"}, {"device", "ft4"}, {"diameter", "0.05"}, {"fill_height_m", "0.05"},
                     {"protocol", "1"}, {"max_stress", "22000"}, {"hold_tau", "0.005"}, {"ramp_rate", "1"},
                      {"relax_memory", "0.1"}});
        p.addPreset("lambdameter", "lambdameter: cylinder D = 149 mm, H = 60 mm, protocol 1 to 25 kPa, relaxation clock memory 0.1 (faster numerical settings)",
                    {{"geometry", "cylinder"}, {"device", "lambdameter"}, {"diameter", "0.149"}, {"fill_height_m", "0.06"},
                     {"protocol", "1"}, {"max_stress", "25000"}, {"hold_tau", "0.005"}, {"ramp_rate", "1"},
                      {"relax_memory", "0.1"}});
        p.setDefault("vtk", "0");
        p.setDefault("restart_output", "0");
        p.setDefault("contact_law", "luding-relax");
        state_.add("fillTime", fillTime_).add("poured", poured_).add("mouldWall", mouldWall_);
    }

protected:
    void setupInitialConditions() override {
        loadProtocol();
        loadMaterial();
        for (ContactParameters* c : {&mat_.pp, &mat_.pw, &pourMat_.pp, &pourMat_.pw}) {
            c->relaxC = relaxC_;
            c->relaxT0 = relaxT0_;
            c->relaxMemory = relaxMemory_;
            c->relaxTimeScale = c->viscTimeScale = 0;  // no lab time passes while filling
            c->viscTime = k_.viscTime;
            c->viscStiffnessRatio = k_.viscRatio;
        }
        const double rMean = 0.5 * k_.dMean;
        // r_max / r_min = sizeRatio with mean radius rMean (uniform distribution)
        const double rMin = 2 * rMean / (1 + mat_.sizeRatio), rMax = mat_.sizeRatio * rMin;
        const double H = fillHeightM_ > 0 ? fillHeightM_ : fillHeight_ * k_.dMean;
        double lx = width_ * k_.dMean;
        double R = 0.5 * diameter_;
        if (cylinder()) lx = diameter_;
        // Particle count: the poured beds settle at a volume fraction of 0.53-0.57 (0.533 in the FT4
        // mould); pour 15 % more than a bed at 0.55 so that the levelling at H (the split) has
        // something to remove (a warning says when the bed ends up below H).
        const double meanR3 = (std::pow(rMax, 4) - std::pow(rMin, 4)) / (4 * (rMax - rMin));
        const double vp = 4.0 / 3.0 * std::numbers::pi * meanR3;
        const double a = cylinder() ? std::numbers::pi * R * R : lx * lx;
        const double count = std::ceil(1.15 * 0.55 * a * H / vp);
        // (a cast of a count beyond size_t, or of NaN, is undefined: check it as a double first)
        if (!(count <= 1e9))
            inputError((std::isnan(count) ? std::string("the bed's particle count is not a number")
                                          : "the bed would need " + fmt(count) + " particles (more than 1e9)") +
                       ": check width/diameter, fill_height(_m) and d_mean");
        const auto n = static_cast<std::size_t>(count);
        auto radii = uniformRadii(n, rMin, rMax, random());

        // ---- fill: grid in a tall column, settle under gravity ------------------------------------
        // Settling without adhesion (a dense, reproducible start, like the FT4 conditioning), no relaxation.
        PourSimulation fill(runName() + "_fill");
        fill.dragTime = pourDragTime_;
        fill.setQuiet(quiet());
        setupSpecies(fill, 0, true);
        // staggered grid in a tall column (no vertical stacks), clipped to the mould
        const double s = 2.05 * rMax;
        const std::vector<Vec3> pts = staggeredColumn(n, s, lx, cylinder() ? R : 0.0, 1.02 * rMax);
        setDomainFor(fill, lx, R, pts.back().z + 2 * s);
        fill.addWall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, 1));
        if (cylinder()) fill.addWall(std::make_unique<CylinderWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, R, 0.0, 1));
        std::shuffle(radii.begin(), radii.end(), random());  // uniformRadii sorts them: mix the sizes
        // the column starts at the terminal speed g * pour_drag_time (it would reach it after about a
        // drag time; every particle lands at that speed either way), with a random sideways jitter
        std::uniform_real_distribution<double> U(-1, 1);
        const double vFall = 9.81 * pourDragTime_;
        for (std::size_t k = 0; k < n; ++k)
            fill.addParticle(pts[k], radii[k], 0, Vec3{0.2 * U(random()), 0.2 * U(random()), -vFall});
        fill.setGravity({0, 0, -9.81});
        fill.setTimeStep(fill.minCollisionTime() / dtFraction_);
        fill.setOutput(commonOptions().output, runName() + "_fill");
        fill.pour();
        fillTime_ = fill.time();
        poured_ = static_cast<double>(n);

        // ---- level at H (the FT4 "split") and set up the main simulation ---------------------------
        setupSpecies(*this, relaxC_);
        double top = 0, solid = 0;
        const ParticleData& F = fill.particles();
        for (std::size_t i = 0; i < F.size(); ++i) {
            if (F.x[i].z > H) continue;
            addParticle(F.x[i], F.r[i], 0);
            top = std::max(top, F.x[i].z + F.r[i]);
            solid += 4.0 / 3.0 * std::numbers::pi * std::pow(F.r[i], 3);
        }
        if (particles().size() < 10) inputError("fill produced fewer than 10 particles below the fill height");
        if (particles().size() == n && !quiet())
            std::cerr << "OedometerRelaxation: warning: the poured bed (top " << fmt(top) << " m) did not reach the fill height " << fmt(H) << " m: nothing levelled away\n";
        solid_ = solid;
        setDomainFor(*this, lx, R, top * 1.5 + 4 * rMax);
        addWall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, 1));
        bottomWall_ = 0;
        pistonZ0_ = top;
        pistonZ_ = top;
        auto piston = std::make_unique<PlaneWall>(Vec3{0, 0, top}, Vec3{0, 0, -1}, 1);
        piston->label = "piston";
        pistonWall_ = addWall(std::move(piston));
        if (cylinder()) {
            auto cyl = std::make_unique<CylinderWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, R, 0.0, 1);
            cyl->label = "mould";
            mouldWall_ = static_cast<long>(addWall(std::move(cyl)));
        }
        installPistonMotion();
        if (gravityOn_) setGravity({0, 0, -9.81});
        setTimeStep(minCollisionTime() / dtFraction_);
        setTimeMax(1e30);
        setSaveEvery(1e30);
    }

    void actionsOnRestart() override {
        // poured counts the spheres inserted, of which those above the fill height were removed
        if (mouldWall_ < -1 || mouldWall_ >= static_cast<long>(walls().size()) || poured_ < 0 || poured_ > 1e12 ||
            poured_ != std::floor(poured_))
            inputError("restart file: mould wall or poured count out of range");
        ConfinedCompression::actionsOnRestart();
        loadMaterial();
        k_.checkLaw(contactLaw().name());
    }

    void actionsBeforeTimeLoop() override {
        ConfinedCompression::actionsBeforeTimeLoop();
        if (!quiet())
            std::cout << "OedometerRelaxation: " << particles().size() << " particles, bed height " << fmt(pistonZ0_)
                      << " m, dt " << fmt(timeStep()) << " s, fill took " << fmt(fillTime_) << " s DEM with " << fmt(poured_)
                      << " particles poured\n";
    }

    double area() const override {
        return cylinder() ? std::numbers::pi * 0.25 * diameter_ * diameter_ : box().length().x * box().length().y;
    }

    /// Mould: radial force on the mould wall over its wetted area pi D h (the lambdameter's sensor).
    /// Periodic bed: the mean of the xx and yy stresses from the contact forces and branch vectors.
    double lateralStress(double h) const override {
        if (cylinder()) {
            double fr = 0;
            for (const auto& c : contacts())
                if (c.j == -1 - mouldWall_) fr += std::abs(c.fn);
            return fr / (std::numbers::pi * diameter_ * h);
        }
        double sxx = 0, syy = 0;
        for (const auto& c : contacts()) {
            const Vec3 f = c.fn * c.n + c.ft;
            sxx += f.x * c.branch.x;
            syy += f.y * c.branch.y;
        }
        return 0.5 * (sxx + syy) / (area() * h);
    }

    void describe(recording::Protocol& p, Json& extra) const override {
        p.device = device_;
        p.diameter = cylinder() ? diameter_ : 0;
        p.wallFriction = k_.muWall;
        p.material = Json::object({{"name", mat_.name},
                                   {"density_kg_m3", mat_.density},
                                   {"d_mean_m", k_.dMean},
                                   {"r_max_over_r_min", mat_.sizeRatio},
                                   {"contact_law", contactLaw().name()},
                                   {"E_star_Pa", k_.hertzModulus},
                                   {"k_N_m", mat_.pp.k},
                                   {"k1_N_m", mat_.pp.k1},
                                   {"kc_N_m", mat_.pp.kc},
                                   {"wall_kc_N_m", mat_.pw.kc},
                                   {"phi_f", mat_.pp.phiF},
                                   {"mu", mat_.pp.muS},
                                   {"mu_r", mat_.pp.muR},
                                   {"relax_C", relaxC_},
                                   {"relax_t0_s", relaxT0_},
                                   {"relax_memory", relaxMemory_},
                                   {"contact_viscous_time_s", k_.viscTime}});
        extra.set("particles", static_cast<double>(particles().size()));
        extra.set("geometry", geometry_);
        extra.set("fill_wall_friction", k_.fillMuWall >= 0 ? k_.fillMuWall : k_.muWall);  // mu_w while the bed was poured
        extra.set("lateral_period_m", cylinder() ? 0.0 : box().length().x);
    }

private:
    bool cylinder() const { return geometry_ == "cylinder"; }
    /// Material preset and contact knobs from the parameters (also after a restart).
    void loadMaterial() {
        k_.contactLaw = parameters().get("contact_law");
        k_.contactLawGiven = parameters().wasSetOnCommandLine("contact_law");
        mat_ = k_.apply();
        pourMat_ = k_.pourMaterial();
        grainDensity_ = mat_.density;
        grainSize_ = k_.dMean;
    }
    void setupSpecies(DPMBase& d, double relaxC, bool settling = false) {
        ContactParameters pp = mat_.pp, pw = mat_.pw;
        if (settling) {  // the plain material (OedometerKnobs::pourLawName says why)
            pp = pourMat_.pp;
            pw = pourMat_.pw;
        }
        pp.relaxC = pw.relaxC = relaxC;
        if (settling) {  // (no lab time passes while pouring: no viscous branch, and its time step)
            pp.kc = pw.kc = 0;
            pp.viscTime = pw.viscTime = 0;
            if (k_.fillMuWall >= 0) pw.muS = pw.muD = k_.fillMuWall;
            d.setContactLaw(k_.pourLawName());
        } else {
            d.setContactLaw(k_.lawName());
            k_.checkLaw(d.contactLaw().name());
        }
        const int a = d.addSpecies(mat_.name, mat_.density, pp);
        const int w = d.addSpecies("wall", mat_.density, pp);
        d.setPairParameters(a, w, pw);
    }
    void setDomainFor(DPMBase& d, double lx, double R, double zTop) {
        if (cylinder()) d.setDomain({-R, -R, 0}, {R, R, zTop}, false, false, false);
        else d.setDomain({0, 0, 0}, {lx, lx, zTop}, true, true, false);
    }

    std::string geometry_, device_;
    double diameter_ = 0, width_ = 0, fillHeight_ = 0, fillHeightM_ = 0;
    double pourDragTime_ = 0.1, dtFraction_ = 25;
    bool gravityOn_ = true;
    OedometerKnobs k_;  ///< the flags that change the material's contacts
    OedometerMaterial mat_, pourMat_;  ///< the test's material, the pour's (OedometerKnobs::pourLawName)
    long mouldWall_ = -1;
    double fillTime_ = 0, poured_ = 0;
};

} // namespace pdpm
