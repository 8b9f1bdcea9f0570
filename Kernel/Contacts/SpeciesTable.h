// Species (material) definitions and the explicit parameters of every species pair.
// Walls have a species too; its density is unused.
#pragma once
#include <string>
#include <vector>

#include "Contacts/ContactParameters.h"

namespace pdpm {

struct Species {
    std::string name;
    double density = 0;
};

class SpeciesTable {
public:
    /// Add a species; its self-interaction parameters are `self`. Returns its index.
    int add(const std::string& name, double density, const ContactParameters& self);
    /// Explicit parameters of the pair (a, b) (symmetric).
    void setPair(int a, int b, const ContactParameters& p);
    const ContactParameters& pair(int a, int b) const { return table_[static_cast<std::size_t>(a) * n_ + b]; }
    ContactParameters& pairMutable(int a, int b) {
        ++revision_;
        return table_[static_cast<std::size_t>(a) * n_ + b];
    }
    /// Changes whenever the table may have changed (add, setPair, pairMutable, clear): DPMBase then
    /// asks the contact law again which form fits (ContactLaw::specialised).
    unsigned long revision() const { return revision_; }
    const Species& operator[](int a) const { return species_.at(a); }
    int size() const { return static_cast<int>(n_); }
    int find(const std::string& name) const;  ///< -1 if absent
    void clear() { species_.clear(); table_.clear(); n_ = 0; ++revision_; }

private:
    std::vector<Species> species_;
    std::vector<ContactParameters> table_;
    std::size_t n_ = 0;
    unsigned long revision_ = 0;
};

} // namespace pdpm
