// ElementTest: the common base of the element-test drivers (IsotropicCompression, UniaxialCyclic,
// DeviatoricD2 / D3 / triaxial) of thesis chapters 2-3, in a fully periodic deformable box.
//
// It owns
//   - the material and system parameters with the presets `default` (fast, frictional, mu = --mu),
//     `thesis-ch2` (frictionless, N = 9261, w = 3) and `thesis-ch3` (frictional, N = 9261, w = 1.5);
//   - the three-step preparation of Sec. 2.3.1 / 3.2.1 (random gas with large random velocities ->
//     isotropic compression at a constant true strain rate to v0 -> relaxation at constant volume),
//     optionally followed by a further isotropic compression to the test's start fraction v_i and a
//     relaxation; or, with --start FILE, the configuration of a restart file written by any element
//     test driver (e.g. IsotropicCompression's RUN.unload_0.700.restart), then a relaxation;
//   - a list of stages (name, duration, what the box controller does), run one after the other;
//   - the BoxController (Kernel/Boundaries/BoxController.h) and the micro-macro analysis written to
//     RUN.macro.csv at every output (Tools/MicroMacro/MicroMacro.h);
//   - restart files at a list of volume fractions on loading and unloading stages
//     (RUN.load_0.700.restart, RUN.unload_0.700.restart).
//
// A driver overrides addTestStages() (and may register parameters in its constructor).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "Boundaries/BoxController.h"
#include "Core/DPMBase.h"
#include "Core/Error.h"
#include "MicroMacro.h"

namespace pdpm {

class ElementTest : public DPMBase {
public:
    ElementTest(const std::string& name, const std::string& description);

    /// What a stage does with the box when it begins.
    enum class Branch { None, Loading, Unloading };
    struct Stage {
        std::string name;
        double duration = 0;
        std::function<void()> begin;  ///< sets up the box controller (called once, at the stage start)
        Branch branch = Branch::None; ///< restart files at save_fractions are written on these
        bool test = false;            ///< part of the test proper: tau counts over these stages
    };

    const BoxController& controller() const { return ctrl_; }
    const MacroCsv& macro() const { return macro_; }
    /// Name of the current stage ("" before the first).
    std::string stageName() const;

protected:
    /// Contact part of the stress diagonal before division by the volume: sum over the records of
    /// f_a branch_a (Eq. 2.5), in the records' order.
    Vec3 contactStressSum() const;
    /// Diagonal of the stress (Eq. 2.5, contact + kinetic) from the current contact records and
    /// velocities: the stress that stress-controlled axes compare with their goal.
    Vec3 stressDiagonalNow() const { return stressDiagonalFrom(contactStressSum()); }
    /// Append the driver's stages (after the preparation). Called at set-up and on --restart (where
    /// the `begin` of stages already begun is not called again).
    virtual void addTestStages() = 0;
    void addStage(Stage s) { stages_.push_back(std::move(s)); }

    // helpers for drivers
    /// Register --drive wall|strain_rate (cosine-law tests): whether only the periodic walls move or
    /// the particles are remapped affinely too. Read the choice with affineDrive().
    void addDriveParameter() {
        parameters().add("drive", &drive_, "wall",
                         "wall: only the periodic walls move; strain_rate: particles are remapped affinely too",
                         {"wall", "strain_rate"});
    }
    bool affineDrive() const { return drive_ == "strain_rate"; }
    void isotropicRate(double rate);  ///< every axis at true strain rate `rate`
    void freeAll();
    double volumeFraction() const;
    /// Current volume fraction; InputError if it is not below --v_max (start of a loading test).
    double startFractionBelowVMax() const {
        const double v = volumeFraction();
        if (!(v < vMax_)) inputError("volume fraction at the start of the test is not below --v_max");
        return v;
    }
    double solidVolume() const { return solid_; }
    /// Box length that gives volume fraction v for a box with the other lengths fixed (axis a).
    double lengthForFraction(int axis, double v) const;
    /// Virtual wall damping for stress control: 2 sqrt(m_w k_eff), k_eff = k L/(2<r>) (springs in series/parallel).
    double wallDampingFor(int axis, double wallMass) const;
    double totalMass() const;
    BoxController& ctrl() { return ctrl_; }
    std::string drive_;  ///< --drive (see addDriveParameter)

    // ---- parameters shared by every element test ----
    long n_ = 0;
    double rMin_ = 0, rMax_ = 0, density_ = 0, k_ = 0, gamma_ = 0, kt_ = 0, gammaT_ = 0, mu_ = 0;
    double gammaB_ = 0, gammaBr_ = 0;
    double vGas_ = 0, gasSpeed_ = 0, v0_ = 0, prepRate_ = 0, relax_ = 0, vi_ = 0, startRelax_ = 0;
    double vMax_ = 0, period_ = 0;
    std::string start_, saveFractions_;
    int outputsPerTest_ = 0;

    // DPMBase hooks
    void setupInitialConditions() override;
    void actionsOnRestart() override;
    void actionsBeforeTimeLoop() override;
    void actionsBeforeTimeStep() override;
    void actionsAfterTimeStep() override;
    void writeOutputFiles() override;
    void saveDriverState(std::vector<std::pair<std::string, std::string>>& kv) const override;
    void loadDriverState(const std::vector<std::pair<std::string, std::string>>& kv) override;

private:
    /// `contactSum` (contactStressSum's form) plus the kinetic part, divided by the volume.
    Vec3 stressDiagonalFrom(Vec3 contactSum) const;
    /// As stressDiagonalNow(), but the first step after a --restart uses the stored contact sum.
    Vec3 currentStressDiagonal();
    void buildStages();
    void enterStage(std::size_t k);
    void setMaterial();
    double testDuration() const;
    double testStart() const;

    BoxController ctrl_;
    MacroCsv macro_;
    std::vector<Stage> stages_;
    std::size_t stage_ = 0;       ///< index of the current stage
    bool begun_ = false;          ///< stage_ has begun
    double stageStart_ = 0;
    double solid_ = 0;
    double lastFraction_ = 0;
    std::vector<double> fractions_;
    Vec3 refLength_;
    /// Stress control after a restart: the contact sum of the step the file was written at. Those records
    /// were made with the predicted velocities of that step, which a re-evaluation cannot reproduce
    /// bit for bit, so the first step after a restart uses the stored sum (see loadDriverState).
    Vec3 restoredContactSum_;
    bool haveRestoredContactSum_ = false;
    bool stressLastStep_ = false;  ///< the last step ran under stress control (not stored: derived from the controller)
};

} // namespace pdpm
