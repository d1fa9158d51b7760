#include "graph/output_cache.h"

#include <algorithm>

namespace voxlux {

void OutputCache::setBudget(size_t bytes) {
    budget_ = bytes;
    fit();
}

void OutputCache::keep(const std::string& stage, const std::string& key, CachedOutput output) {
    if (budget_ == 0 || output.bytes > budget_ || !output.value) return;
    Entry& e = entries_[{stage, key}];
    bytes_ -= e.output.bytes;
    bytes_ += output.bytes;
    e.output = std::move(output);
    e.used = ++clock_;
    fit();
}

const CachedOutput* OutputCache::find(const std::string& stage, const std::string& key) {
    auto it = entries_.find({stage, key});
    if (it == entries_.end()) return nullptr;
    it->second.used = ++clock_;
    return &it->second.output;
}

void OutputCache::fit() {
    while (bytes_ > budget_) {   // a few entries a frame: a scan for the oldest is cheap
        auto oldest = std::min_element(entries_.begin(), entries_.end(),
                                       [](const auto& a, const auto& b) { return a.second.used < b.second.used; });
        bytes_ -= oldest->second.output.bytes;
        entries_.erase(oldest);
    }
}

}  // namespace voxlux
