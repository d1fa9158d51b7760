// The render as a graph that runs, as a build system or Inviwo's processors do. Each stage
// declares what it reads: keys of the render document (the scene as `voxlux scene` writes it, plus
// the frame's input file), and the upstream stages whose outputs it takes, which its constructor
// registers as it takes them (Stage::input, as Inviwo's ports), so an edge is stated once. The
// graph orders the stages from these declarations, derives each stage's key by hashing what it declares, and runs a stage only
// when its key changed; otherwise the stage keeps its last output. `voxlux render --explain`
// prints this graph, and --stats and the EXR timings name the stages as it does.
// Cost: a hash of each stage's declared JSON values per frame, microseconds next to any stage.
#pragma once
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "graph/output_cache.h"
#include "scene/scene.h"

namespace voxlux {

// What a stage reads. Keys are JSON pointers into the render document; "*" stands for every
// element of an array ("/lights/*/position"), and a key covers everything below it. A key ending
// in "?" reads only whether the value is set (present, and not false or null): the stages that
// size their memory by whether an effect is on, not by its knobs.
struct StageReads {
    std::vector<std::string> keys;
};

// Whether a stage takes part in rendering a scene, and why: the line --explain prints.
struct StageActivity {
    bool runs = true;
    std::string reason;
};

class KernelBackend;
struct StageReport;

// The scene as a stage's run reads it: each read names the keys its output takes from it (JSON
// pointers of the render document, as StageReads has them), also those a helper reads for it
// (makeKernelInputs reads the whole scene; the stage names the parts its output depends on). When
// reads are checked (setStageReadChecks: tests and debug builds), a key that neither the stage nor
// a stage upstream of it declares is refused with
// std::logic_error ("stage 'march' reads /render/exposure, which it does not declare"), so a read
// added to a run() without its declaration fails where it is made; the every-key sweep
// (tests/render/test_render_graph.cpp) checks the declarations against what the outputs depend on.
class SceneReader {
public:
    // `declared`: the keys of the stage `stage` and of the stages upstream of it.
    SceneReader(const Scene& scene, const nlohmann::json& document, std::string stage, std::vector<std::string> declared);

    // The typed scene, for the values at `keys`: each a key at or below a declared one, or a
    // section holding declared ones (a helper that reads every light, where the stage declares the
    // parts of a light that change its output).
    const Scene& operator()(std::initializer_list<std::string_view> keys) const;
    const Scene& operator()(const std::vector<std::string>& keys) const;
    // The value at `key` (no wildcards) of the render document, null when absent: the input's
    // file and frame, which the scene does not hold.
    const nlohmann::json& value(std::string_view key) const;
    // The frame number the render is for (/input/frame; 0 for a file without ####).
    float frame() const;
    // The values at `key` as readKey's text, for the key of a part of an output (a selective update's).
    std::string keyText(std::string_view key) const;
    // The whole render document, unchecked: for a stage's own key (stageKey hashes only what the
    // stage declares).
    const nlohmann::json& uncheckedDocument() const { return document_; }

private:
    void check(std::string_view key) const;

    const Scene& scene_;
    const nlohmann::json& document_;
    std::string stage_;
    std::vector<std::string> declared_;
};

// Whether SceneReader checks its keys: on in debug builds, and in the tests, which turn it on.
void setStageReadChecks(bool on);
bool stageReadsChecked();

// What a stage's run sees besides its upstream stages' outputs.
struct StageRun {
    SceneReader scene;                    // the scene and the render document its keys point into
    KernelBackend& backend;               // the scene's backend (render.backend)
    const std::vector<StageReport>& so_far;  // the stages of this frame before it
    std::vector<std::string>& reused;     // parts of its output a stage that ran kept (selective updates)
    std::vector<std::string>& warnings;   // recoverable oddities, one line each
    const std::map<std::string, std::string>& keys;   // every stage's key this frame (RenderGraph::keys)
};

class Stage {
public:
    virtual ~Stage() = default;
    virtual std::string name() const = 0;
    virtual StageReads reads() const = 0;
    virtual StageActivity activity(const Scene& scene) const = 0;
    // Brings the output up to date. It may reuse parts of the last output that the change left
    // valid (a selective update); what it keeps goes into run.reused.
    virtual void run(StageRun& run) = 0;
    // The stage does not take part (any more): drop the output and its memory.
    virtual void release() {}
    // True when the upstream outputs leave nothing to do (an empty frame has no light to compute):
    // the stage is then skipped and released, as if the scene did not need it.
    virtual bool idle() const { return false; }
    // Called before any stage of a frame runs, when this stage's key changed: a stage that rebuilds
    // its output whole may drop it here, so the old and new outputs never coexist (unless the
    // output cache keeps the old one, within its budget).
    virtual void stale() {}
    // A stage whose output is dear to remake and worth keeping past its key (a frame's grids and
    // bricks, which a viewer scrubbing a sequence comes back to) shares it with the graph's output
    // cache, and adopts one the cache gives back for its key. Others share nothing.
    virtual SharedOutput sharedOutput() const { return {}; }
    virtual size_t outputBytes() const { return 0; }
    virtual void adoptOutput(const SharedOutput&) {}
    // Warnings that belong to the current output, repeated on every frame that reuses it.
    const std::vector<std::string>& outputWarnings() const { return output_warnings_; }
    // The upstream stages whose outputs it takes: the graph's edges into it.
    const std::vector<const Stage*>& inputs() const { return inputs_; }

protected:
    // Registers `upstream` as an input and hands it back: a stage's constructor takes each
    // upstream stage through this (`brick_(input(brick))`), which states the edge.
    template <class UpstreamStage>
    const UpstreamStage& input(const UpstreamStage& upstream) {
        inputs_.push_back(&upstream);
        return upstream;
    }

    friend class RenderGraph;
    std::vector<std::string> output_warnings_;

private:
    std::vector<const Stage*> inputs_;
};

enum class StageStatus { Ran, Reused, Skipped };

// Thrown by RenderGraph::run when its `cancelled` test says so (the viewer's next edit).
struct Cancelled : std::runtime_error {
    Cancelled() : std::runtime_error("render cancelled") {}
};

struct StageReport {
    std::string name;
    StageStatus status = StageStatus::Skipped;
    double seconds = 0.0;                 // of the run (0 unless it ran)
    bool cached = false;                  // reused from the output cache, not from the last frame
};

// The value of `pointer` (with "*" wildcards) in `document`, as text: every match's path and
// value, or "null" where nothing matches.
std::string readKey(const nlohmann::json& document, const std::string& pointer);

// 64-bit FNV-1a of `text`, as 16 hex digits.
std::string hashText(const std::string& text);

// The hash of a plain value's bytes: a key part that changes exactly when the value does.
template <typename T>
std::string hashBytes(const T& value) {
    return hashText(std::string(reinterpret_cast<const char*>(&value), sizeof value));
}

// The key of `stage` for `document`: the hash of the values it reads and of its upstream stages'
// `keys` (what RenderGraph::keys gives every stage that takes part). An upstream stage that does
// not take part hands on its own inputs' keys: its readers then read what it would have passed
// through (transfer_2d, when it does not run, hands on load's grids).
std::string stageKey(const Stage& stage, const nlohmann::json& document, const std::map<std::string, std::string>& keys);

class RenderGraph {
public:
    // Orders `stages` (not owned): each after the stages it reads, otherwise as given. Throws
    // std::logic_error when a stage reads one that is not among them, or on a cycle.
    explicit RenderGraph(std::vector<Stage*> stages);

    const std::vector<Stage*>& stages() const { return order_; }
    const Stage& stage(const std::string& name) const;

    // Runs, in order, the stages that `targets` need and the scene activates. Stages that do not
    // take part release their outputs. A stage that throws keeps no key, so it runs next time.
    // Appends the stages' output warnings to `warnings`, and the parts kept inside stages that ran
    // to `reused` (after the names of the stages reused whole).
    // `cancelled`, when given, is asked before each stage and after each run: once it is true the
    // run throws Cancelled, and a stage that ran meanwhile (its parallel loops may have stopped
    // early under a cancelled TBB context) releases its output and keeps no key, so it runs again.
    // `starting`, when given, is told each stage's name before it runs.
    std::vector<StageReport> run(const Scene& scene, const nlohmann::json& document, KernelBackend& backend,
                                 const std::vector<std::string>& targets, std::vector<std::string>& reused,
                                 std::vector<std::string>& warnings, const std::function<bool()>& cancelled = {},
                                 const std::function<void(const std::string&)>& starting = {});

    // Outputs that stages share (a frame's grids and bricks) are kept past their key within
    // `bytes` (OutputCache; 0, the default, keeps none), and taken back when the key returns.
    void setCacheBudget(size_t bytes) { cache_.setBudget(bytes); }
    const OutputCache& cache() const { return cache_; }

    // Each stage's key for this scene and document ("" for stages that do not take part).
    std::map<std::string, std::string> keys(const Scene& scene, const nlohmann::json& document) const;

    // Whether `stage` or a stage upstream of it declares a key that covers `pointer`.
    bool reads(const std::string& stage, const std::string& pointer) const;

    // The graph for `scene`, one line a stage in order: run or skip, the name, why, and what it reads.
    std::string explain(const Scene& scene) const;

private:
    std::vector<Stage*> needed(const std::vector<std::string>& targets) const;
    // The keys `stage` and the stages upstream of it declare, each once.
    std::vector<std::string> declaredKeys(const std::string& stage) const;

    std::vector<Stage*> order_;
    std::map<std::string, Stage*> by_name_;
    std::map<std::string, std::string> last_keys_;   // what each stage's current output was computed from
    OutputCache cache_;
};

}  // namespace voxlux
