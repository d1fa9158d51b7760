// Past outputs of the stages that share them (Stage::sharedOutput), kept by stage and key within
// a memory budget, the least recently used dropped first: a viewer scrubbing a sequence takes a
// frame's grids and bricks back instead of reading and densifying the file again. The render
// graph keeps an output here when its key moves on, and looks here before running a stage.
// Cost: the budget's memory (0, the default, keeps nothing); a lookup is a map search.
#pragma once
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <typeinfo>
#include <utility>
#include <vector>

namespace voxlux {

// A stage's output as the cache holds it: shared, and knowing its type, so that it is taken back
// only as what it is (`as` refuses another type).
class SharedOutput {
public:
    SharedOutput() = default;
    template <class T>
    SharedOutput(std::shared_ptr<const T> value) : value_(std::move(value)), type_(&typeid(T)) {}
    explicit operator bool() const { return value_ != nullptr; }
    template <class T>
    std::shared_ptr<const T> as() const {
        if (!value_ || *type_ != typeid(T)) throw std::logic_error("output cache: an output taken back as another type");
        return std::static_pointer_cast<const T>(value_);
    }

private:
    std::shared_ptr<const void> value_;
    const std::type_info* type_ = nullptr;
};

struct CachedOutput {
    SharedOutput value;                  // the stage's own type: only that stage adopts it
    size_t bytes = 0;
    std::vector<std::string> warnings;   // the stage's output warnings, repeated when it is reused
};

class OutputCache {
public:
    void setBudget(size_t bytes);
    size_t budget() const { return budget_; }
    size_t bytes() const { return bytes_; }
    size_t entries() const { return entries_.size(); }

    // Keeps `output` of `stage` under `key`, then drops the least recently used outputs until the
    // cache fits its budget (an output larger than the budget, or any with a budget of 0, is not
    // kept).
    void keep(const std::string& stage, const std::string& key, CachedOutput output);
    // The output of `stage` kept under `key`, now the most recently used, or null.
    const CachedOutput* find(const std::string& stage, const std::string& key);

private:
    struct Entry {
        CachedOutput output;
        uint64_t used = 0;   // when it was last kept or found: higher is more recent
    };
    void fit();

    size_t budget_ = 0, bytes_ = 0;
    uint64_t clock_ = 0;
    std::map<std::pair<std::string, std::string>, Entry> entries_;
};

}  // namespace voxlux
