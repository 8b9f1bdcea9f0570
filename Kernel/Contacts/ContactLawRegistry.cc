// The one place where contact laws are registered by name. Adding a law = one line here.
#include <functional>
#include <map>

#include "Contacts/ComposedLaw.h"
#include "Contacts/RelaxationLaws.h"
#include "Contacts/ViscousLaws.h"
#include "Core/Error.h"

namespace pdpm {

namespace {
struct Entry {
    std::string description;
    std::function<std::unique_ptr<ContactLaw>(const std::string&)> make;
};

template <class N, class T, class R, class O>
Entry law(const std::string& description) {
    return {description, [](const std::string& n) { return std::make_unique<ComposedLaw<N, T, R, O>>(n); }};
}

const std::map<std::string, Entry>& registry() {
    static const std::map<std::string, Entry> r = {
        {"linear-frictionless", law<NormalLinear, NoPart, NoPart, NoPart>("linear spring-dashpot normal force only (Eq. 2.1)")},
        {"linear", law<NormalLinear, TangentialCoulomb, NoPart, NoPart>("linear normal + linear tangential spring-dashpot with Coulomb sliding")},
        {"linear-rolling", law<NormalLinear, TangentialCoulomb, RollingResistance, TorsionResistance>("linear + sliding, rolling and torsion friction")},
        {"hertz", law<NormalHertz, NoPart, NoPart, NoPart>("Hertz normal force with Tsuji-type damping, frictionless")},
        {"hertz-mindlin", law<NormalHertz, TangentialMindlin, NoPart, NoPart>("Hertz + Mindlin no-slip tangential with Coulomb sliding")},
        {"hertz-mindlin-rolling", law<NormalHertz, TangentialMindlin, RollingResistance, TorsionResistance>("Hertz-Mindlin + rolling and torsion friction")},
        {"luding", law<NormalLuding, TangentialCoulomb, RollingResistance, TorsionResistance>("Luding's hysteretic plastic-adhesive normal force (Eqs. 5.5-5.7) + sliding, rolling, torsion friction")},
        {"linear-relax", law<Relaxing<NormalLinear>, TangentialCoulomb, NoPart, NoPart>("linear + sliding friction, with the time-dependent relaxation of Eq. 4.1 (relaxC, relaxT0, relaxTimeScale, relaxMemory)")},
        {"hertz-mindlin-relax", law<Relaxing<NormalHertz>, TangentialMindlin, NoPart, NoPart>("Hertz-Mindlin with the time-dependent relaxation of Eq. 4.1")},
        {"hertz-rolling-relax", law<Relaxing<NormalHertz>, TangentialCoulomb, RollingResistance, TorsionResistance>("Hertz normal force + linear sliding, rolling and torsion friction (the parts of luding-relax around a Hertz normal force), with the time-dependent relaxation of Eq. 4.1")},
        {"luding-relax", law<Relaxing<NormalLuding>, TangentialCoulomb, RollingResistance, TorsionResistance>("Luding + sliding, rolling, torsion friction, with the time-dependent relaxation of Eq. 4.1")},
        {"linear-relax-viscous", law<LabViscous<Relaxing<NormalLinear>>, TangentialCoulomb, NoPart, NoPart>("linear-relax + a contact viscosity on the lab clock (Maxwell branch: viscTime, viscStiffnessRatio, viscTimeScale)")},
        {"luding-relax-viscous", law<LabViscous<Relaxing<NormalLuding>>, TangentialCoulomb, RollingResistance, TorsionResistance>("luding-relax + a contact viscosity on the lab clock (Maxwell branch: viscTime, viscStiffnessRatio, viscTimeScale)")},
    };
    return r;
}
} // namespace

std::unique_ptr<ContactLaw> makeContactLaw(const std::string& name) {
    const auto& r = registry();
    auto it = r.find(name);
    if (it == r.end()) {
        std::string known;
        for (const auto& [k, e] : r) known += (known.empty() ? "" : ", ") + k;
        inputError("unknown contact law '" + name + "' (known: " + known + ")");
    }
    return it->second.make(name);
}

std::vector<std::pair<std::string, std::string>> contactLawNames() {
    std::vector<std::pair<std::string, std::string>> out;
    for (const auto& [k, e] : registry()) out.emplace_back(k, e.description);
    return out;
}

} // namespace pdpm
