#include "graph/render_graph.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <functional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "core/json_reader.h"

namespace voxlux {
namespace {

std::vector<std::string> tokensOf(const std::string& pointer) {
    std::vector<std::string> out;
    std::stringstream in(pointer);
    std::string token;
    std::getline(in, token, '/');   // the empty text before the leading '/'
    while (std::getline(in, token, '/')) out.push_back(token);
    return out;
}

// Appends "path=value;" for every match of tokens[i..] below `node` at `path`.
void collect(const nlohmann::json& node, const std::vector<std::string>& tokens, size_t i, const std::string& path,
             std::string& out) {
    if (i == tokens.size()) {
        out += path + "=" + jsonText(node) + ";";
        return;
    }
    const std::string& t = tokens[i];
    if (t == "*") {
        if (node.is_array())
            for (size_t k = 0; k < node.size(); ++k) collect(node[k], tokens, i + 1, path + "/" + std::to_string(k), out);
        else if (node.is_object())
            for (const auto& [name, child] : node.items()) collect(child, tokens, i + 1, path + "/" + name, out);
        return;
    }
    if (node.is_object() && node.contains(t)) return collect(node[t], tokens, i + 1, path + "/" + t, out);
    const bool index = !t.empty() && std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (node.is_array() && index && std::stoul(t) < node.size()) return collect(node[std::stoul(t)], tokens, i + 1, path + "/" + t, out);
    out += path + "/" + t + "=absent;";
}

// Whether a change at `changed` can change what `declared` reads: one is a prefix of the other,
// with "*" matching any one token; a presence key ("?") only sees changes at or above it.
bool covers(std::string declared, const std::string& changed) {
    const bool presence = !declared.empty() && declared.back() == '?';
    if (presence) declared.pop_back();
    const auto a = tokensOf(declared), b = tokensOf(changed);
    if (presence && b.size() > a.size()) return false;   // a change inside the value leaves it set
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
        if (a[i] != "*" && b[i] != "*" && a[i] != b[i]) return false;
    return true;
}

// Whether a stage that declares `declared` may read `key`: a key at or below the declared one,
// or a section holding it (a helper reads every light; the stage declares the parts of a light
// that change its output), but not the whole document unless it declares it. Unlike `covers`, a
// "*" in `key` reads every element, so only a "*" declares it. Whether a value is set ("?") is
// read under a declaration of the value or of that presence; the value itself, not under a
// presence.
bool mayRead(std::string declared, std::string key) {
    const bool declared_presence = !declared.empty() && declared.back() == '?';
    const bool key_presence = !key.empty() && key.back() == '?';
    if (declared_presence) declared.pop_back();
    if (key_presence) key.pop_back();
    const auto d = tokensOf(declared), k = tokensOf(key);
    if (k.empty() && !d.empty()) return false;
    if (declared_presence && (key_presence ? k.size() != d.size() : k.size() >= d.size())) return false;
    for (size_t i = 0; i < std::min(d.size(), k.size()); ++i)
        if (d[i] != "*" && d[i] != k[i]) return false;
    return true;
}

#ifdef NDEBUG
std::atomic<bool> stage_reads_checked{false};
#else
std::atomic<bool> stage_reads_checked{true};
#endif

}  // namespace

void setStageReadChecks(bool on) { stage_reads_checked = on; }
bool stageReadsChecked() { return stage_reads_checked; }

SceneReader::SceneReader(const Scene& scene, const nlohmann::json& document, std::string stage, std::vector<std::string> declared)
    : scene_(scene), document_(document), stage_(std::move(stage)), declared_(std::move(declared)) {}

void SceneReader::check(std::string_view key) const {
    if (!stage_reads_checked) return;
    const std::string k(key);
    if (std::none_of(declared_.begin(), declared_.end(), [&](const std::string& d) { return mayRead(d, k); }))
        throw std::logic_error("stage '" + stage_ + "' reads " + (k.empty() ? "the whole document" : k) + ", which it does not declare");
}

const Scene& SceneReader::operator()(std::initializer_list<std::string_view> keys) const {
    for (std::string_view key : keys) check(key);
    return scene_;
}

const Scene& SceneReader::operator()(const std::vector<std::string>& keys) const {
    for (const std::string& key : keys) check(key);
    return scene_;
}

const nlohmann::json& SceneReader::value(std::string_view key) const {
    if (key.find('*') != std::string_view::npos) throw std::logic_error("SceneReader::value takes one value's key, not " + std::string(key));
    check(key);
    static const nlohmann::json absent;
    const nlohmann::json::json_pointer at{std::string(key)};
    return document_.contains(at) ? document_[at] : absent;
}

float SceneReader::frame() const {
    const nlohmann::json& frame = value("/input/frame");
    return frame.is_number() ? frame.get<float>() : 0.0f;
}

std::string SceneReader::keyText(std::string_view key) const {
    check(key);
    return readKey(document_, std::string(key));
}

std::string readKey(const nlohmann::json& document, const std::string& pointer) {
    std::string out;
    if (!pointer.empty() && pointer.back() == '?') {
        const nlohmann::json::json_pointer at(pointer.substr(0, pointer.size() - 1));
        const bool set = document.contains(at) && !document[at].is_null() && document[at] != false;
        return pointer + (set ? "=set;" : "=unset;");
    }
    collect(document, tokensOf(pointer), 0, "", out);
    return out;
}

std::string hashText(const std::string& text) {
    uint64_t h = 14695981039346656037ull;   // FNV offset basis
    for (unsigned char c : text) {
        h ^= c;
        h *= 1099511628211ull;
    }
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

RenderGraph::RenderGraph(std::vector<Stage*> stages) {
    for (Stage* s : stages) by_name_[s->name()] = s;
    std::set<std::string> placed, visiting;
    std::function<void(Stage*)> place = [&](Stage* s) {
        if (placed.count(s->name())) return;
        if (!visiting.insert(s->name()).second) throw std::logic_error("render graph: a cycle through stage " + s->name());
        for (const Stage* up : s->inputs()) {
            auto it = by_name_.find(up->name());
            if (it == by_name_.end() || it->second != up)
                throw std::logic_error("render graph: stage " + s->name() + " reads stage " + up->name() + ", which is not in the graph");
            place(it->second);
        }
        placed.insert(s->name());
        order_.push_back(s);
    };
    for (Stage* s : stages) place(s);
}

const Stage& RenderGraph::stage(const std::string& name) const { return *by_name_.at(name); }

std::vector<Stage*> RenderGraph::needed(const std::vector<std::string>& targets) const {
    std::set<std::string> want;
    std::function<void(const std::string&)> need = [&](const std::string& name) {
        if (!want.insert(name).second) return;
        for (const Stage* up : by_name_.at(name)->inputs()) need(up->name());
    };
    for (const auto& t : targets) need(t);
    std::vector<Stage*> out;
    for (Stage* s : order_)
        if (want.count(s->name())) out.push_back(s);
    return out;
}

std::map<std::string, std::string> RenderGraph::keys(const Scene& scene, const nlohmann::json& document) const {
    std::map<std::string, std::string> keys;
    for (const Stage* s : order_) {
        if (!s->activity(scene).runs) {
            keys[s->name()] = "";
            continue;
        }
        keys[s->name()] = stageKey(*s, document, keys);
    }
    return keys;
}

namespace {

// The key `stage` hands its readers: its own, or when it does not take part its inputs' ("" when
// nothing upstream of it takes part either).
std::string handedOn(const Stage& stage, const std::map<std::string, std::string>& keys) {
    const std::string& own = keys.at(stage.name());
    if (!own.empty()) return own;
    std::string through;
    for (const Stage* up : stage.inputs()) through += handedOn(*up, keys);
    return through.empty() ? "" : hashText(through);
}

}  // namespace

std::string stageKey(const Stage& stage, const nlohmann::json& document, const std::map<std::string, std::string>& keys) {
    std::string text = stage.name() + "\n";
    for (const auto& k : stage.reads().keys) text += readKey(document, k) + "\n";
    for (const Stage* up : stage.inputs()) text += up->name() + "=" + handedOn(*up, keys) + "\n";
    return hashText(text);
}

bool RenderGraph::reads(const std::string& stage, const std::string& pointer) const {
    const std::vector<std::string> declared = declaredKeys(stage);
    return std::any_of(declared.begin(), declared.end(), [&](const std::string& k) { return covers(k, pointer); });
}

std::vector<std::string> RenderGraph::declaredKeys(const std::string& stage) const {
    std::set<std::string> keys;
    std::function<void(const Stage&)> gather = [&](const Stage& s) {
        for (const std::string& k : s.reads().keys) keys.insert(k);
        for (const Stage* up : s.inputs()) gather(*up);
    };
    gather(*by_name_.at(stage));
    return {keys.begin(), keys.end()};
}

std::vector<StageReport> RenderGraph::run(const Scene& scene, const nlohmann::json& document,
                                          KernelBackend& backend, const std::vector<std::string>& targets, std::vector<std::string>& reused,
                                          std::vector<std::string>& warnings, const std::function<bool()>& cancelled,
                                          const std::function<void(const std::string&)>& starting) {
    const auto stop = [&] { return cancelled && cancelled(); };
    const std::map<std::string, std::string> keys = this->keys(scene, document);
    std::vector<StageReport> reports;
    std::vector<std::string> kept_inside;
    const std::vector<Stage*> stages = needed(targets);
    for (Stage* s : stages) {
        const std::string& key = keys.at(s->name());
        if (!key.empty() && (!last_keys_.count(s->name()) || last_keys_[s->name()] != key)) {
            if (last_keys_.count(s->name())) {
                cache_.find(s->name(), key);   // made the newest first, so keeping the old output cannot drop it
                cache_.keep(s->name(), last_keys_[s->name()], {s->sharedOutput(), s->outputBytes(), s->output_warnings_});
            }
            last_keys_.erase(s->name());   // its output is gone: it runs, even if this frame fails and the key comes back
            s->stale();
        }
    }
    for (Stage* s : stages) {
        if (stop()) throw Cancelled();
        StageReport report{s->name()};
        const std::string& key = keys.at(s->name());
        if (key.empty() || s->idle()) {
            s->release();
            s->output_warnings_.clear();
            last_keys_.erase(s->name());
        } else if (last_keys_.count(s->name()) && last_keys_[s->name()] == key) {
            report.status = StageStatus::Reused;
            reused.push_back(s->name());
        } else if (const CachedOutput* kept = cache_.find(s->name(), key)) {
            s->adoptOutput(kept->value);
            s->output_warnings_ = kept->warnings;
            report.status = StageStatus::Reused;
            report.cached = true;
            reused.push_back(s->name());
            last_keys_[s->name()] = key;
        } else {
            last_keys_.erase(s->name());
            s->output_warnings_.clear();
            // The keys a checked read may name; unchecked, none are gathered.
            std::vector<std::string> declared = stageReadsChecked() ? declaredKeys(s->name()) : std::vector<std::string>{};
            StageRun run{SceneReader(scene, document, s->name(), std::move(declared)), backend, reports, kept_inside,
                         s->output_warnings_, keys};
            if (starting) starting(s->name());
            const auto start = std::chrono::steady_clock::now();
            s->run(run);
            report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (stop()) {
                s->release();
                s->output_warnings_.clear();
                throw Cancelled();
            }
            report.status = StageStatus::Ran;
            last_keys_[s->name()] = key;
        }
        warnings.insert(warnings.end(), s->outputWarnings().begin(), s->outputWarnings().end());
        reports.push_back(report);
    }
    reused.insert(reused.end(), kept_inside.begin(), kept_inside.end());
    return reports;
}

std::string RenderGraph::explain(const Scene& scene) const {
    std::ostringstream out;
    for (const Stage* s : order_) {
        const StageActivity a = s->activity(scene);
        const StageReads r = s->reads();
        out << (a.runs ? "run   " : "skip  ") << s->name() << ' ';   // a long name still ends in a space
        for (size_t pad = s->name().size() + 1; pad < 18; ++pad) out << ' ';
        out << a.reason << "  [after:";
        for (const Stage* up : s->inputs()) out << ' ' << up->name();
        if (s->inputs().empty()) out << " -";
        out << "; reads:";
        for (const auto& k : r.keys) out << ' ' << (k.empty() ? "(the whole document)" : k);
        if (r.keys.empty()) out << " -";
        out << "]\n";
    }
    return out.str();
}

}  // namespace voxlux
