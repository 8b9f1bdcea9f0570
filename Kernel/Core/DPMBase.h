// DPMBase: owns particles, species, walls, the (periodic) domain, the contact law, time stepping and
// output. A driver is a small subclass that overrides the hooks below.
//
// Order of calls (the one place where it is documented; see also Documentation/writing-a-driver.md):
//
//   run(argc, argv)
//     parse the command line (registered parameters, --preset, --help, --output, --threads, ...)
//     fresh start:  setupInitialConditions()
//     --restart F:  read F (parameters, state, histories)  ->  actionsOnRestart()
//     solve()
//       check parameters, species pairs, time step (<= t_c/10), initial overlaps (fresh start)
//       build neighbour list, compute forces (fresh start: at t = 0 with zero elapsed time, so springs
//         and relaxation clocks do not advance; a state read with readRestart(file, true) keeps its stored forces)
//       actionsBeforeTimeLoop()
//       fresh start: writeOutputFiles() at t = 0
//       while (time < time_max && continueSolve()):
//         actionsBeforeTimeStep()                 (drivers deform the box, move things, ...)
//         first half kick + drift:  v += dt/2 F/m,  x += dt v   (same for rotation);
//           predicted velocities v + dt/2 F/m are what dashpots, friction and background damping see
//         time += dt; walls move to their prescribed position at the new time
//         rebuild the neighbour list if needed
//         forces: contacts (pairs, then walls) -> computeAdditionalForces() -> gravity, background damping
//         second half kick:  v += dt/2 F/m
//         NaN check
//         actionsAfterTimeStep()
//         if an output time was reached: writeOutputFiles()   (ene, vtu, fstat, restart)
//       actionsAfterSolve()
//       final output if the last step was not an output step
#pragma once
#include <fstream>
#include <memory>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "Boundaries/PeriodicBox.h"
#include "Contacts/ContactLaw.h"
#include "Contacts/SpeciesTable.h"
#include "Core/Parameters.h"
#include "Core/Progress.h"
#include "IO/AtomicFile.h"
#include "Neighbours/NeighbourList.h"
#include "Particles/ParticleData.h"
#include "Walls/Wall.h"

namespace pdpm {

class SnapshotWriter;

class DPMBase {
public:
    /// `name`: the program's name (default run name, messages); `description`: first line of --help.
    explicit DPMBase(std::string name, std::string description = "");
    virtual ~DPMBase();
    DPMBase(const DPMBase&) = delete;
    DPMBase& operator=(const DPMBase&) = delete;

    /// Parse the command line, set up or restart, solve. Returns the exit code (2 for bad input).
    int run(int argc, char** argv);
    /// Run the time loop from the current state (setup must have been done).
    void solve();

    // ---- set-up -------------------------------------------------------------------------------
    ParameterSet& parameters() { return params_; }
    const ParameterSet& parameters() const { return params_; }
    ParticleData& particles() { return particles_; }
    const ParticleData& particles() const { return particles_; }
    SpeciesTable& species() { return species_; }
    const SpeciesTable& species() const { return species_; }
    PeriodicBox& box() { return box_; }
    const PeriodicBox& box() const { return box_; }
    const WallList& walls() const { return walls_; }
    Wall& wall(std::size_t k) { return *walls_.at(k); }

    void setContactLaw(const std::string& name);
    const ContactLaw& contactLaw() const { return *law_; }
    /// The neighbour list (pairs and their contact histories), read only: for analysis and tests.
    const NeighbourList& neighbourList() const { return neighbours_; }
    int addSpecies(const std::string& name, double density, const ContactParameters& self);
    void setPairParameters(int a, int b, const ContactParameters& p) { species_.setPair(a, b, p); }
    /// Add a sphere of the given species (mass from the species density). Returns its index.
    std::size_t addParticle(const Vec3& x, double radius, int speciesIndex = 0, const Vec3& v = {},
                            const Vec3& w = {}, bool fixed = false);
    /// Add a wall; returns its index.
    std::size_t addWall(std::unique_ptr<Wall> w);
    void setDomain(const Vec3& lo, const Vec3& hi, bool px, bool py, bool pz) { box_.set(lo, hi, px, py, pz); }
    void setGravity(const Vec3& g) { gravity_ = g; }
    const Vec3& gravity() const { return gravity_; }
    /// Background damping: F = -gammaT v, torque = -gammaR w (Sec. 2.2.1).
    void setBackgroundDamping(double gammaT, double gammaR) { gammaBt_ = gammaT; gammaBr_ = gammaR; }
    // The setters below give the driver's value; a value given on the command line
    // (--dt, --time_max, --save_every, --contact_law) wins over them.
    void setTimeStep(double dt);
    double timeStep() const { return dt_; }
    void setTimeMax(double t);
    double timeMax() const { return timeMax_; }
    /// Time between outputs (0: 100 outputs over the run).
    void setSaveEvery(double dt);
    void setOutput(const std::string& dir, const std::string& runName);
    const std::string& outputDirectory() const { return outDir_; }
    const std::string& runName() const { return runName_; }
    /// The program's name (the driver class's, as given to the constructor).
    const std::string& programName() const { return name_; }
    /// Path of an output file: DIR/RUN + suffix.
    std::string outputPath(const std::string& suffix) const;
    void setNeighbourSkin(double s) { neighbours_.setSkin(s); }
    /// Switch off every output file (VTK, RUN.ene, RUN.fstat, RUN.restart): for internal runs
    /// (packing preparation) and benchmarks.
    void disableFileOutput();
    /// Text in front of the progress line (default: empty; e.g. "filling: ").
    void setProgressLabel(std::string label) { progressLabel_ = std::move(label); }
    void setQuiet(bool q) { quiet_ = q; }
    bool quiet() const { return quiet_; }
    std::mt19937_64& random() { return rng_; }

    /// Collision time of the fastest particle pair (and particle-wall pair) of the current law.
    double minCollisionTime() const;
    /// t_c/50 of the fastest pair, the thesis' choice (Sec. 2.2.2).
    double suggestedTimeStep() const { return minCollisionTime() / 50; }

    // ---- state and analysis ---------------------------------------------------------------------
    double time() const { return time_; }
    long step() const { return step_; }
    void setTime(double t) { time_ = t; }
    double kineticEnergy() const;
    double rotationalEnergy() const;
    double gravitationalEnergy() const;
    /// Elastic energy stored in the contacts at the last recorded step.
    double elasticEnergy() const { return elasticEnergy_; }
    /// Contacts of the last step in which records were made (output steps, or after requestContacts()).
    const std::vector<ContactRecord>& contacts() const { return contactsFlat_; }
    /// True if contacts() describes the current step (records were made during it).
    bool contactsAreCurrent() const { return lastStepRecorded_; }
    /// Ask for contact records (and elastic energy) to be made during the next force evaluation:
    /// called in actionsBeforeTimeStep() it applies to this step, in actionsAfterTimeStep() to the next.
    void requestContacts() { recordRequested_ = true; }
    /// Recompute contact records and elastic energy now, at the current state (no time advance;
    /// histories, particle forces/torques and wall forces are left as they were).
    void refreshContacts();
    /// Number of particle-particle pairs in contact now (no records made).
    std::size_t countContacts() const;
    std::size_t neighbourPairs() const { return neighbours_.pairCount(); }
    long neighbourBuilds() const { return neighbours_.builds(); }
    std::size_t memoryBytes() const;

    // ---- output -----------------------------------------------------------------------------------
    void writeRestart(const std::string& path) const;
    /// Read a restart file. With `stateOnly`, load just the configuration (particles, species, law,
    /// walls, box, contact histories) from a file of any program, without parameters, driver state,
    /// output schedule or clock (time and step restart at 0): for a driver that starts a new
    /// experiment from another driver's state (call it in setupInitialConditions(); the histories
    /// carry over into the fresh start's first neighbour build if the law is the same).
    void readRestart(const std::string& path, bool stateOnly = false);

protected:
    // ---- hooks (see the order above) ----------------------------------------------------------
    virtual void setupInitialConditions() {}
    virtual void actionsOnRestart() {}
    virtual void actionsBeforeTimeLoop() {}
    virtual void actionsBeforeTimeStep() {}
    virtual void computeAdditionalForces() {}
    virtual void actionsAfterTimeStep() {}
    virtual void actionsAfterSolve() {}
    virtual bool continueSolve() const { return true; }
    /// Completed fraction of the run in [0, 1] for the progress line, for drivers whose end is not
    /// time_max (a protocol that ends by itself); negative (the default) uses time / time_max.
    /// Called at most once per printed progress line.
    virtual double progressFraction() const { return -1; }
    /// Writes RUN.ene, the VTK snapshot, RUN.fstat and RUN.restart (each if enabled).
    virtual void writeOutputFiles();
    /// Columns of RUN.ene; override and call the base to append columns.
    virtual void writeEneHeader(std::ostream& os) const;
    virtual void writeEneTimeStep(std::ostream& os) const;
    /// Driver state for restart files (key/value); parameters are saved automatically.
    virtual void saveDriverState(std::vector<std::pair<std::string, std::string>>& kv) const { (void)kv; }
    virtual void loadDriverState(const std::vector<std::pair<std::string, std::string>>& kv) { (void)kv; }

    /// Options parsed by run() (output dir, threads, ...).
    const CommonOptions& commonOptions() const { return options_; }

private:
    void prepare(bool freshStart);
    /// Run the form of the contact law that fits the species table (ContactLaw::specialised; e.g. no
    /// sliding flag when every pair has mu_s = mu_d), converting the stored histories between layouts.
    /// Called before the first neighbour build and again whenever the species table has changed.
    void specialiseLaw();
    void specialiseLawIfSpeciesChanged() {
        if (species_.revision() != lawRevision_) specialiseLaw();
    }
    /// A loaded state is run under another law than its file's: drop its histories and stored forces.
    void discardLoadedContacts();
    /// Pair, wall and additional forces at the current state. `historyDt` is the time over which the
    /// incremental histories (tangential, rolling and torsion springs, relaxation clocks) advance:
    /// dt_ in the time loop, 0 for the evaluation of a fresh start at t = 0 (no time has passed yet).
    void computeForces(bool record, double historyDt);
    double integrateFirstHalf();
    void wrapWithFlow();
    bool integrateSecondHalf();
    void addBodyForces();
    void reportNonFinite();
    bool stateIsFinite() const;
    void gatherRecords();
    void writeEne();
    void writeSnapshot();
    void writeFstat();
    void finishFiles();
    double outputInterval() const;
    /// Moves the next output time past the current step by whole intervals (at most 64; beyond, or
    /// when the interval is below the clock's resolution, to the next step).
    void advanceNextOutput(double every);
    bool outputNeedsContacts() const;

    std::string name_, description_;
    ParameterSet params_;
    CommonOptions options_;
    ParticleData particles_;
    SpeciesTable species_;
    PeriodicBox box_;
    WallList walls_;
    std::unique_ptr<ContactLaw> law_;
    unsigned long lawRevision_ = ~0ul;  ///< species_.revision() when the law's form was last chosen
    NeighbourList neighbours_;
    Vec3 gravity_;
    double gammaBt_ = 0, gammaBr_ = 0;
    double dt_ = 0, time_ = 0, timeMax_ = 0, saveEvery_ = 0;
    long step_ = 0;
    double nextOutput_ = 0;
    double outputEvery_ = 0;  ///< output interval fixed at the fresh start (restart files keep it)
    int outputIndex_ = 0;
    bool quiet_ = false;
    std::string outDir_ = ".", runName_;
    std::mt19937_64 rng_{12345};
    bool vtkOutput_ = true, fstatOutput_ = false, restartOutput_ = true, eneOutput_ = true;
    long seed_ = 12345;
    double skinParameter_ = 0;
    double maxInitialOverlap_ = 0.1;
    std::string lawName_ = "linear";

    // per-step scratch (allocated once)
    std::vector<std::vector<ContactRecord>> slabRecords_;
    std::vector<double> slabEnergy_;
    std::vector<Vec3> wallForce_, wallTorque_;
    std::vector<double> wallEnergy_;
    std::vector<uint8_t> wallSliding_;
    std::vector<ContactRecord> contactsFlat_;
    double elasticEnergy_ = 0;
    bool recordRequested_ = false;
    bool lastStepRecorded_ = false;
    bool prepared_ = false;
    bool stateLoaded_ = false;  ///< readRestart(path, true) loaded particles with their forces
    bool forcesZeroed_ = false;
    bool usePredicted_ = false;
    std::vector<Vec3> vPred_, wPred_;  ///< predicted full-step velocities (see integrateFirstHalf)

    // output state
    std::string eneBuffer_;
    std::unique_ptr<SnapshotWriter> snapshotWriter_;
    std::unique_ptr<AtomicOFStream> fstatStream_;  ///< RUN.fstat.tmp until the run ends or stops on NaN (then renamed); removed if the run fails otherwise
    double lastFiniteRestartTime_ = -1;
    std::unique_ptr<ProgressReporter> progress_;
    std::string progressLabel_;
};

} // namespace pdpm
