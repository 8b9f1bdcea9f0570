// In-situ use of the tools from a driver hook (e.g. writeOutputFiles or actionsAfterTimeStep):
// fill the tools' plain snapshot structs from a running simulation through DPMBase's public
// interface only, without writing particle files.
//
//   void writeOutputFiles() override {
//       DPMBase::writeOutputFiles();                    // contacts() are current at output steps
//       cg_.add(tools::particleSnapshot(*this), &contacts_ = tools::contactSnapshot(*this));
//   }
#pragma once
#include "Snapshot.h"
#include "Core/DPMBase.h"

namespace pdpm::tools {

/// Particles of `d` now (positions wrapped into the periodic box, coordination from the last
/// contact records when they are current).
ParticleSnapshot particleSnapshot(const DPMBase& d);
/// Contacts of `d` at its last recorded step (DPMBase::contacts()); call d.refreshContacts() first
/// when d.contactsAreCurrent() is false.
ContactSnapshot contactSnapshot(const DPMBase& d);

} // namespace pdpm::tools
