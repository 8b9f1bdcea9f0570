#include "Contacts/SpeciesTable.h"

#include <cmath>

#include "Core/Error.h"

namespace pdpm {

int SpeciesTable::add(const std::string& name, double density, const ContactParameters& self) {
    if (!(density > 0) || !std::isfinite(density))
        inputError("species '" + name + "': density must be > 0");
    const std::size_t n = n_ + 1;
    std::vector<ContactParameters> t(n * n);
    for (std::size_t a = 0; a < n_; ++a)
        for (std::size_t b = 0; b < n_; ++b) t[a * n + b] = table_[a * n_ + b];
    table_ = std::move(t);
    n_ = n;
    species_.push_back({name, density});
    const int idx = static_cast<int>(n_ - 1);
    setPair(idx, idx, self);
    return idx;
}

void SpeciesTable::setPair(int a, int b, const ContactParameters& p) {
    if (a < 0 || b < 0 || a >= size() || b >= size()) inputError("species pair index out of range");
    ContactParameters q = p;
    q.defined = true;
    table_[static_cast<std::size_t>(a) * n_ + b] = q;
    table_[static_cast<std::size_t>(b) * n_ + a] = q;
    ++revision_;
}

int SpeciesTable::find(const std::string& name) const {
    for (std::size_t a = 0; a < species_.size(); ++a)
        if (species_[a].name == name) return static_cast<int>(a);
    return -1;
}

} // namespace pdpm
