#include "IO/Json.h"

#include <charconv>
#include <cmath>
#include <cstdint>

#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "IO/NumberFormat.h"

namespace pdpm {

Json::Json(double x) : type_(Type::Number), number_(x) {
    if (!std::isfinite(x)) inputError("json: numbers must be finite");
}

Json Json::array(std::vector<Json> items) {
    Json j;
    j.type_ = Type::Array;
    j.array_ = std::move(items);
    return j;
}

Json Json::object(std::vector<Member> members) {
    Json j;
    j.type_ = Type::Object;
    for (auto& m : members) j.set(m.first, std::move(m.second));
    return j;
}

const char* Json::typeName(Type t) {
    switch (t) {
        case Type::Null: return "null";
        case Type::Bool: return "a boolean";
        case Type::Number: return "a number";
        case Type::String: return "a string";
        case Type::Array: return "an array";
        case Type::Object: return "an object";
    }
    return "?";
}

namespace {
[[noreturn]] void typeError(const std::string& what, const char* expected, Json::Type got) {
    inputError(what + ": expected " + expected + " (got " + Json::typeName(got) + ")");
}
} // namespace

bool Json::asBool(const std::string& what) const {
    if (type_ != Type::Bool) typeError(what, "a boolean", type_);
    return bool_;
}
double Json::asNumber(const std::string& what) const {
    if (type_ != Type::Number) typeError(what, "a number", type_);
    return number_;
}
const std::string& Json::asString(const std::string& what) const {
    if (type_ != Type::String) typeError(what, "a string", type_);
    return string_;
}
const std::vector<Json>& Json::asArray(const std::string& what) const {
    if (type_ != Type::Array) typeError(what, "an array", type_);
    return array_;
}
const std::vector<Json::Member>& Json::asObject(const std::string& what) const {
    if (type_ != Type::Object) typeError(what, "an object", type_);
    return object_;
}

const Json* Json::find(const std::string& key) const {
    if (type_ != Type::Object) return nullptr;
    for (const auto& m : object_)
        if (m.first == key) return &m.second;
    return nullptr;
}
bool Json::has(const std::string& key) const { return find(key) != nullptr; }
const Json& Json::at(const std::string& key) const {
    if (type_ != Type::Object) typeError("'" + key + "'", "an object containing it", type_);
    const Json* j = find(key);
    if (!j) inputError("missing key '" + key + "'");
    return *j;
}
Json& Json::set(const std::string& key, Json value) {
    if (type_ == Type::Null) type_ = Type::Object;
    if (type_ != Type::Object) typeError("set '" + key + "'", "an object", type_);
    for (auto& m : object_)
        if (m.first == key) {
            m.second = std::move(value);
            return m.second;
        }
    object_.emplace_back(key, std::move(value));
    return object_.back().second;
}
Json& Json::push(Json value) {
    if (type_ == Type::Null) type_ = Type::Array;
    if (type_ != Type::Array) typeError("push", "an array", type_);
    array_.push_back(std::move(value));
    return array_.back();
}
std::size_t Json::size() const {
    if (type_ == Type::Array) return array_.size();
    if (type_ == Type::Object) return object_.size();
    return 0;
}

bool Json::operator==(const Json& o) const {
    if (type_ != o.type_) return false;
    switch (type_) {
        case Type::Null: return true;
        case Type::Bool: return bool_ == o.bool_;
        case Type::Number: return number_ == o.number_;
        case Type::String: return string_ == o.string_;
        case Type::Array: return array_ == o.array_;
        case Type::Object: return object_ == o.object_;
    }
    return false;
}

namespace {
/// Length of the well-formed UTF-8 sequence that starts at byte p of t (a byte >= 0x80), 0 if there is
/// none: no stray continuation byte, no overlong form, no surrogate, nothing above U+10FFFF.
std::size_t utf8SequenceLength(const std::string& t, std::size_t p) {
    const auto at = [&](std::size_t k) { return k < t.size() ? static_cast<unsigned char>(t[k]) : 0u; };
    const unsigned c = at(p);
    const auto cont = [&](std::size_t k) { return (at(k) & 0xC0u) == 0x80u; };
    if (c >= 0xC2 && c <= 0xDF) return cont(p + 1) ? 2 : 0;
    if (c >= 0xE0 && c <= 0xEF) {
        const unsigned c1 = at(p + 1);
        if (!cont(p + 1) || !cont(p + 2)) return 0;
        if ((c == 0xE0 && c1 < 0xA0) || (c == 0xED && c1 > 0x9F)) return 0;  // overlong, surrogate
        return 3;
    }
    if (c >= 0xF0 && c <= 0xF4) {
        const unsigned c1 = at(p + 1);
        if (!cont(p + 1) || !cont(p + 2) || !cont(p + 3)) return 0;
        if ((c == 0xF0 && c1 < 0x90) || (c == 0xF4 && c1 > 0x8F)) return 0;  // overlong, > U+10FFFF
        return 4;
    }
    return 0;
}
} // namespace

// ---- writing -------------------------------------------------------------------------------------

namespace {
void writeString(std::string& out, const std::string& s) {
    out += '"';
    for (std::size_t i = 0; i < s.size(); ++i) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        if (c >= 0x80) {
            // well-formed UTF-8 is copied; any other byte (a Latin-1 file name, say) is written as the
            // character it stands for in Latin-1, so that every file written here reads back
            const std::size_t n = utf8SequenceLength(s, i);
            if (n > 0) {
                out.append(s, i, n);
                i += n - 1;
            } else {
                out += static_cast<char>(0xC0 | (c >> 6));
                out += static_cast<char>(0x80 | (c & 0x3F));
            }
            continue;
        }
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\b': out += "\\b"; break;
            case '\f': out += "\\f"; break;
            case '\n': out += "\\n"; break;
            case '\r': out += "\\r"; break;
            case '\t': out += "\\t"; break;
            default:
                if (c < 0x20) {
                    static const char* hex = "0123456789abcdef";
                    out += "\\u00";
                    out += hex[c >> 4];
                    out += hex[c & 15];
                } else {
                    out += static_cast<char>(c);
                }
        }
    }
    out += '"';
}
void newline(std::string& out, int indent, int level) {
    if (indent <= 0) return;
    out += '\n';
    out.append(static_cast<std::size_t>(indent * level), ' ');
}
} // namespace

void Json::write(std::string& out, int indent, int level) const {
    switch (type_) {
        case Type::Null: out += "null"; return;
        case Type::Bool: out += bool_ ? "true" : "false"; return;
        case Type::Number: out += fmt(number_); return;
        case Type::String: writeString(out, string_); return;
        case Type::Array: {
            if (array_.empty()) { out += "[]"; return; }
            // Arrays of plain numbers stay on one line (readable tables).
            bool flat = true;
            for (const auto& a : array_) flat = flat && (a.isNumber() || a.isBool() || a.isNull());
            out += '[';
            for (std::size_t k = 0; k < array_.size(); ++k) {
                if (k) out += flat && indent > 0 ? ", " : ",";
                if (!flat) newline(out, indent, level + 1);
                array_[k].write(out, indent, level + 1);
            }
            if (!flat) newline(out, indent, level);
            out += ']';
            return;
        }
        case Type::Object: {
            if (object_.empty()) { out += "{}"; return; }
            out += '{';
            for (std::size_t k = 0; k < object_.size(); ++k) {
                if (k) out += ',';
                newline(out, indent, level + 1);
                writeString(out, object_[k].first);
                out += indent > 0 ? ": " : ":";
                object_[k].second.write(out, indent, level + 1);
            }
            newline(out, indent, level);
            out += '}';
            return;
        }
    }
}

std::string Json::dump(int indent) const {
    std::string out;
    write(out, indent, 0);
    if (indent > 0) out += '\n';
    return out;
}

// ---- parsing -------------------------------------------------------------------------------------

namespace {
class Parser {
public:
    Parser(const std::string& text, const std::string& source) : t_(text), src_(source) {}

    Json parseDocument() {
        skipWs();
        Json v = value(0);
        skipWs();
        if (pos_ < t_.size()) fail("unexpected text after the JSON value");
        return v;
    }

private:
    [[noreturn]] void fail(const std::string& msg) const {
        std::size_t line = 1, col = 1;
        for (std::size_t k = 0; k < pos_ && k < t_.size(); ++k) {
            if (t_[k] == '\n') { ++line; col = 1; } else { ++col; }
        }
        inputError(src_ + ":" + std::to_string(line) + ":" + std::to_string(col) + ": " + msg);
    }
    void skipWs() {
        while (pos_ < t_.size() && (t_[pos_] == ' ' || t_[pos_] == '\t' || t_[pos_] == '\n' || t_[pos_] == '\r')) ++pos_;
    }
    char peek() const { return pos_ < t_.size() ? t_[pos_] : '\0'; }
    void expectLiteral(const char* lit) {
        for (const char* c = lit; *c; ++c) {
            if (pos_ >= t_.size() || t_[pos_] != *c) fail(std::string("invalid literal (expected '") + lit + "')");
            ++pos_;
        }
    }
    Json value(int depth) {
        if (depth > 256) fail("nesting deeper than 256");
        if (pos_ >= t_.size()) fail("unexpected end of input (expected a value)");
        const char c = t_[pos_];
        switch (c) {
            case '{': return object(depth);
            case '[': return array(depth);
            case '"': return Json(string());
            case 't': expectLiteral("true"); return Json(true);
            case 'f': expectLiteral("false"); return Json(false);
            case 'n': expectLiteral("null"); return Json();
            default:
                if (c == '-' || (c >= '0' && c <= '9')) return Json(number());
                fail(std::string("unexpected character '") + c + "'");
        }
    }
    Json object(int depth) {
        ++pos_;  // {
        Json obj = Json::object();
        skipWs();
        if (peek() == '}') { ++pos_; return obj; }
        for (;;) {
            skipWs();
            if (peek() != '"') fail("expected a string key");
            const std::size_t keyPos = pos_;
            std::string key = string();
            if (obj.has(key)) { pos_ = keyPos; fail("duplicate key '" + key + "'"); }
            skipWs();
            if (peek() != ':') fail("expected ':' after a key");
            ++pos_;
            skipWs();
            obj.set(key, value(depth + 1));
            skipWs();
            if (peek() == ',') { ++pos_; skipWs(); if (peek() == '}') fail("trailing comma"); continue; }
            if (peek() == '}') { ++pos_; return obj; }
            fail("expected ',' or '}' in an object");
        }
    }
    Json array(int depth) {
        ++pos_;  // [
        Json arr = Json::array();
        skipWs();
        if (peek() == ']') { ++pos_; return arr; }
        for (;;) {
            skipWs();
            arr.push(value(depth + 1));
            skipWs();
            if (peek() == ',') { ++pos_; skipWs(); if (peek() == ']') fail("trailing comma"); continue; }
            if (peek() == ']') { ++pos_; return arr; }
            fail("expected ',' or ']' in an array");
        }
    }
    unsigned hex4() {
        if (pos_ + 4 > t_.size()) fail("truncated \\u escape");
        unsigned v = 0;
        for (int k = 0; k < 4; ++k) {
            const char c = t_[pos_++];
            v <<= 4;
            if (c >= '0' && c <= '9') v |= static_cast<unsigned>(c - '0');
            else if (c >= 'a' && c <= 'f') v |= static_cast<unsigned>(c - 'a' + 10);
            else if (c >= 'A' && c <= 'F') v |= static_cast<unsigned>(c - 'A' + 10);
            else { --pos_; fail("invalid hex digit in \\u escape"); }
        }
        return v;
    }
    static void utf8(std::string& out, unsigned cp) {
        if (cp < 0x80) out += static_cast<char>(cp);
        else if (cp < 0x800) { out += static_cast<char>(0xC0 | (cp >> 6)); out += static_cast<char>(0x80 | (cp & 0x3F)); }
        else if (cp < 0x10000) {
            out += static_cast<char>(0xE0 | (cp >> 12));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        } else {
            out += static_cast<char>(0xF0 | (cp >> 18));
            out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        }
    }
    std::string string() {
        ++pos_;  // "
        std::string out;
        for (;;) {
            if (pos_ >= t_.size()) fail("unterminated string");
            const unsigned char c = static_cast<unsigned char>(t_[pos_]);
            if (c == '"') { ++pos_; return out; }
            if (c < 0x20) fail("control character in a string (escape it)");
            if (c >= 0x80) {  // a multi-byte UTF-8 sequence (JSON text is UTF-8, RFC 8259), copied whole
                const std::size_t n = utf8SequenceLength(t_, pos_);
                if (n == 0) fail("invalid UTF-8 byte in a string");
                out.append(t_, pos_, n);
                pos_ += n;
                continue;
            }
            if (c != '\\') { out += static_cast<char>(c); ++pos_; continue; }
            ++pos_;
            if (pos_ >= t_.size()) fail("unterminated escape");
            const char e = t_[pos_++];
            switch (e) {
                case '"': out += '"'; break;
                case '\\': out += '\\'; break;
                case '/': out += '/'; break;
                case 'b': out += '\b'; break;
                case 'f': out += '\f'; break;
                case 'n': out += '\n'; break;
                case 'r': out += '\r'; break;
                case 't': out += '\t'; break;
                case 'u': {
                    unsigned cp = hex4();
                    if (cp >= 0xD800 && cp <= 0xDBFF) {
                        if (pos_ + 2 > t_.size() || t_[pos_] != '\\' || t_[pos_ + 1] != 'u') fail("unpaired surrogate in \\u escape");
                        pos_ += 2;
                        const unsigned lo = hex4();
                        if (lo < 0xDC00 || lo > 0xDFFF) fail("invalid low surrogate in \\u escape");
                        cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
                    } else if (cp >= 0xDC00 && cp <= 0xDFFF) {
                        fail("unpaired surrogate in \\u escape");
                    }
                    utf8(out, cp);
                    break;
                }
                default: --pos_; fail(std::string("invalid escape '\\") + e + "'");
            }
        }
    }
    double number() {
        const std::size_t start = pos_;
        if (peek() == '-') ++pos_;
        if (peek() == '0') {
            ++pos_;
            if (peek() >= '0' && peek() <= '9') fail("leading zeros are not allowed");
        } else if (peek() >= '1' && peek() <= '9') {
            while (peek() >= '0' && peek() <= '9') ++pos_;
        } else {
            fail("invalid number");
        }
        if (peek() == '.') {
            ++pos_;
            if (!(peek() >= '0' && peek() <= '9')) fail("invalid number (digit expected after '.')");
            while (peek() >= '0' && peek() <= '9') ++pos_;
        }
        if (peek() == 'e' || peek() == 'E') {
            ++pos_;
            if (peek() == '+' || peek() == '-') ++pos_;
            if (!(peek() >= '0' && peek() <= '9')) fail("invalid number (digit expected in exponent)");
            while (peek() >= '0' && peek() <= '9') ++pos_;
        }
        double x = 0;
        const char* b = t_.data() + start;
        const char* e = t_.data() + pos_;
        const auto res = std::from_chars(b, e, x);
        if (res.ec != std::errc() || res.ptr != e || !std::isfinite(x)) {
            pos_ = start;
            fail("number out of range");
        }
        return x;
    }

    const std::string& t_;
    std::string src_;
    std::size_t pos_ = 0;
};
} // namespace

Json parseJson(const std::string& text, const std::string& source) { return Parser(text, source).parseDocument(); }

Json readJsonFile(const std::string& path) { return parseJson(readWholeFile(path), path); }

void writeJsonFile(const std::string& path, const Json& value) { writeWholeFile(path, value.dump(2)); }

} // namespace pdpm
