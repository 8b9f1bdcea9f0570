// Named scalar fields of a driver's own state, for restart files: a driver binds each member once
// (in its constructor), and saveDriverState / loadDriverState call save() and load(), so the list
// of fields exists in one place. Values are written with fmt() (round-trip exact).
#pragma once
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "Core/Error.h"
#include "IO/NumberFormat.h"

namespace pdpm {

class StateFields {
public:
    using KeyValues = std::vector<std::pair<std::string, std::string>>;

    template <class T>
    StateFields& add(const std::string& name, T& member) {
        fields_.push_back({name, &member});
        return *this;
    }

    void save(KeyValues& kv) const {
        for (const auto& f : fields_)
            std::visit([&](auto* p) { kv.emplace_back(f.name, fmt(static_cast<double>(*p))); }, f.target);
    }

    /// Sets the field `key` from `value`; false if `key` is not a field. A malformed number (not
    /// finite; for an integer field not a whole number within its type; for a bool not 0 or 1) is an
    /// input error naming the field.
    bool load(const std::string& key, const std::string& value) const {
        for (const auto& f : fields_) {
            if (f.name != key) continue;
            double x = 0;
            const auto bad = [&] { inputError("restart file: bad value of driver state '" + key + "': '" + value + "'"); };
            if (!parseDouble(value, x)) bad();
            std::visit(
                [&](auto* p) {
                    using T = std::remove_pointer_t<decltype(p)>;
                    if constexpr (std::is_same_v<T, bool>) {
                        if (x != 0 && x != 1) bad();
                        *p = x != 0;
                    } else if constexpr (std::is_integral_v<T>) {
                        // whole numbers within the type (2^53 bounds what a double holds exactly)
                        const double lo = std::is_signed_v<T> ? -9007199254740992.0 : 0.0;
                        if (x != std::floor(x) || x < lo || x > 9007199254740992.0 ||
                            x < static_cast<double>(std::numeric_limits<T>::lowest()) ||
                            x > static_cast<double>(std::numeric_limits<T>::max()))
                            bad();
                        *p = static_cast<T>(x);
                    } else {
                        *p = static_cast<T>(x);
                    }
                },
                f.target);
            return true;
        }
        return false;
    }

    /// Every bound field must be in `kv` (a file edited after it was sealed could drop one, and the
    /// member would keep whatever the driver's set-up left in it).
    void requireAll(const KeyValues& kv) const;

private:
    struct Field {
        std::string name;
        std::variant<double*, bool*, std::size_t*, long*, int*> target;
    };
    std::vector<Field> fields_;
};

/// An input error naming the first of `keys` that `kv` lacks (the keys a driver's saveDriverState
/// always writes).
inline void requireDriverKeys(const StateFields::KeyValues& kv, const std::vector<std::string>& keys) {
    for (const auto& key : keys) {
        bool found = false;
        for (const auto& [k, v] : kv) found = found || k == key;
        if (!found) inputError("restart file: the driver state lacks '" + key + "' (file edited or written by another driver)");
    }
}

inline void StateFields::requireAll(const KeyValues& kv) const {
    std::vector<std::string> names;
    for (const auto& f : fields_) names.push_back(f.name);
    requireDriverKeys(kv, names);
}

/// Numbers separated by single spaces (fmt), "-" for none; splitNumbers() reads them back and
/// names `key` in the message on a malformed number.
inline std::string joinNumbers(const std::vector<double>& v) {
    std::string out;
    for (double x : v) {
        if (!out.empty()) out += ' ';
        out += fmt(x);
    }
    return out.empty() ? "-" : out;
}
inline std::vector<double> splitNumbers(const std::string& text, const std::string& key) {
    std::vector<double> out;
    if (text == "-") return out;
    std::istringstream is(text);
    for (std::string w; is >> w;) {
        double x = 0;
        if (!parseDouble(w, x)) inputError("restart file: bad number in driver state '" + key + "'");
        out.push_back(x);
    }
    return out;
}

} // namespace pdpm
