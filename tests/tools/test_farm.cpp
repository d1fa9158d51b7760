// `voxlux farm`: the job folder and Slurm batch script a dry run writes, and the whole path on a
// real one-node Slurm cluster on localhost (tests/farm/slurm_cluster.sh): six frames of the Blender
// fire in chunks of two equal a local render of the same frames, and after a task is cancelled
// and a frame cut short, `collect --resubmit` completes the sequence.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <ImfStringAttribute.h>
#include <nlohmann/json.hpp>

#include "test_support.h"

namespace voxlux::test {
namespace {
namespace fs = std::filesystem;

std::string fileText(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

TEST(Farm, DryRunWritesTheJobFolderAndTheBatchScript) {
    const std::string dir = tempDir("farm_dry");
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const char* f : {"0001", "0002", "0003", "0004", "0005"})
        fs::copy_file(sourceDir() + "/grids/cloud.vdb", dir + "/cloud." + f + ".vdb");
    const std::string submit = "farm submit " + dir + "/cloud.####.vdb --frames 1-5 --chunk 2 --frame-on 1 --res 16x16 --backend cpu -o " +
                               dir + "/out/cloud.####.exr --job-dir " + dir + "/job";
    CliResult r = runCli(submit + " --dry-run");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out.substr(0, r.out.find('\n')), "wrote " + dir + "/job for 3 chunks of up to 2 frames (frames 1-5); dry run: sbatch --parsable --array=0-2 "
                                                 "--job-name=voxlux-job --output=" + dir + "/job/logs/chunk_%a.out --open-mode=append " +
                                                 dir + "/job/slurm.sh");
    const std::string script = fileText(dir + "/job/slurm.sh");
    const std::string task = voxluxBinary() + " render " + dir + "/job/scene.json --frames ";
    EXPECT_NE(script.find("  0) exec " + task + "1-2 --resume --log-json " + dir + "/job/logs/chunk_0.jsonl ;;\n"), std::string::npos) << script;
    EXPECT_NE(script.find("  2) exec " + task + "5 --resume --log-json " + dir + "/job/logs/chunk_2.jsonl ;;\n"), std::string::npos) << script;
    // The task's scene has the camera fixed and the output absolute; a dry run leaves no job.
    const nlohmann::json scene = nlohmann::json::parse(fileText(dir + "/job/scene.json"));
    EXPECT_TRUE(scene.contains("camera"));
    EXPECT_EQ(scene["output"]["path"], dir + "/out/cloud.####.exr");
    EXPECT_EQ(scene["volumes"][0]["path"], "../cloud.####.vdb");
    EXPECT_FALSE(fs::exists(dir + "/job/job.json"));

    // --threads asks the scheduler for that many cores a task, and each task uses that many.
    r = runCli(submit + " --threads 3 --dry-run");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find(" --cpus-per-task=3 "), std::string::npos) << r.out;
    EXPECT_NE(fileText(dir + "/job/slurm.sh").find("  0) exec " + task + "1-2 --resume --log-json " + dir + "/job/logs/chunk_0.jsonl --threads 3 ;;\n"),
              std::string::npos);

    // Without sbatch on PATH, submit says so and leaves no job either.
    r = runShell("PATH=/nonexistent " + voxluxBinary() + " " + submit);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: sbatch: cannot run (not installed, or not on PATH)\n");
    EXPECT_FALSE(fs::exists(dir + "/job/job.json"));
    r = runCli("farm status " + dir + "/job");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: " + dir + "/job/job.json: no farm job here (voxlux farm submit makes one)\n");
    r = runCli("farm submit " + sourceDir() + "/grids/cloud.vdb -o x.exr --dry-run");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "voxlux: error: " + sourceDir() +
                         "/grids/cloud.vdb: renders one file; a farm job needs a #### sequence and its frames\n");
}

// A one-node cluster for one test; skips the test when slurmctld (or munged, slurmd) cannot start.
class SlurmCluster {
public:
    SlurmCluster() {
        char name[] = "/tmp/vxslurm.XXXXXX";   // munge's socket path must stay under 108 bytes
        const char* made = mkdtemp(name);
        if (!made) return;
        dir_ = made;
        const CliResult r = runShell(sourceDir() + "/tests/farm/slurm_cluster.sh start " + dir_);
        started_ = r.exit_code == 0;
        skipped_ = r.exit_code == 77;   // a daemon could not start; any other failure is the script's
        message_ = r.err;
        if (started_) setenv("SLURM_CONF", (dir_ + "/slurm.conf").c_str(), 1);
    }
    ~SlurmCluster() {
        if (dir_.empty()) return;
        runShell(sourceDir() + "/tests/farm/slurm_cluster.sh stop " + dir_);
        unsetenv("SLURM_CONF");
        fs::remove_all(dir_);
    }
    bool started() const { return started_; }
    bool skipped() const { return skipped_; }
    const std::string& message() const { return message_; }

private:
    std::string dir_, message_ = "no temporary folder for it";
    bool started_ = false, skipped_ = false;
};

TEST(FarmSlurm, FireChunksMatchLocalRendersAndResubmitCompletesTheSequence) {
    VOXLUX_REQUIRE_SHARED(frame1, "blender/fire/fluid_data_0001.vdb");
    SlurmCluster cluster;
    if (cluster.skipped()) GTEST_SKIP() << "no Slurm cluster on localhost: " << cluster.message();
    ASSERT_TRUE(cluster.started()) << cluster.message();
    const std::string dir = tempDir("farm_slurm");
    fs::remove_all(dir);
    const std::string cache = fs::path(frame1).parent_path().string() + "/fluid_data_####.vdb";
    const std::string look = " --frames 1-6 --blackbody-grid temperature --res 48x48 --backend cpu --shadows raymarch";

    // Held, so that a task is cancelled before it can run, whatever the machine's speed.
    setenv("SBATCH_HOLD", "1", 1);
    CliResult r = runCli("farm submit " + cache + look + " --chunk 2 -o " + dir + "/farm/fire.####.exr --job-dir " + dir + "/job");
    unsetenv("SBATCH_HOLD");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string id = nlohmann::json::parse(fileText(dir + "/job/job.json"))["submissions"][0]["job_id"];
    const CliResult released = runShell("scancel " + id + "_1 && scontrol release " + id);
    ASSERT_EQ(released.exit_code, 0) << released.out << released.err;   // Slurm's own words, should it refuse
    r = runCli("farm collect " + dir + "/job --wait");
    EXPECT_EQ(r.exit_code, 3) << r.out << r.err;
    EXPECT_NE(r.out.find("collect: 4 of 6 frames done; not done: frames 3-4\n"), std::string::npos) << r.out;
    r = runCli("farm status " + dir + "/job");
    // A task cancelled before it ran leaves Slurm's queue at once (and no accounting runs here).
    EXPECT_NE(r.out.find("  chunk 1 (frames 3-4): GONE\n"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("tasks: 2 COMPLETED 1 GONE"), std::string::npos) << r.out;

    // A frame cut short is found by its read, not its header, and its chunk runs again.
    fs::resize_file(dir + "/farm/fire.0006.exr", fs::file_size(dir + "/farm/fire.0006.exr") - 100);
    r = runCli("farm collect " + dir + "/job --resubmit --wait");
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("frame 6 (chunk 2): corrupt: " + dir + "/farm/fire.0006.exr: cannot read EXR"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("resubmitted chunks 1-2 as slurm job "), std::string::npos) << r.out;
    EXPECT_EQ(r.out.substr(r.out.rfind("collect: ")), "collect: 6 of 6 frames done\n");
    // Chunk 2's task ran twice and resumed: the second time frame 5 was done and skipped, and
    // frame 6 rendered again.
    std::vector<nlohmann::json> log;
    std::ifstream lines(dir + "/job/logs/chunk_2.jsonl");
    for (std::string line; std::getline(lines, line);) log.push_back(nlohmann::json::parse(line));
    ASSERT_EQ(log.size(), 4u);
    EXPECT_EQ(log[2]["frame"], 5);
    EXPECT_EQ(log[2]["status"], "skipped");
    EXPECT_EQ(log[3]["frame"], 6);
    EXPECT_EQ(log[3]["status"], "rendered");

    r = runCli("render " + cache + look + " -o " + dir + "/local/fire.####.exr");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (int f = 1; f <= 6; ++f) {
        const std::string name = "/fire.000" + std::to_string(f) + ".exr";
        Exr farm = readExr(dir + "/farm" + name), local = readExr(dir + "/local" + name);
        EXPECT_EQ(farm.planes, local.planes) << name;
        EXPECT_EQ(farm.header.typedAttribute<Imf::StringAttribute>("voxlux/sceneHash").value(),
                  local.header.typedAttribute<Imf::StringAttribute>("voxlux/sceneHash").value()) << name;
    }
}

}  // namespace
}  // namespace voxlux::test
