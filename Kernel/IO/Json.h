// A small strict JSON reader/writer (RFC 8259) for protocol and metadata files.
//
// Reading is strict: no comments, no trailing commas, no NaN/Infinity, no leading zeros, no
// duplicate object keys, no control characters in strings, nothing after the value but white space,
// nesting depth <= 256. Numbers must be finite doubles. \uXXXX escapes (with surrogate pairs) become
// UTF-8. Every error throws pdpm::InputError "SOURCE:LINE:COLUMN: message".
//
// Objects keep their members in file order. Writing produces indented, deterministic text; numbers
// use the shortest representation that reads back exactly.
#pragma once
#include <cstddef>
#include <initializer_list>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace pdpm {

class Json {
public:
    enum class Type { Null, Bool, Number, String, Array, Object };
    using Member = std::pair<std::string, Json>;

    Json() = default;                                  ///< null
    Json(std::nullptr_t) {}                            ///< null
    Json(bool b) : type_(Type::Bool), bool_(b) {}
    Json(double x);                                    ///< InputError if not finite
    Json(int x) : Json(static_cast<double>(x)) {}
    Json(long x) : Json(static_cast<double>(x)) {}
    Json(const char* s) : type_(Type::String), string_(s) {}
    Json(std::string s) : type_(Type::String), string_(std::move(s)) {}

    static Json array(std::vector<Json> items = {});
    static Json object(std::vector<Member> members = {});

    Type type() const { return type_; }
    bool isNull() const { return type_ == Type::Null; }
    bool isBool() const { return type_ == Type::Bool; }
    bool isNumber() const { return type_ == Type::Number; }
    bool isString() const { return type_ == Type::String; }
    bool isArray() const { return type_ == Type::Array; }
    bool isObject() const { return type_ == Type::Object; }

    // Typed access; InputError "WHAT: expected a number (got a string)" on the wrong type.
    bool asBool(const std::string& what = "value") const;
    double asNumber(const std::string& what = "value") const;
    const std::string& asString(const std::string& what = "value") const;
    const std::vector<Json>& asArray(const std::string& what = "value") const;
    const std::vector<Member>& asObject(const std::string& what = "value") const;

    // Object access.
    bool has(const std::string& key) const;
    /// Member `key`; InputError naming the key if absent or if this is not an object.
    const Json& at(const std::string& key) const;
    /// Member `key` or nullptr.
    const Json* find(const std::string& key) const;
    /// Adds or replaces a member (keeps the position of an existing key). This must be an object.
    Json& set(const std::string& key, Json value);
    /// Appends to an array.
    Json& push(Json value);
    std::size_t size() const;  ///< elements of an array / members of an object, else 0

    bool operator==(const Json& o) const;

    /// Indented text (indent 0: one line), with a final newline when indent > 0.
    std::string dump(int indent = 2) const;
    static const char* typeName(Type t);

private:
    void write(std::string& out, int indent, int level) const;
    Type type_ = Type::Null;
    bool bool_ = false;
    double number_ = 0;
    std::string string_;
    std::vector<Json> array_;
    std::vector<Member> object_;
};

/// Parses JSON text; `source` names it in error messages.
Json parseJson(const std::string& text, const std::string& source = "json");
/// Reads and parses a file (InputError if missing or malformed).
Json readJsonFile(const std::string& path);
/// Writes a value atomically (AtomicOFStream).
void writeJsonFile(const std::string& path, const Json& value);

} // namespace pdpm
