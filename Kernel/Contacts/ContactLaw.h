// Contact laws: composed from a normal, a tangential, a rolling and a torsion part, registered by
// name once (Contacts/ContactLawRegistry.cc). The kernel calls computePairForces/computeWallForces,
// which run the law's inlined loop over the neighbour list; evaluate() is the same law as a pure
// function of one contact, for tests and tools.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "Contacts/ContactParameters.h"
#include "Contacts/ContactRecord.h"
#include "Contacts/ContactState.h"
#include "Contacts/SpeciesTable.h"
#include "Neighbours/NeighbourList.h"

namespace pdpm {

struct ParticleData;
class PeriodicBox;

/// Everything the force loops read and write in one step.
struct ForceContext {
    ParticleData& particles;
    const PeriodicBox& box;
    NeighbourList& neighbours;
    const WallList& walls;
    const SpeciesTable& species;
    double dt = 0;
    double time = 0;
    /// Velocities the dashpots and friction see: the predicted full-step velocities
    /// v(n+1) ~ v(n+1/2) + dt/2 F(n)/m during the time loop (so that damping is not half a step
    /// late), the current velocities otherwise.
    const Vec3* velocity = nullptr;
    const Vec3* angularVelocity = nullptr;
    /// When true, the loops also fill `records` (one vector per slab + one for walls, in a
    /// thread-count independent order) and `energy` (one sum per slab + one for walls).
    bool record = false;
    std::vector<std::vector<ContactRecord>>* records = nullptr;
    std::vector<double>* energy = nullptr;
    /// Scratch for wall reactions (one entry per wall-list entry).
    std::vector<Vec3>* wallForce = nullptr;
    std::vector<Vec3>* wallTorque = nullptr;
    std::vector<double>* wallEnergy = nullptr;
    std::vector<uint8_t>* wallSliding = nullptr;
};

class ContactLaw {
public:
    virtual ~ContactLaw() = default;
    virtual std::string name() const = 0;
    /// Doubles of history per contact.
    virtual int historySize() const = 0;
    /// The form of this law to run with this species table, or nullptr if it is this one. Linear laws
    /// with Coulomb friction and no rolling parts drop the sliding flag from their history when every
    /// pair has mu_s = mu_d (it selects between equal coefficients), and take it back otherwise; the
    /// forces are the same bits (ComposedLaw, TangentialCoulombOneMu). DPMBase asks before the time
    /// loop and whenever the species table changes.
    virtual std::unique_ptr<ContactLaw> specialised(const SpeciesTable&) const { return nullptr; }
    /// Slot of the law's canonical history that this form does not store (-1: none). Restart files
    /// hold the canonical layout: historySize() + 1 doubles per contact with 0 in this slot.
    virtual int omittedSlot() const { return -1; }
    int canonicalHistorySize() const { return historySize() + (omittedSlot() >= 0 ? 1 : 0); }
    /// Doubles of history per wall contact (a one-coefficient form keeps the canonical layout there).
    virtual int wallHistorySize() const { return historySize(); }
    /// Throw InputError naming `who` if a parameter this law uses is out of range.
    virtual void validate(const ContactParameters& p, const std::string& who) const = 0;
    /// Largest stiffness of any part (for the time step), and the normal dashpot.
    virtual double stiffness(const ContactParameters& p, double rEff) const = 0;
    virtual double normalDamping(const ContactParameters& p) const = 0;
    /// The law as a pure function of one contact: updates `history` in place.
    virtual void evaluate(const ContactParameters& p, const ContactState& s, double* history, ContactOutput& out) const = 0;
    virtual void computePairForces(ForceContext& c) const = 0;
    virtual void computeWallForces(ForceContext& c) const = 0;
};

/// Create a registered law by name; InputError listing the known names otherwise.
std::unique_ptr<ContactLaw> makeContactLaw(const std::string& name);
/// Names of all registered laws, with a one-line description each.
std::vector<std::pair<std::string, std::string>> contactLawNames();

} // namespace pdpm
