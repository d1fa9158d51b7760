// Strict reading of a JSON object: every error names the file and the JSON pointer of the bad
// key, and keys nobody asked for are reported (they are usually typos).
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace voxlux {

class JsonObject {
public:
    // `file` is used in messages; `pointer` is the JSON pointer of `value` ("" for the root).
    // Keeps a reference: `value` must outlive this object.
    JsonObject(const nlohmann::json& value, std::string file, std::string pointer);

    bool has(const std::string& key) const;
    float number(const std::string& key, float fallback) const;
    float number(const std::string& key) const;
    int integer(const std::string& key, int fallback) const;
    bool boolean(const std::string& key, bool fallback) const;
    std::string string(const std::string& key) const;
    std::string string(const std::string& key, const std::string& fallback) const;
    // One of `choices`; the message lists them.
    std::string choice(const std::string& key, const std::vector<std::string>& choices,
                       const std::string& fallback) const;
    glm::vec3 vec3(const std::string& key, glm::vec3 fallback) const;
    glm::vec3 vec3(const std::string& key) const;
    std::vector<float> numbers(const std::string& key, size_t count) const;
    JsonObject object(const std::string& key) const;
    std::vector<JsonObject> objects(const std::string& key) const;
    // Element `index` of the array at `key`, which must be an object (arrays mixing kinds).
    JsonObject element(const std::string& key, size_t index) const;
    const nlohmann::json& raw(const std::string& key) const;
    std::string pointer(const std::string& key) const;

    // Throws for any key not in `known`.
    void rejectUnknown(const std::vector<std::string>& known) const;

    [[noreturn]] void fail(const std::string& key, const std::string& problem) const;
    // About the object itself rather than one of its keys.
    [[noreturn]] void fail(const std::string& problem) const;

private:
    const nlohmann::json& value_;
    std::string file_;
    std::string pointer_;
};

// Deepest nesting of arrays and objects voxlux reads. Scenes need 4 levels; the limit keeps every
// recursive walk over a document (the reader's, the library's) far from the end of the stack.
constexpr int kMaxJsonDepth = 64;

// Throws InputError "<source>: JSON nested deeper than 64 levels at line L" when `text` opens more
// than kMaxJsonDepth arrays or objects at once (text in strings does not count). One pass, no
// allocation: it runs before the parser ever recurses.
void checkJsonDepth(const std::string& text, const std::string& source);

// `json` as text for keys, hashes and printing; never throws. File names are bytes, not always
// UTF-8 (a Latin-1 "caf\xe9.vdb"): bytes that are not UTF-8 are written as the text \xHH.
std::string jsonText(const nlohmann::json& json, int indent = -1);

// The bytes of the file at `path`; throws InputError "<path>: cannot open <what>".
std::string readFileText(const std::string& path, const std::string& what);

// Parses `text` (read from `file`); syntax errors give line and column, nesting past
// kMaxJsonDepth is refused.
nlohmann::json parseJson(const std::string& text, const std::string& file);

}  // namespace voxlux
