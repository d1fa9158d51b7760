// The render graph's machinery on toy stages: the order from the edges their constructors state,
// keys (wildcards, presence, the keys a skipped stage hands on), reuse, failures, and the output
// cache with its typed outputs. The renderer's own graph: tests/render/test_render_graph.cpp.
#include <memory>
#include <string>
#include <vector>

#include "backend/backend_choice.h"
#include "core/error.h"
#include "graph/render_graph.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

// A stage that counts its runs and reads what it is told to: document keys (declared, and read at
// run), and the stages given (or added with `after`, which can make a cycle no constructor could).
class ToyStage final : public Stage {
public:
    ToyStage(std::string name, std::vector<std::string> keys, std::vector<const Stage*> upstream = {})
        : name_(std::move(name)), reads_{std::move(keys)} {
        for (const Stage* up : upstream) input(*up);
    }
    void after(const Stage& upstream) { input(upstream); }
    std::string name() const override { return name_; }
    StageReads reads() const override { return reads_; }
    StageActivity activity(const Scene&) const override { return {active, active ? "on" : "skipped: off"}; }
    void run(StageRun& run) override {
        ++runs;
        if (fail) throw InputError(name_ + ": failed");
        for (const std::string& key : reads_at_run) run.scene({key});
        output = run.scene.uncheckedDocument().dump();
        if (!warning.empty()) run.warnings.push_back(warning);
    }
    void release() override { output.clear(); }
    SharedOutput sharedOutput() const override {
        return shares ? SharedOutput(std::make_shared<const std::string>(output)) : SharedOutput();
    }
    size_t outputBytes() const override { return output.size(); }
    void adoptOutput(const SharedOutput& kept) override { output = *kept.as<std::string>(); }

    bool active = true, fail = false, shares = false;
    std::vector<std::string> reads_at_run;   // keys its run reads through run.scene
    int runs = 0;
    std::string output, warning;

private:
    std::string name_;
    StageReads reads_;
};

struct ToyRun {
    std::vector<StageReport> reports;
    std::vector<std::string> reused, warnings;
    std::string status(const std::string& name) const {
        for (const auto& r : reports)
            if (r.name == name) return r.status == StageStatus::Ran ? "ran" : r.status == StageStatus::Reused ? "reused" : "skipped";
        return "not needed";
    }
};

ToyRun runToy(RenderGraph& graph, const nlohmann::json& document, std::vector<std::string> targets) {
    static auto backend = makeCpuBackend();
    ToyRun r;
    r.reports = graph.run(Scene{}, document, *backend, targets, r.reused, r.warnings);
    return r;
}

TEST(RenderGraph, OrdersStagesFromWhatTheyRead) {
    ToyStage load("load", {"/volume"}), march("march", {"/render"}, {&load}), write("write", {}, {&march});
    RenderGraph graph({&write, &march, &load});
    std::vector<std::string> order;
    for (const Stage* s : graph.stages()) order.push_back(s->name());
    EXPECT_EQ(order, (std::vector<std::string>{"load", "march", "write"}));

    ToyStage nowhere("nowhere", {}), lonely("lonely", {}, {&nowhere});
    try {
        RenderGraph bad({&lonely});
        FAIL() << "no error";
    } catch (const std::logic_error& e) {
        EXPECT_EQ(std::string(e.what()), "render graph: stage lonely reads stage nowhere, which is not in the graph");
    }
    ToyStage a("a", {}), b("b", {}, {&a});
    a.after(b);
    try {
        RenderGraph cyclic({&a, &b});
        FAIL() << "no error";
    } catch (const std::logic_error& e) {
        EXPECT_EQ(std::string(e.what()), "render graph: a cycle through stage a");
    }
}

TEST(RenderGraph, RunsAStageOnlyWhenWhatItReadsChanged) {
    ToyStage load("load", {"/volume"}), light("light", {"/lights/*/position"}, {&load}), march("march", {"/render"}, {&light});
    RenderGraph graph({&load, &light, &march});
    nlohmann::json doc = {{"volume", "a.vdb"}, {"lights", {{{"position", {0, 1, 0}}, {"color", 1}}}}, {"render", 1}};
    ToyRun first = runToy(graph, doc, {"march"});
    EXPECT_EQ(first.status("load") + first.status("light") + first.status("march"), "ranranran");
    EXPECT_TRUE(first.reused.empty());

    doc["lights"][0]["color"] = 2;   // read by no stage
    ToyRun colour = runToy(graph, doc, {"march"});
    EXPECT_EQ(colour.reused, (std::vector<std::string>{"load", "light", "march"}));
    doc["render"] = 2;
    ToyRun render = runToy(graph, doc, {"march"});
    EXPECT_EQ(render.status("load") + render.status("light") + render.status("march"), "reusedreusedran");
    doc["lights"].push_back({{"position", {1, 1, 1}}});   // "*" covers a new element
    ToyRun added = runToy(graph, doc, {"march"});
    EXPECT_EQ(added.status("load") + added.status("light") + added.status("march"), "reusedranran");
    doc["volume"] = "b.vdb";                                 // upstream keys flow down
    ToyRun volume = runToy(graph, doc, {"light"});
    EXPECT_EQ(volume.status("load") + volume.status("light") + volume.status("march"), "ranrannot needed");
    EXPECT_EQ(load.runs, 2);
    EXPECT_EQ(light.runs, 3);
    EXPECT_EQ(march.runs, 3);
}

// Turns the check of stages' reads off while it lives.
struct UncheckedStageReads {
    UncheckedStageReads() { setStageReadChecks(false); }
    ~UncheckedStageReads() { setStageReadChecks(true); }
};

// A stage's run reads the scene through keys it or a stage upstream of it declares; the tests
// check reads (test_support.cpp), and any other key is refused where it is read.
TEST(RenderGraph, ARunReadsOnlyWhatItOrItsUpstreamDeclares) {
    ASSERT_TRUE(stageReadsChecked());
    ToyStage load("load", {"/volume"}), light("light", {"/lights/*/position", "/effects/indirect?"}, {&load});
    RenderGraph graph({&load, &light});
    nlohmann::json doc = {{"volume", {{"path", "a.vdb"}}}, {"lights", {{{"position", {0, 1, 0}}}}}, {"render", 1},
                          {"effects", {{"indirect", {{"angle", 30}}}}}};
    // Below a declared key, a section holding one, an upstream stage's key, a declared presence
    // and a section holding it.
    light.reads_at_run = {"/lights/0/position", "/lights/*/position", "/lights", "/volume/path", "/effects/indirect?", "/effects"};
    EXPECT_EQ(runToy(graph, doc, {"light"}).status("light"), "ran");
    const std::pair<const char*, const char*> refused[] = {
        {"/render", "stage 'light' reads /render, which it does not declare"},
        {"/lights/0/color", "stage 'light' reads /lights/0/color, which it does not declare"},
        {"/effects/indirect/angle", "stage 'light' reads /effects/indirect/angle, which it does not declare"},
        {"/effects/indirect", "stage 'light' reads /effects/indirect, which it does not declare"},
        {"", "stage 'light' reads the whole document, which it does not declare"},
        {"/*", "stage 'light' reads /*, which it does not declare"},
        {"/lights/*/color", "stage 'light' reads /lights/*/color, which it does not declare"},
    };
    for (const auto& [key, message] : refused) {
        light.reads_at_run = {key};
        doc["volume"]["path"] = std::string(key) + ".vdb";   // a change both stages read: they run
        try {
            runToy(graph, doc, {"light"});
            ADD_FAILURE() << key << ": no error";
        } catch (const std::logic_error& e) {
            EXPECT_EQ(std::string(e.what()), message);
        }
    }
    // Unchecked (a release build outside the tests), the same read goes through.
    const UncheckedStageReads unchecked;
    light.reads_at_run = {"/render"};
    doc["volume"]["path"] = "b.vdb";
    EXPECT_EQ(runToy(graph, doc, {"light"}).status("light"), "ran");
}

// A stage that does not take part passes its inputs' keys on (as transfer_2d, when it does not
// run, passes load's grids on): what reads it still re-runs when what is upstream of it changed.
TEST(RenderGraph, AStageThatDoesNotRunHandsOnItsInputsKeys) {
    ToyStage load("load", {"/volume"}), filter("filter", {"/filter"}, {&load}), march("march", {}, {&filter});
    filter.active = false;
    RenderGraph graph({&load, &filter, &march});
    nlohmann::json doc = {{"volume", "a.vdb"}, {"filter", 1}};
    ToyRun first = runToy(graph, doc, {"march"});
    EXPECT_EQ(first.status("load") + first.status("filter") + first.status("march"), "ranskippedran");
    doc["filter"] = 2;   // read only by the stage that does not run
    ToyRun filtered = runToy(graph, doc, {"march"});
    EXPECT_EQ(filtered.status("load") + filtered.status("filter") + filtered.status("march"), "reusedskippedreused");
    doc["volume"] = "b.vdb";
    ToyRun volume = runToy(graph, doc, {"march"});
    EXPECT_EQ(volume.status("load") + volume.status("filter") + volume.status("march"), "ranskippedran");
    EXPECT_EQ(march.runs, 2);
}

TEST(RenderGraph, AFailedStageRunsAgainAndInactiveOnesReleaseTheirOutput) {
    ToyStage load("load", {"/volume"}), light("light", {}, {&load});
    light.warning = "a warning that belongs to the light's output";
    RenderGraph graph({&load, &light});
    const nlohmann::json doc = {{"volume", "a.vdb"}};
    load.fail = true;
    EXPECT_THROW(runToy(graph, doc, {"light"}), InputError);
    load.fail = false;
    ToyRun again = runToy(graph, doc, {"light"});
    EXPECT_EQ(again.status("load") + again.status("light"), "ranran");
    EXPECT_EQ(again.warnings, std::vector<std::string>{light.warning});
    ToyRun reused = runToy(graph, doc, {"light"});
    EXPECT_EQ(reused.warnings, std::vector<std::string>{light.warning});   // it still describes the output
    light.active = false;
    ToyRun off = runToy(graph, doc, {"light"});
    EXPECT_EQ(off.status("light"), "skipped");
    EXPECT_TRUE(light.output.empty());
    EXPECT_TRUE(off.warnings.empty());
    light.active = true;
    EXPECT_EQ(runToy(graph, doc, {"light"}).status("light"), "ran");   // nothing kept from before
}

TEST(RenderGraph, KeysReadWildcardsAndPresence) {
    const nlohmann::json doc = {{"lights", {{{"type", "point"}, {"position", {1, 2, 3}}}, {{"type", "directional"}}}},
                                {"effects", {{"indirect", false}, {"surface", {{"specular", 0.5}}}}}};
    EXPECT_EQ(readKey(doc, "/lights/*/position"), "/lights/0/position=[1,2,3];/lights/1/position=absent;");
    EXPECT_EQ(readKey(doc, "/effects/indirect?"), "/effects/indirect?=unset;");
    EXPECT_EQ(readKey(doc, "/effects/surface?"), "/effects/surface?=set;");
    EXPECT_EQ(readKey(doc, "/effects/missing?"), "/effects/missing?=unset;");
    EXPECT_EQ(readKey(doc, "/effects/surface/specular"), "/effects/surface/specular=0.5;");
    EXPECT_EQ(hashText(""), "cbf29ce484222325");   // FNV-1a's offset basis
}

// A kept output is taken back only as the type it was kept as.
TEST(RenderGraph, AKeptOutputIsTakenBackOnlyAsItsOwnType) {
    const SharedOutput kept(std::make_shared<const std::string>("grids"));
    EXPECT_EQ(*kept.as<std::string>(), "grids");
    try {
        kept.as<int>();
        FAIL() << "no error";
    } catch (const std::logic_error& e) {
        EXPECT_EQ(std::string(e.what()), "output cache: an output taken back as another type");
    }
}

// A stage that shares its output gets it back from the cache when its key returns, with its
// warnings, as long as the budget holds it; the least recently used goes first.
TEST(RenderGraph, SharedOutputsComeBackFromTheCacheWithinItsBudget) {
    ToyStage load("load", {"/frame"}), march("march", {"/camera"}, {&load});
    load.shares = true;
    RenderGraph graph({&load, &march});
    const nlohmann::json one = {{"frame", 1}, {"camera", 0}}, two = {{"frame", 2}, {"camera", 0}}, three = {{"frame", 3}, {"camera", 0}};
    const size_t bytes = one.dump().size();   // every frame's output has this size
    graph.setCacheBudget(2 * bytes);
    load.warning = "frame 1 has NaN voxels";
    runToy(graph, one, {"march"});
    load.warning.clear();
    runToy(graph, two, {"march"});
    EXPECT_EQ(load.runs, 2);

    ToyRun back = runToy(graph, one, {"march"});
    EXPECT_EQ(back.status("load"), "reused");
    EXPECT_TRUE(back.reports[0].cached);
    EXPECT_EQ(load.runs, 2);
    EXPECT_EQ(load.output, one.dump());
    EXPECT_EQ(back.warnings, std::vector<std::string>{"frame 1 has NaN voxels"});
    EXPECT_EQ(back.status("march"), "ran");   // its key reads load's, which changed
    EXPECT_EQ(graph.cache().entries(), 2u);
    EXPECT_EQ(graph.cache().bytes(), 2 * bytes);

    runToy(graph, three, {"march"});
    EXPECT_EQ(load.runs, 3);
    // Back to frame 1: keeping frame 3 overflows the budget, and frame 2, the least recently
    // used, goes; not frame 1, which this very run takes back.
    EXPECT_EQ(runToy(graph, one, {"march"}).status("load"), "reused");
    EXPECT_EQ(graph.cache().entries(), 2u);
    EXPECT_EQ(runToy(graph, two, {"march"}).status("load"), "ran");
    EXPECT_EQ(load.runs, 4);

    graph.setCacheBudget(0);   // the default: nothing kept
    EXPECT_EQ(graph.cache().entries(), 0u);
    EXPECT_EQ(runToy(graph, one, {"march"}).status("load"), "ran");
    EXPECT_EQ(runToy(graph, two, {"march"}).status("load"), "ran");
    EXPECT_EQ(graph.cache().entries(), 0u);
}

}  // namespace
}  // namespace voxlux::test
