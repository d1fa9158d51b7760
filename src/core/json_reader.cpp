#include "core/json_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

#include "core/error.h"

namespace voxlux {
namespace {

std::string typeName(const nlohmann::json& v) { return v.type_name(); }

// A JSON number as a float, or nothing when it has none (beyond +-FLT_MAX): converting such a
// double to float is undefined, and the kernel would see infinity.
std::optional<float> asFloat(const nlohmann::json& v) {
    const double d = v.get<double>();
    if (!(std::fabs(d) <= double(std::numeric_limits<float>::max()))) return std::nullopt;
    return float(d);
}

std::string numberText(const nlohmann::json& v) { return v.dump(); }

std::string joined(const std::vector<std::string>& words) {
    std::string out;
    for (const auto& w : words) out += (out.empty() ? "" : ", ") + w;
    return out;
}

// Length of the UTF-8 sequence starting at s[i], or 0 when the bytes there are not one.
size_t utf8Length(const std::string& s, size_t i) {
    const unsigned char lead = static_cast<unsigned char>(s[i]);
    const size_t n = lead < 0x80 ? 1 : lead >= 0xC2 && lead <= 0xDF ? 2 : lead >= 0xE0 && lead <= 0xEF ? 3
                                     : lead >= 0xF0 && lead <= 0xF4 ? 4 : 0;
    if (n == 0 || i + n > s.size()) return 0;
    for (size_t k = 1; k < n; ++k)
        if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return 0;
    return n;
}

std::string escapedBytes(const std::string& s) {
    std::string out;
    for (size_t i = 0; i < s.size();) {
        if (const size_t n = utf8Length(s, i)) {
            out.append(s, i, n);
            i += n;
        } else {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02X", static_cast<unsigned char>(s[i++]));
            out += hex;
        }
    }
    return out;
}

void escapeStrings(nlohmann::json& j) {
    if (j.is_string()) j = escapedBytes(j.get_ref<const std::string&>());
    else if (j.is_structured())
        for (auto& child : j) escapeStrings(child);
}

}  // namespace

JsonObject::JsonObject(const nlohmann::json& value, std::string file, std::string pointer)
    : value_(value), file_(std::move(file)), pointer_(std::move(pointer)) {
    if (!value_.is_object())
        throw InputError(file_ + ": " + (pointer_.empty() ? "/" : pointer_) +
                         ": expected an object, got " + typeName(value_));
}

std::string JsonObject::pointer(const std::string& key) const { return pointer_ + "/" + key; }

void JsonObject::fail(const std::string& key, const std::string& problem) const {
    throw InputError(file_ + ": " + pointer(key) + ": " + problem);
}

void JsonObject::fail(const std::string& problem) const {
    throw InputError(file_ + ": " + (pointer_.empty() ? "/" : pointer_) + ": " + problem);
}

// A key set to null is present: it is refused by type ("expected a number, got null"), never read
// as its default, so a NaN that became null on its way is caught.
bool JsonObject::has(const std::string& key) const { return value_.contains(key); }

const nlohmann::json& JsonObject::raw(const std::string& key) const {
    if (!has(key)) fail(key, "required key is missing");
    return value_.at(key);
}

float JsonObject::number(const std::string& key) const {
    const auto& v = raw(key);
    if (!v.is_number()) fail(key, "expected a number, got " + typeName(v));
    const std::optional<float> f = asFloat(v);
    if (!f) fail(key, numberText(v) + " is beyond the float range (+-3.4e38)");
    return *f;
}

float JsonObject::number(const std::string& key, float fallback) const {
    return has(key) ? number(key) : fallback;
}

int JsonObject::integer(const std::string& key, int fallback) const {
    if (!has(key)) return fallback;
    const auto& v = raw(key);
    if (!v.is_number_integer()) fail(key, "expected an integer, got " + typeName(v));
    // Read wide and checked: get<int>() would wrap 4294967297 to 1.
    const bool fits = v.is_number_unsigned() ? v.get<uint64_t>() <= uint64_t(std::numeric_limits<int>::max())
                                             : v.get<int64_t>() >= std::numeric_limits<int>::min() &&
                                                   v.get<int64_t>() <= std::numeric_limits<int>::max();
    if (!fits) fail(key, numberText(v) + " is beyond the int range");
    return v.get<int>();
}

bool JsonObject::boolean(const std::string& key, bool fallback) const {
    if (!has(key)) return fallback;
    const auto& v = raw(key);
    if (!v.is_boolean()) fail(key, "expected true or false, got " + typeName(v));
    return v.get<bool>();
}

std::string JsonObject::string(const std::string& key) const {
    const auto& v = raw(key);
    if (!v.is_string()) fail(key, "expected a string, got " + typeName(v));
    return v.get<std::string>();
}

std::string JsonObject::string(const std::string& key, const std::string& fallback) const {
    return has(key) ? string(key) : fallback;
}

std::string JsonObject::choice(const std::string& key, const std::vector<std::string>& choices,
                               const std::string& fallback) const {
    std::string s = string(key, fallback);
    if (std::find(choices.begin(), choices.end(), s) == choices.end())
        fail(key, "'" + s + "' is not one of " + joined(choices));
    return s;
}

std::vector<float> JsonObject::numbers(const std::string& key, size_t count) const {
    const auto& v = raw(key);
    if (!v.is_array() || v.size() != count)
        fail(key, "expected an array of " + std::to_string(count) + " numbers");
    std::vector<float> out;
    for (const auto& e : v) {
        if (!e.is_number()) fail(key, "expected an array of " + std::to_string(count) + " numbers");
        const std::optional<float> f = asFloat(e);
        if (!f) fail(key, numberText(e) + " is beyond the float range (+-3.4e38)");
        out.push_back(*f);
    }
    return out;
}

glm::vec3 JsonObject::vec3(const std::string& key) const {
    auto n = numbers(key, 3);
    return {n[0], n[1], n[2]};
}

glm::vec3 JsonObject::vec3(const std::string& key, glm::vec3 fallback) const {
    return has(key) ? vec3(key) : fallback;
}

JsonObject JsonObject::object(const std::string& key) const {
    return JsonObject(raw(key), file_, pointer(key));
}

std::vector<JsonObject> JsonObject::objects(const std::string& key) const {
    const auto& v = raw(key);
    if (!v.is_array()) fail(key, "expected an array, got " + typeName(v));
    std::vector<JsonObject> out;
    for (size_t i = 0; i < v.size(); ++i)
        out.emplace_back(v[i], file_, pointer(key) + "/" + std::to_string(i));
    return out;
}

JsonObject JsonObject::element(const std::string& key, size_t index) const {
    return JsonObject(raw(key).at(index), file_, pointer(key) + "/" + std::to_string(index));
}

void JsonObject::rejectUnknown(const std::vector<std::string>& known) const {
    for (const auto& [key, _] : value_.items())
        if (std::find(known.begin(), known.end(), key) == known.end())
            fail(key, "unknown key (expected one of " + joined(known) + ")");
}

std::string jsonText(const nlohmann::json& json, int indent) {
    try {
        return json.dump(indent);
    } catch (const nlohmann::json::type_error&) {  // a string that is not UTF-8
        nlohmann::json escaped = json;
        escapeStrings(escaped);
        return escaped.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
    }
}

void checkJsonDepth(const std::string& text, const std::string& source) {
    int depth = 0, line = 1;
    bool in_string = false, escaped = false;
    for (char c : text) {
        if (c == '\n') ++line;
        if (in_string) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth)
                throw InputError(source + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels at line " +
                                 std::to_string(line));
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

nlohmann::json parseJson(const std::string& text, const std::string& file) {
    checkJsonDepth(text, file);
    try {
        return nlohmann::json::parse(text);
    } catch (const nlohmann::json::out_of_range& e) {
        // A number too large for a double: "number overflow parsing '1e400'".
        std::string what = e.what();
        if (auto close = what.find("] "); close != std::string::npos) what = what.substr(close + 2);
        throw InputError(file + ": malformed JSON: " + what);
    } catch (const nlohmann::json::parse_error& e) {
        // e.what() is "[json.exception.parse_error.101] parse error at line L, column C: syntax error
        // while parsing <what> - <problem>"; keep the position and the problem.
        std::string what = e.what();
        std::string where;
        if (auto at = what.find("at line "); at != std::string::npos) where = what.substr(at, what.find(':', at) - at);
        if (auto dash = what.find(" - "); dash != std::string::npos) what = what.substr(dash + 3);
        throw InputError(file + ": malformed JSON" + (where.empty() ? "" : " " + where) + ": " + what);
    }
}

std::string readFileText(const std::string& path, const std::string& what) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open " + what);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

}  // namespace voxlux
