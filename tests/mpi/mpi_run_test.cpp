// `mpirun -np N crex run ...` on this machine (issue 19): rank 0 alone reads, checks and plans
// (rank 1 given inputs that do not exist still renders; an input error is said once); ranks
// render bands of rows, balanced per stage by camera samples, and share them, so without an
// irradiance cache the image is the single-process image, pixel for pixel, at any rank count. With a cache: component is the single-process image at N = 2 and the same
// image on every run at a fixed N (one PA and two; two PAs at N = 8), broadcast and central
// make fewer records than none. Faults: a rank killed with SIGKILL ends the run with mpirun's
// error naming it, and rank 0 writes the rows it finished (mpirun's SIGTERM); a stopped rank
// (renderer or PA) is named by --rank-timeout; none leaves a process or a half-written output.
// --resume finishes a partial image in one process: the uninterrupted image, exactly.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <numeric>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "runtime/io/image_io.h"
#include "tests/support/crex_cli.h"

namespace crex {
namespace {

namespace fs = std::filesystem;

const char* kMpirun = "/usr/bin/mpirun";

testing::CommandResult mpirun(int ranks, const std::vector<std::string>& args) {
    // As root Open MPI wants --allow-run-as-root; --oversubscribe: more ranks than cores.
    std::vector<std::string> cmd = {kMpirun, "--allow-run-as-root", "--oversubscribe", "-np", std::to_string(ranks), CREX_BINARY};
    cmd.insert(cmd.end(), args.begin(), args.end());
    return testing::run_command(cmd);
}

// Multiple program, multiple data: rank 0 runs `rank0` and rank 1 `rank1`. Rank 1 given
// paths that do not exist stands for a cluster where only rank 0's machine has the inputs.
testing::CommandResult mpirun_each(const std::vector<std::string>& rank0, const std::vector<std::string>& rank1) {
    std::vector<std::string> cmd = {kMpirun, "--allow-run-as-root", "--oversubscribe", "-np", "1", CREX_BINARY};
    cmd.insert(cmd.end(), rank0.begin(), rank0.end());
    cmd.insert(cmd.end(), {":", "-np", "1", CREX_BINARY});
    cmd.insert(cmd.end(), rank1.begin(), rank1.end());
    return testing::run_command(cmd);
}

size_t count(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

std::vector<float> pixels(const std::string& path) {
    int w = 0, h = 0;
    std::vector<float> rgb;
    EXPECT_EQ(read_image(path, w, h, rgb), "") << path;
    return rgb;
}

// The single-process image, as far as Embree's ray streams allow: a stream traces its rays in
// packets whose members depend on which rays are traced together, and a ray's hit can differ in
// its last bit with its companions. Traced one at a time (rtcIntersect1) the band-split images
// are bit for bit the single-process ones, but bench/render_bench traced 12-39 % slower. So:
// every value within a relative 1e-5 (a wrong sample or a lost pass moves a pixel by far more),
// and at most one value in a hundred differs at all.
::testing::AssertionResult same_image_up_to_traversal(const std::vector<float>& got, const std::vector<float>& want) {
    if (got.size() != want.size()) return ::testing::AssertionFailure() << got.size() << " values against " << want.size();
    size_t differ = 0;
    for (size_t i = 0; i < got.size(); ++i) {
        if (got[i] == want[i]) continue;
        ++differ;
        const double tolerance = 1e-5 * std::max(std::abs(double(want[i])), 1e-3);
        if (!(std::abs(double(got[i]) - double(want[i])) <= tolerance))
            return ::testing::AssertionFailure() << "value " << i << ": " << got[i] << " against " << want[i];
    }
    if (differ * 100 > got.size())
        return ::testing::AssertionFailure() << differ << " of " << got.size() << " values differ, more than one in a hundred";
    return ::testing::AssertionSuccess();
}

// The shell command of `crex run ARGS` on 2 ranks with the test hooks `env` ("NAME=value ...",
// each passed to every rank with -x), under timeout(1): a run that hangs ends the test (exit
// 124) instead of CI.
std::string hooked_run(const std::string& env, const std::string& args) {
    std::string exports;
    std::istringstream words(env);
    for (std::string word; words >> word;) exports += " -x " + word.substr(0, word.find('='));
    return env + " timeout -k 5 60 " + kMpirun + " --allow-run-as-root --oversubscribe" + exports + " -np 2 " + CREX_BINARY +
           " run " + args;
}

// The crex processes still running a `crex run --size SIZE ...` (none once a run has ended).
std::string crex_left(const std::string& size) {
    return testing::run_command({"/bin/sh", "-c", "pgrep -f '[c]rex run --size " + size + "' || true"}).out;
}

class MpiRun : public ::testing::Test {
protected:
    void SetUp() override {
        ASSERT_TRUE(fs::exists(kMpirun)) << "the mpi tests need Open MPI (openmpi-bin, tools/debian-packages.txt)";
        dir_ = fs::temp_directory_path() / ("crex_mpi_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    nlohmann::json reported_against_one_process(const std::vector<std::string>& args, double relative = 0);
    fs::path dir_;
};

TEST_F(MpiRun, ACrexRendersTheSingleProcessImageAtAnyRankCount) {
    const std::vector<std::string> args = {"run", "--size", "24x17", "--spp", "4", "-q"};
    auto one = testing::crex_cli({"run", "--size", "24x17", "--spp", "4", "-q", "-o", path("one.exr")});
    ASSERT_EQ(one.exit_code, 0) << one.err;
    for (int ranks : {2, 3, 4}) {
        std::vector<std::string> a = args;
        a.insert(a.end(), {"-o", path("n.exr")});
        auto n = mpirun(ranks, a);
        ASSERT_EQ(n.exit_code, 0) << ranks << " ranks: " << n.err;
        EXPECT_TRUE(same_image_up_to_traversal(pixels(path("n.exr")), pixels(path("one.exr")))) << ranks << " ranks";
    }
}

TEST_F(MpiRun, APipelineWithoutACacheRendersTheSingleProcessImage) {
    // Guidance runs on the whole preview on every rank; the selective samples by bands.
    const std::string pipe = CREX_SOURCE_DIR "/stdlib/pipelines/sel_rp.pipe";
    auto one = testing::crex_cli({"run", pipe, "--size", "24x16", "-q", "-o", path("one.exr")});
    ASSERT_EQ(one.exit_code, 0) << one.err;
    auto two = mpirun(2, {"run", pipe, "--size", "24x16", "-q", "-o", path("two.exr")});
    ASSERT_EQ(two.exit_code, 0) << two.err;
    EXPECT_TRUE(same_image_up_to_traversal(pixels(path("two.exr")), pixels(path("one.exr"))));
}

// The rows in each band of the last stage, from rank 0's note in the JSON summary.
std::vector<int> last_stage_band_rows(const std::string& json) {
    const auto j = nlohmann::json::parse(json, nullptr, false);
    std::vector<int> rows;
    if (!j.is_object() || !j.contains("notes")) return rows;
    for (const auto& note : j["notes"]) {
        std::smatch m;
        const std::string text = note.get<std::string>();
        if (!std::regex_search(text, m, std::regex("the last stage's hold ([0-9, ]+) rows"))) continue;
        std::istringstream list(std::regex_replace(m[1].str(), std::regex(","), " "));
        for (int n = 0; list >> n;) rows.push_back(n);
    }
    return rows;
}

// Each stage's bands carry about the same camera samples. Here every selective sample goes to
// the edges of the ceiling light, in the top rows: the last stage's bands there are narrow,
// the last band takes the rest of the image, and the image is still the single-process one
// (each pixel's samples traced by one rank, in one process's order).
TEST_F(MpiRun, BandsBalancedBySamplesRenderTheSingleProcessImage) {
    const std::string pipe = path("light_edges.pipe");
    std::ofstream(pipe) << "pipeline light_edges {\n"
                           "  preselective { crex \"(TTMRSGD)*\"  spp 1 }\n"
                           "  guidance { e = edges(emission) }\n"
                           "  selective { vary spp 1 .. 32 by e }\n"
                           "}\n";
    const int height = 48;
    const std::vector<std::string> args = {"run", pipe, "--size", "48x" + std::to_string(height), "--format", "json"};
    std::vector<std::string> a = args;
    a.insert(a.end(), {"-o", path("one.exr")});
    auto one = testing::crex_cli(a);
    ASSERT_EQ(one.exit_code, 0) << one.err;
    for (int ranks : {2, 4}) {
        SCOPED_TRACE(std::to_string(ranks) + " ranks");
        a = args;
        a.insert(a.end(), {"-o", path("n.exr")});
        auto n = mpirun(ranks, a);
        ASSERT_EQ(n.exit_code, 0) << n.err;
        EXPECT_TRUE(same_image_up_to_traversal(pixels(path("n.exr")), pixels(path("one.exr"))));
        const std::vector<int> rows = last_stage_band_rows(n.out);
        ASSERT_EQ(rows.size(), static_cast<size_t>(ranks)) << n.out;
        EXPECT_EQ(std::accumulate(rows.begin(), rows.end(), 0), height);
        EXPECT_LT(rows.front(), height / ranks) << "a narrow first band, where the light's edges are";
        EXPECT_GT(rows.back(), height / ranks) << "the last band takes the rows that ask for no sample";
        EXPECT_TRUE(std::all_of(rows.begin(), rows.end(), [](int r) { return r > 0; }));
    }
}

// A pipeline whose preview carries rays to the selective stage (cbtcr_sel: a "TT" preview)
// stands them in as av until they run, in the preview the maps see: shared with the rows, so
// every rank computes the same maps and bands. With --ambient 0.3 the image is the
// single-process image (before, each rank's preview had only its own rows' stand-ins: RMSE 0.34
// against one process at 48x48 on 4 ranks). With --ambient auto (a pipeline's default) the
// rays its crex leaves unexecuted stand in with what every rank's rays of their component
// brought back, wherever the bands moved them: the image too, but for the order in which the
// ranks' sums are added.
TEST_F(MpiRun, APipelineThatCarriesRaysRendersTheSingleProcessImage) {
    const std::string pipe = CREX_SOURCE_DIR "/stdlib/pipelines/cbtcr_sel.pipe";
    for (const std::string ambient : {"0.3", "auto"}) {
        SCOPED_TRACE("--ambient " + ambient);
        const std::vector<std::string> args = {"run", pipe, "--no-budget", "--size", "32x24", "--ambient", ambient, "-q"};
        std::vector<std::string> a = args;
        a.insert(a.end(), {"-o", path("one.exr")});
        auto one = testing::crex_cli(a);
        ASSERT_EQ(one.exit_code, 0) << one.err;
        const std::vector<float> want = pixels(path("one.exr"));
        for (int ranks : {2, 4}) {
            a = args;
            a.insert(a.end(), {"-o", path("n.exr")});
            auto n = mpirun(ranks, a);
            ASSERT_EQ(n.exit_code, 0) << ranks << " ranks: " << n.err;
            const std::vector<float> got = pixels(path("n.exr"));
            ASSERT_EQ(got.size(), want.size());
            if (ambient != "auto") {
                EXPECT_EQ(got, want) << ranks << " ranks";
                continue;
            }
            for (size_t i = 0; i < got.size(); ++i)
                ASSERT_NEAR(got[i], want[i], 1e-5f * std::max(1.0f, std::abs(want[i]))) << ranks << " ranks, value " << i;
        }
    }
}

// Rank 0 alone reads, checks and plans; the other ranks get the plan, the scene and the
// settings as data: rank 1 is given a pipeline and a scene that do not exist, and still
// renders its rows of the single-process image.
TEST_F(MpiRun, OnlyRankZeroReadsThePipelineAndTheScene) {
    const std::string pipe = CREX_SOURCE_DIR "/stdlib/pipelines/sel_rp.pipe";
    const std::string scene = CREX_SOURCE_DIR "/examples/scenes/cornell_diffuse/scene.json";
    const std::vector<std::string> args = {"--scene", scene, "--size", "24x16", "-q"};
    std::vector<std::string> a = {"run", pipe};
    a.insert(a.end(), args.begin(), args.end());
    a.insert(a.end(), {"-o", path("one.exr")});
    auto one = testing::crex_cli(a);
    ASSERT_EQ(one.exit_code, 0) << one.err;
    auto two = mpirun_each({"run", pipe, "--scene", scene, "--size", "24x16", "-q", "-o", path("two.exr")},
                           {"run", path("missing.pipe"), "--scene", path("missing.json"), "--size", "24x16", "-q", "-o", path("two.exr")});
    ASSERT_EQ(two.exit_code, 0) << two.err;
    EXPECT_TRUE(same_image_up_to_traversal(pixels(path("two.exr")), pixels(path("one.exr"))));
}

// A kept plan (JSON) and a RADIANCE scene with a view file, read by rank 0 only: the plan goes
// as its JSON, the scene (its camera from the view file) as the scene's JSON.
TEST_F(MpiRun, AKeptPlanAndARadianceSceneWithAViewRenderTheSingleProcessImage) {
    const std::string rad = CREX_SOURCE_DIR "/examples/scenes/cornell/scene.rad";
    const std::string vf = CREX_SOURCE_DIR "/examples/scenes/cornell/scene.vf";
    auto plan = testing::crex_cli({"plan", "-e", "(TTMRSGD)*", "--scene", rad, "--format", "json", "-o", path("plan.json")});
    ASSERT_EQ(plan.exit_code, 0) << plan.err;
    auto one = testing::crex_cli({"run", path("plan.json"), "--scene", rad, "--view", vf, "--size", "20x18", "--spp", "2", "-q", "-o", path("one.exr")});
    ASSERT_EQ(one.exit_code, 0) << one.err;
    auto two = mpirun_each({"run", path("plan.json"), "--scene", rad, "--view", vf, "--size", "20x18", "--spp", "2", "-q", "-o", path("two.exr")},
                           {"run", path("no-plan.json"), "--scene", path("no.rad"), "--view", path("no.vf"), "--size", "20x18", "--spp", "2", "-q",
                            "-o", path("two.exr")});
    ASSERT_EQ(two.exit_code, 0) << two.err;
    EXPECT_TRUE(same_image_up_to_traversal(pixels(path("two.exr")), pixels(path("one.exr"))));
}

// A scene of a JSON file with an OBJ mesh (and its .mtl), and the OBJ itself: rank 0 loads
// them, the mesh goes inline in the scene's JSON.
TEST_F(MpiRun, AnObjMeshSceneIsSentInline) {
    std::ofstream(path("m.mtl")) << "newmtl wall\nKd 0.6 0.5 0.4\nnewmtl lamp\nKd 0 0 0\nKe 5 5 4\n";
    std::ofstream(path("m.obj")) << "mtllib m.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv 0 0 1\n"
                                    "usemtl wall\nf 1 2 3 4\nusemtl lamp\nf 1 2 5\n";
    std::ofstream(path("s.json")) << R"({"materials": [{"name": "l", "type": "light", "color": [4, 4, 4]}],
      "shapes": [{"type": "mesh", "file": "m.obj"}, {"type": "sphere", "material": "l", "center": [0, 0, 3], "radius": 0.5}]})";
    for (const std::string& scene : {path("s.json"), path("m.obj")}) {
        auto one = testing::crex_cli({"run", "--scene", scene, "--size", "16x12", "--spp", "2", "-q", "-o", path("one.exr")});
        ASSERT_EQ(one.exit_code, 0) << scene << ": " << one.err;
        auto two = mpirun_each({"run", "--scene", scene, "--size", "16x12", "--spp", "2", "-q", "-o", path("two.exr")},
                               {"run", "--scene", path("none.json"), "--size", "16x12", "--spp", "2", "-q", "-o", path("two.exr")});
        ASSERT_EQ(two.exit_code, 0) << scene << ": " << two.err;
        EXPECT_TRUE(same_image_up_to_traversal(pixels(path("two.exr")), pixels(path("one.exr")))) << scene;
        fs::remove(path("two.exr"));
    }
}

// A RADIANCE identifier in Latin-1 (not UTF-8) goes through the scene's JSON to rank 1.
TEST_F(MpiRun, ANameThatIsNotUtf8StillReachesTheOtherRanks) {
    std::ofstream(path("l1.rad")) << "void light lamp\n0\n0\n3 10 10 10\n\nvoid plastic gr\xe9y\n0\n0\n5 .5 .5 .5 0 0\n\n"
                                     "lamp sphere s1\n0\n0\n4 0 2 0 .5\n\ngr\xe9y sphere s2\n0\n0\n4 0 0 0 1\n";
    const std::vector<std::string> args = {"run", "--scene", path("l1.rad"), "--size", "16x12", "--spp", "2", "-q", "-o"};
    std::vector<std::string> a = args;
    a.push_back(path("one.exr"));
    auto one = testing::crex_cli(a);
    ASSERT_EQ(one.exit_code, 0) << one.err;
    a = args;
    a.push_back(path("two.exr"));
    auto two = mpirun(2, a);
    ASSERT_EQ(two.exit_code, 0) << two.err;
    EXPECT_TRUE(same_image_up_to_traversal(pixels(path("two.exr")), pixels(path("one.exr"))));
}

// An error in the input is rank 0's to say, once, with its location; every rank exits 1.
TEST_F(MpiRun, AnInputErrorIsSaidOnceAndEveryRankExitsOne) {
    std::ofstream(path("bad.pipe")) << "pipeline bad {\n  preselective { crex \"(TTMRSGD)*\" spp }\n}\n";
    auto r = mpirun(3, {"run", path("bad.pipe"), "--size", "8x8", "-q", "-o", path("bad.exr")});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(count(r.err, path("bad.pipe") + ":2:"), 1u) << r.err;
    EXPECT_EQ(count(r.err, "nothing rendered"), 1u) << r.err;
    EXPECT_FALSE(fs::exists(path("bad.exr")));
    // Usage errors too, of the flags (every rank parses them) and of their values.
    for (const std::vector<std::string>& flags : {std::vector<std::string>{"--spp", "0"}, {"--ambient", "bogus"}, {"--bogus"}}) {
        std::vector<std::string> a = {"run", "--size", "8x8", "-q", "-o", path("bad.exr")};
        a.insert(a.end(), flags.begin(), flags.end());
        auto usage = mpirun(3, a);
        EXPECT_EQ(usage.exit_code, 2) << usage.err;
        EXPECT_EQ(count(usage.err, "crex run: error:"), 1u) << flags[0] << ": " << usage.err;
    }
    // A missing file is an I/O failure (3), said once too.
    auto missing = mpirun(2, {"run", path("none.pipe"), "--size", "8x8", "-q", "-o", path("bad.exr")});
    EXPECT_EQ(missing.exit_code, 3) << missing.err;
    EXPECT_EQ(count(missing.err, "cannot read '" + path("none.pipe") + "'"), 1u) << missing.err;
}

// `partial` holds the first `finished` rows of `crex run --size WxH --spp 2` in one process,
// pixel for pixel, and black below them.
void expect_finished_rows_of_one_process(const std::string& partial, int width, int height, int finished, const std::string& one) {
    auto r = testing::crex_cli({"run", "--size", std::to_string(width) + "x" + std::to_string(height), "--spp", "2", "-q", "-o", one});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    int w = 0, h = 0;
    std::vector<float> got, want = pixels(one);
    ASSERT_EQ(read_image(partial, w, h, got), "") << partial;
    ASSERT_EQ(w, width);
    ASSERT_EQ(h, height);
    const size_t split = 3 * static_cast<size_t>(width) * static_cast<size_t>(finished);
    EXPECT_TRUE(std::equal(got.begin(), got.begin() + static_cast<std::ptrdiff_t>(split), want.begin())) << "rank 0's finished rows";
    EXPECT_TRUE(std::all_of(got.begin() + static_cast<std::ptrdiff_t>(split), got.end(), [](float v) { return v == 0; }))
        << "the unfinished rows are black";
    EXPECT_TRUE(std::any_of(want.begin() + static_cast<std::ptrdiff_t>(split), want.end(), [](float v) { return v > 0; }))
        << "the test would show nothing";
}

// A shell script that starts `mpirun ... crex run --size SIZE ...` (`mpirun_args`), finds
// `rank` by Open MPI's environment once it is `state` (R: any; T: stopped), waits `settle`
// seconds, kills it with SIGKILL and prints `exit=<mpirun's code> seconds=<from the kill to
// mpirun's end>`, or `rank-not-found`.
std::string kill_rank(int rank, const std::string& mpirun_args, const std::string& size, const std::string& state, double settle) {
    const std::string find = "pgrep -f 'crex run --size " + size + "'";
    const std::string is_state = state == "T" ? " && [ \"$(cut -d' ' -f3 /proc/$p/stat)\" = T ]" : "";
    return std::string(kMpirun) + " " + mpirun_args + " & m=$!; for i in $(seq 1 400); do for p in $(" + find +
           "); do if tr '\\0' '\\n' < /proc/$p/environ 2>/dev/null | grep -qx OMPI_COMM_WORLD_RANK=" + std::to_string(rank) + is_state + "; then sleep " +
           std::to_string(settle) + "; t0=$(date +%s.%N); kill -9 $p; wait $m; e=$?; t1=$(date +%s.%N); echo exit=$e seconds=$(echo \"$t1 - $t0\" | bc); "
           "exit 0; fi; done; sleep 0.1; done; echo rank-not-found; kill $m";
}

double seconds_after_kill(const std::string& out) {
    std::smatch m;
    if (!std::regex_search(out, m, std::regex("seconds=([0-9.]+)"))) return -1;
    return std::stod(m[1]);
}

// Nothing but `names` in the test's directory: no staged file (.NAME.crex-staged-PID.EXT).
void expect_only(const fs::path& dir, std::vector<std::string> names) {
    std::vector<std::string> found;
    for (const auto& e : fs::directory_iterator(dir)) found.push_back(e.path().filename().string());
    std::sort(found.begin(), found.end());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(found, names);
}

TEST_F(MpiRun, ARankKilledMidRenderEndsTheRunNamedWithNothingLeftBehind) {
    // Rank 1 is killed (SIGKILL) a second after it is found running, when both ranks are past
    // MPI_Init and render a band far too large to finish; mpirun names it and ends rank 0,
    // which has no finished row: no output, no partial, no staged file, no crex process left.
    // (Killed at once, the rank could die inside MPI_Init, where Open MPI's launcher once waited
    // until ctest's 600 s timeout in a full parallel run: that is the launcher's start-up, not
    // a render. timeout(1) bounds the run, so a hang fails here with exit=124.)
    const std::string out = path("killed.exr");
    auto r = testing::run_command(
        {"/bin/sh", "-c",
         "timeout -k 5 120 " + kill_rank(1, "--allow-run-as-root --oversubscribe -np 2 " + std::string(CREX_BINARY) +
                                                " run --size 512x512 --spp 1024 -q -o " + out,
                                            "512x512 --spp 1024", "R", 1)});
    EXPECT_NE(r.out.find("exit="), std::string::npos) << r.out << r.err;
    EXPECT_EQ(r.out.find("exit=0"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("exit=124"), std::string::npos) << "the run hung until timeout(1) ended it: " << r.out;
    EXPECT_NE(r.err.find("rank 1"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("signal 9"), std::string::npos) << r.err;
    expect_only(dir_, {});
    EXPECT_EQ(crex_left("512x512 --spp 1024"), "") << "processes left running";
}

TEST_F(MpiRun, AKilledRankHasRankZeroWriteItsFinishedRows) {
    // Rank 1 stops itself at the first (and last) exchange of rows, whose wait --rank-timeout
    // would end only after 60 s; rank 0 has rendered its band, rows 0..11 of 25, and waits
    // there. Then rank 1 is killed with SIGKILL: mpirun names it and ends rank 0 with SIGTERM,
    // then SIGKILL a second later; in that second rank 0 writes its rows to killed.partial.exr,
    // which --resume then finishes.
    const std::string out = path("killed.exr"), partial = path("killed.partial.exr");
    auto r = testing::run_command(
        {"/bin/sh", "-c",
         "CREX_TEST_STALL_RANK=1 timeout -k 5 60 " +
             kill_rank(1, "--allow-run-as-root --oversubscribe -x CREX_TEST_STALL_RANK -np 2 " + std::string(CREX_BINARY) +
                               " run --size 33x25 --spp 2 -q --rank-timeout 60 -o " + out,
                           "33x25", "T", 2)});
    EXPECT_NE(r.out.find("exit="), std::string::npos) << r.out << r.err;
    EXPECT_EQ(r.out.find("exit=0"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("exit=124"), std::string::npos) << "the run hung until timeout(1) ended it: " << r.out;
    const double seconds = seconds_after_kill(r.out);
    EXPECT_GT(seconds, 0) << r.out;
    EXPECT_LT(seconds, 10.0) << "mpirun ends the run about 1 s after the kill";
    EXPECT_NE(r.err.find("rank 1"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("signal 9"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("crex run: error: the run was ended from outside (SIGTERM to rank 0)"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("rows 0..11 of 25 finished, written to " + partial), std::string::npos) << r.err;
    expect_only(dir_, {"killed.partial.exr"});  // not the requested output, no staged file
    EXPECT_EQ(crex_left("33x25"), "") << "processes left running";
    expect_finished_rows_of_one_process(partial, 33, 25, 12, path("one.exr"));
    // And resumable: the same command with --resume renders rows 12..24 and writes the whole.
    auto resumed = testing::crex_cli({"run", "--size", "33x25", "--spp", "2", "-q", "--resume", partial, "-o", out});
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    EXPECT_TRUE(same_image_up_to_traversal(pixels(out), pixels(path("one.exr"))));
}

TEST_F(MpiRun, AStoppedRankEndsTheRunNamedWithinTheTimeout) {
    // Rank 1 stops itself (SIGSTOP, the test hook of builds with tests) when it reaches the
    // first exchange of rows: alive to Open MPI, silent to rank 0. Rank 0 waits --rank-timeout
    // (8 s), names rank 1 and aborts; mpirun ends the stopped rank too (SIGKILL).
    const std::string out = path("stalled.exr");
    // `timeout`: without the watchdog the run would hang the test (exit 124 then). 8 s, not 2
    // or 4: with other MPI tests and two builds beside it on two cores, rank 0 took over 4 s
    // to reach the start of the render and rank 1 named that instead: start-up is not what
    // this measures.
    const std::string script = hooked_run("CREX_TEST_STALL_RANK=1", "--size 31x29 --spp 2 -q --rank-timeout 8 -o " + out);
    const auto start = std::chrono::steady_clock::now();
    auto r = testing::run_command({"/bin/sh", "-c", script});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NE(r.err.find("crex run: error: rank 1 did not reach the exchange of rows no. 1"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("within 8 s"), std::string::npos) << r.err;
    EXPECT_LT(seconds, 40.0) << "the timeout is 8 s; start-up and the abort take the rest";
    EXPECT_FALSE(fs::exists(out)) << "the requested output is never written by a failed run";
    EXPECT_EQ(crex_left("31x29"), "") << "processes left running";
    // Rank 0 had rendered its band, rows 0..13 of 29, before it waited: they are written to
    // stalled.partial.exr, as the single-process image has them; the other rows are black.
    const std::string partial = path("stalled.partial.exr");
    EXPECT_NE(r.err.find("rows 0..13 of 29 finished, written to " + partial), std::string::npos) << r.err;
    expect_finished_rows_of_one_process(partial, 31, 29, 14, path("one.exr"));
}

// A rank that fails (an exception; the test hook throws in rank 1's first exchange of rows)
// reports to rank 0, which is waiting there with its band finished: it writes that band and
// ends the run with the failing rank's exit code.
TEST_F(MpiRun, AFailingRankHasRankZeroWriteItsFinishedRows) {
    const std::string out = path("failed.exr");
    const std::string script =
        hooked_run("CREX_TEST_FAIL_RANK=1", "--size 30x20 --spp 2 -q --rank-timeout 20 -o " + out + " -o " + path("failed.png"));
    const auto start = std::chrono::steady_clock::now();
    auto r = testing::run_command({"/bin/sh", "-c", script});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NE(r.err.find("crex run: error: rank 1: rendering failed: test hook"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("rows 0..9 of 20 finished, written to " + path("failed.partial.exr") + ", " + path("failed.partial.png")),
              std::string::npos)
        << r.err;
    EXPECT_LT(seconds, 15.0) << "rank 0 takes the report at once, not after --rank-timeout";
    EXPECT_TRUE(fs::exists(path("failed.partial.exr")));
    EXPECT_TRUE(fs::exists(path("failed.partial.png")));
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(path("failed.png")));
}

// Rank 0 itself stopped: rank 1 names it, and after its grace of 10 s ends the run. mpirun
// continues rank 0 (SIGCONT) before ending it. After an MPI_Abort, SIGTERM and SIGKILL can
// follow each other within milliseconds, so rank 0 writes its rows only when it wins that race
// (about 1 run in 3 here it does not): what is certain is the error, the end, no process left,
// and that a partial, when there is one, holds exactly the single-process rows.
TEST_F(MpiRun, AStoppedRankZeroIsNamedAndTheRunEnds) {
    // A timeout of 8 s, not 1 or 4: under load rank 0 took seconds to read and check its
    // inputs, and rank 1 named the start of the render instead.
    const std::string script = hooked_run("CREX_TEST_STALL_RANK=0", "--size 27x19 --spp 2 -q --rank-timeout 8 -o " + path("r0.exr"));
    auto r = testing::run_command({"/bin/sh", "-c", script});
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NE(r.err.find("crex run: error: rank 0 did not reach the exchange of rows no. 1"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("rank 0, which holds the image, did not end the run within 10 s"), std::string::npos) << r.err;
    EXPECT_EQ(crex_left("27x19"), "") << "processes left running";
    EXPECT_FALSE(fs::exists(path("r0.exr"))) << "the requested output is never written by a failed run";
    if (r.err.find("rows 0..8 of 19 finished, written to " + path("r0.partial.exr")) != std::string::npos)
        expect_finished_rows_of_one_process(path("r0.partial.exr"), 27, 19, 9, path("one.exr"));
}

// Rank 0 killed (SIGKILL) with its band finished: it holds the image, so nothing can be
// written; mpirun names it and ends rank 1.
TEST_F(MpiRun, AKilledRankZeroLeavesNothingWritten) {
    auto r = testing::run_command(
        {"/bin/sh", "-c",
         "CREX_TEST_STALL_RANK=0 timeout -k 5 60 " +
             kill_rank(0, "--allow-run-as-root --oversubscribe -x CREX_TEST_STALL_RANK -np 2 " + std::string(CREX_BINARY) +
                              " run --size 29x21 --spp 2 -q --rank-timeout 60 -o " + path("r0.exr"),
                       "29x21", "T", 0.5)});
    EXPECT_NE(r.out.find("exit="), std::string::npos) << r.out << r.err;
    EXPECT_EQ(r.out.find("exit=0"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("exit=124"), std::string::npos) << "the run hung until timeout(1) ended it: " << r.out;
    EXPECT_LT(seconds_after_kill(r.out), 10.0) << r.out;
    EXPECT_NE(r.err.find("rank 0"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("signal 9"), std::string::npos) << r.err;
    expect_only(dir_, {});
    EXPECT_EQ(crex_left("29x21"), "") << "processes left running";
}

// A run whose rank 1 fails at exchange of rows no. `exchange` (or `end`: the last; the hook
// throws there), so rank 0 writes the rows it finished to NAME.partial.exr; `args` follow
// `crex run`.
testing::CommandResult fail_rank_one_at(const std::string& exchange, const std::string& args) {
    return testing::run_command({"/bin/sh", "-c", hooked_run("CREX_TEST_FAIL_RANK=1 CREX_TEST_FAULT_EXCHANGE=" + exchange, args)});
}

long rays_of(const testing::CommandResult& r) {
    const auto j = nlohmann::json::parse(r.out, nullptr, false);
    return j.is_object() && j.contains("rays") ? j["rays"].get<long>() : -1L;
}

// --resume: the same command, in one process, renders only the rows the partial image does not
// hold and writes the whole image, which is the uninterrupted single-process image exactly.
// A plain crex renders the other rows alone (about half the rays); a pipeline (guidance over
// the whole image, two rounds) renders the preview and its first round whole and skips the
// final rows only in the last round. Rank 1 fails at the last exchange of rows, before which
// rank 0's band of the last stage is final.
TEST_F(MpiRun, AResumedRunFinishesThePartialAsOneUninterruptedProcess) {
    struct Case {
        std::string name, args;
        std::string rows;  // rank 0's, when known beforehand
    };
    const std::string pipe = CREX_SOURCE_DIR "/stdlib/pipelines/sel_rp.pipe";
    // The pipeline's last round has bands balanced by its samples: rank 0's rows are its band's.
    for (const Case& c : {Case{"crex", "--size 30x20 --spp 2", "rows 0..9 of 20"}, Case{"pipeline", pipe + " --size 40x30 --rounds 2", ""}}) {
        SCOPED_TRACE(c.name);
        const std::string out = path(c.name + ".exr"), partial = path(c.name + ".partial.exr");
        auto failed = fail_rank_one_at("end", c.args + " -q -o " + out);
        ASSERT_EQ(failed.exit_code, 3) << failed.err;
        std::smatch m;
        ASSERT_TRUE(std::regex_search(failed.err, m, std::regex("(rows 0\\.\\.[0-9]+ of [0-9]+) finished, written to "))) << failed.err;
        const std::string rows = m[1];
        if (!c.rows.empty()) {
            EXPECT_EQ(rows, c.rows);
        }
        ASSERT_NE(failed.err.find(rows + " finished, written to " + partial), std::string::npos) << failed.err;
        auto args = [&](const std::string& more) {
            std::vector<std::string> a = {"run"};
            std::istringstream words(c.args + " --format json " + more);
            for (std::string w; words >> w;) a.push_back(w);
            return a;
        };
        auto resumed = testing::crex_cli(args("--resume " + partial + " -o " + out));
        ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
        EXPECT_NE(resumed.err.find("crex run: note: " + rows + " taken from " + partial), std::string::npos) << resumed.err;
        auto one = testing::crex_cli(args("-o " + path(c.name + "-one.exr")));
        ASSERT_EQ(one.exit_code, 0) << one.err;
        const std::vector<float> want = pixels(path(c.name + "-one.exr")), got = pixels(out);
        ASSERT_EQ(got.size(), want.size());
        EXPECT_TRUE(got == want) << "the resumed image is the uninterrupted one";
        EXPECT_TRUE(std::any_of(want.begin(), want.end(), [](float v) { return v > 0; }));
        EXPECT_TRUE(std::none_of(got.begin(), got.end(), [](float v) { return std::isnan(v); }));
        const long rays_resumed = rays_of(resumed), rays_one = rays_of(one);
        EXPECT_GT(rays_resumed, 0) << resumed.out;
        EXPECT_LT(rays_resumed, rays_one) << "the final rows' last samples were not traced again";
        if (c.name == "crex") {
            EXPECT_LT(rays_resumed, 0.7 * static_cast<double>(rays_one)) << "half the rows: about half the rays";
        }
    }
}

// A pipeline that varies subsample (apict) interpolates pixels from corners in other rows at
// the end: rank 0's band, rendered and waiting at the last exchange, is not final yet, so a
// fault there writes no row (it wrote the band without the interpolation, 71 % of its pixels
// wrong at 32x32).
TEST_F(MpiRun, APipelineThatInterpolatesAcrossRowsWritesNoRowBeforeEveryBandIsIn) {
    const std::string pipe = CREX_SOURCE_DIR "/stdlib/pipelines/apict.pipe";
    auto r = fail_rank_one_at("end", pipe + " --size 32x32 -q -o " + path("a.exr"));
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NE(r.err.find("crex run: error: rank 1: rendering failed: test hook"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("rank 0 had no finished row"), std::string::npos) << r.err;
    expect_only(dir_, {});
}

// --resume refuses (exit 2, the requested output not written) a partial of another run (the
// setting that differs named), an image that is not a partial, a run it cannot resume exactly
// (an irradiance cache), and mpirun (said once).
TEST_F(MpiRun, ResumingRefusesWhatItCannotFinishExactly) {
    const std::string partial = path("p.partial.exr");
    auto failed = fail_rank_one_at("1", "--size 26x18 --spp 2 -q -o " + path("p.exr"));
    ASSERT_EQ(failed.exit_code, 3) << failed.err;
    ASSERT_TRUE(fs::exists(partial)) << failed.err;
    struct Case {
        std::vector<std::string> args;  // besides -q -o; --size 26x18 and --spp 2 unless given
        std::string error;
    };
    auto resume = [&](const Case& c) {
        std::vector<std::string> a = {"run", "-q", "-o", path("r.exr")};
        auto given = [&](const std::string& flag) { return std::find(c.args.begin(), c.args.end(), flag) != c.args.end(); };
        if (!given("--size")) a.insert(a.end(), {"--size", "26x18"});
        if (!given("--spp")) a.insert(a.end(), {"--spp", "2"});
        a.insert(a.end(), c.args.begin(), c.args.end());
        return testing::crex_cli(a);
    };
    auto one = testing::crex_cli({"run", "--size", "26x18", "--spp", "2", "-q", "-o", path("one.exr")});
    ASSERT_EQ(one.exit_code, 0) << one.err;
    for (const Case& c : {Case{{"--seed", "3", "--resume", partial}, "it was rendered with seed '0', this run's '3'"},
                          Case{{"--spp", "4", "--resume", partial}, "it was rendered with spp 2, this run has spp 4"},
                          Case{{"--size", "26x19", "--resume", partial}, "it was rendered with size 26x18, this run has size 26x19"},
                          Case{{"--resume", path("one.exr")}, "not a partial image of crex run"},
                          Case{{"--ic", "--resume", partial}, "cannot resume a run with an irradiance cache"}}) {
        auto r = resume(c);
        EXPECT_EQ(r.exit_code, 2) << r.err;
        EXPECT_NE(r.err.find("crex run: error: --resume "), std::string::npos) << r.err;
        EXPECT_NE(r.err.find(c.error), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(path("r.exr")));
    }
    // A header that names rows its pixels do not hold (issue 37: it resumed into black rows):
    // the same partial, its crex:finished_rows edited to claim every row.
    {
        int w = 0, h = 0;
        ImageMetadata header;
        std::vector<float> rgb;
        ASSERT_EQ(read_image_metadata(partial, w, h, header), "");
        ASSERT_EQ(read_image(partial, w, h, rgb), "");
        for (auto& [key, value] : header)
            if (key == "crex:finished_rows") value = "0..17";
        ImageMetadata kept;
        for (const auto& [key, value] : header)
            if (key.rfind("crex:", 0) == 0) kept.push_back({key, value});
        ASSERT_EQ(write_image(path("edited.partial.exr"), w, h, {{"", rgb}}, kept), "");
        auto r = resume({{"--resume", path("edited.partial.exr")}, ""});
        EXPECT_EQ(r.exit_code, 1) << r.err;
        EXPECT_NE(r.err.find("its crex:finished_rows '0..17' names rows its pixels do not hold"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(path("r.exr")));
    }
    auto under_mpirun = mpirun(2, {"run", "--size", "26x18", "--spp", "2", "-q", "--resume", partial, "-o", path("r.exr")});
    EXPECT_EQ(under_mpirun.exit_code, 2) << under_mpirun.err;
    EXPECT_EQ(count(under_mpirun.err, "--resume is not supported yet"), 1u) << under_mpirun.err;
    EXPECT_FALSE(fs::exists(path("r.exr")));
}

// The irradiance records made over all ranks, from rank 0's note.
long records_over_ranks(const testing::CommandResult& r) {
    std::smatch m;
    EXPECT_TRUE(std::regex_search(r.err, m, std::regex("([0-9]+) irradiance records over all ranks"))) << r.err;
    return m.size() > 1 ? std::stol(m[1]) : -1L;
}

// --ic-share broadcast and central: the records each rank made reach every rank at least
// after the preview and before each later round, so the ranks together make fewer than when
// each keeps its own. (Central's exchanges during the render depend on timing: only the
// inequality is stable.)
TEST_F(MpiRun, BroadcastAndCentralSharingMakeFewerRecordsThanNone) {
    const std::string pipe = CREX_SOURCE_DIR "/stdlib/pipelines/adaptive.pipe";  // a cache, three rounds
    auto records = [&](const std::string& mode) {
        auto r = mpirun(2, {"run", pipe, "--size", "48x48", "-q", "--ic-share", mode, "-o", path(mode + ".exr")});
        EXPECT_EQ(r.exit_code, 0) << mode << ": " << r.err;
        EXPECT_NE(r.err.find("--ic-share " + mode), std::string::npos) << r.err;
        return records_over_ranks(r);
    };
    const long none = records("none"), broadcast = records("broadcast"), central = records("central");
    EXPECT_GT(none, 0);
    EXPECT_GT(broadcast, 0);
    EXPECT_GT(central, 0);
    EXPECT_LT(broadcast, none);
    EXPECT_LT(central, none);
}

// --ic-share component at N = 2: one PA answers every D batch of the one PR, which renders
// every row in the single process's order, so the image is the single-process image.
TEST_F(MpiRun, ComponentSharingOnTwoRanksRendersTheSingleProcessImage) {
    const std::vector<std::string> args = {"run", "--size", "32x24", "--spp", "2", "--ic", "--ad", "64", "-q"};
    std::vector<std::string> a = args;
    a.insert(a.end(), {"-o", path("one.exr")});
    auto one = testing::crex_cli(a);
    ASSERT_EQ(one.exit_code, 0) << one.err;
    a = args;
    a.insert(a.end(), {"-o", path("two.exr")});  // component is the default with a cache
    auto two = mpirun(2, a);
    ASSERT_EQ(two.exit_code, 0) << two.err;
    EXPECT_NE(two.err.find("1 PA rank(s) answering irradiance queries, 1 PR rank(s)"), std::string::npos) << two.err;
    EXPECT_TRUE(same_image_up_to_traversal(pixels(path("two.exr")), pixels(path("one.exr"))));
}

// --ic-file under component: rank 0 reads it and the PA loads the bytes rank 0 sent; at the
// end the PA sends its records back and rank 0 writes the file. Rank 1 (the PA) is given a
// path in a directory that does not exist: it never touches the file.
TEST_F(MpiRun, RankZeroReadsAndWritesTheCacheFileOfAnAnsweringRank) {
    const std::string ic = path("cache.ic");
    const std::vector<std::string> args = {"run", "--size", "32x24", "--spp", "2", "--ad", "64", "-q"};
    auto run = [&](const std::string& out) {
        std::vector<std::string> a0 = args, a1 = args;
        a0.insert(a0.end(), {"--ic-file", ic, "-o", path(out)});
        a1.insert(a1.end(), {"--ic-file", path("nowhere/cache.ic"), "-o", path(out)});
        return mpirun_each(a0, a1);
    };
    auto first = run("first.exr");
    ASSERT_EQ(first.exit_code, 0) << first.err;
    ASSERT_TRUE(fs::exists(ic)) << first.err;
    EXPECT_FALSE(fs::exists(path("nowhere")));
    auto second = run("second.exr");
    ASSERT_EQ(second.exit_code, 0) << second.err;
    const long made_first = records_over_ranks(first), made_second = records_over_ranks(second);
    EXPECT_GT(made_first, 0);
    EXPECT_LT(made_second, made_first) << "the records loaded from the file are used";
}

// At N = 3 the PA serves its two PRs in rank order, round-robin: the same image on every run
// (it differs from one process's: the batches come in another order).
TEST_F(MpiRun, ComponentSharingIsDeterministicForAFixedRankCount) {
    const std::string pipe = CREX_SOURCE_DIR "/stdlib/pipelines/adaptive.pipe";  // rounds: exchanges mid-render
    long records[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
        auto r = mpirun(3, {"run", pipe, "--size", "40x30", "-q", "--ic-share", "component", "-o", path(std::to_string(k) + ".exr")});
        ASSERT_EQ(r.exit_code, 0) << r.err;
        records[k] = records_over_ranks(r);
    }
    EXPECT_GT(records[0], 0);
    EXPECT_EQ(records[0], records[1]);
    EXPECT_EQ(pixels(path("0.exr")), pixels(path("1.exr")));
}

// At N = 8 two PAs (ranks 6 and 7) each serve three PRs and exchange their records where
// the PRs exchange rows: still the same image on every run.
TEST_F(MpiRun, TwoAnsweringRanksExchangeRecordsDeterministically) {
    const std::string pipe = CREX_SOURCE_DIR "/stdlib/pipelines/adaptive.pipe";
    for (int k = 0; k < 2; ++k) {
        auto r = mpirun(8, {"run", pipe, "--size", "24x24", "--threads", "1", "-q", "-o", path(std::to_string(k) + ".exr")});
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_NE(r.err.find("2 PA rank(s) answering irradiance queries, 6 PR rank(s)"), std::string::npos) << r.err;
    }
    EXPECT_EQ(pixels(path("0.exr")), pixels(path("1.exr")));
}

TEST_F(MpiRun, AStoppedAnsweringRankIsNamedToo) {
    // --ic-share component on 2 ranks: rank 1 is the PA and stops after its first answer;
    // the PR waits twice --rank-timeout for it (the PA may be waiting that long for another PR).
    // --rank-timeout 6, not 1 or 3: on a loaded machine rank 0 took over 3 s to reach the start
    // of the render, and rank 1 named that instead (seen with two builds beside ctest -j2).
    const std::string script =
        hooked_run("CREX_TEST_STALL_RANK=1", "--size 33x21 --spp 2 --ic --ad 32 -q --rank-timeout 6 -o " + path("pa.exr"));
    auto r = testing::run_command({"/bin/sh", "-c", script});
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NE(r.err.find("crex run: error: rank 1 did not answer irradiance queries within 12 s"), std::string::npos) << r.err;
    // Rank 0 was still rendering its band (waiting for answers): no row was final.
    EXPECT_NE(r.err.find("rank 0 had no finished row (rows are final from the last exchange of rows on): nothing written"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("pa.partial.exr")));
    EXPECT_EQ(crex_left("33x21"), "") << "processes left running";
}

// A budget under mpirun: each rank spends all of it on its own band, so the run ends after
// about the budget (a render the budget cuts far short) and both bands have light in them.
TEST_F(MpiRun, EachRankSpendsTheBudgetOnItsOwnBand) {
    const auto start = std::chrono::steady_clock::now();
    auto r = mpirun(2, {"run", "--size", "40x30", "--spp", "100000", "--budget", "1s", "-o", path("b.exr")});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_LT(seconds, 20.0) << "the budget is 1 s; without it the render takes hours";
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.err, m, std::regex("each rank spends the whole budget \\(1 s\\) on its own band of rows, deciding "
                                                       "its passes alone: ([0-9]+) camera samples left out over all ranks")))
        << r.err;
    EXPECT_GT(std::stod(m[1]), 0.0);
    const std::vector<float> rgb = pixels(path("b.exr"));
    ASSERT_EQ(rgb.size(), 3u * 40 * 30);
    const size_t half = rgb.size() / 2;
    EXPECT_TRUE(std::any_of(rgb.begin(), rgb.begin() + half, [](float v) { return v > 0; })) << "rank 0's band";
    EXPECT_TRUE(std::any_of(rgb.begin() + half, rgb.end(), [](float v) { return v > 0; })) << "rank 1's band";
}

// --report and --reference under mpirun: rank 0 writes the report from the shared film. A plain
// crex exchanges rows only at the end, so its error curve has one point, the end (before it
// rank 0's film holds only its own band). The reference here is the single-process image,
// which the 2-rank image equals: error 0.
// `args` once in one process (one.exr), then on 2 ranks with that image as the reference and
// a report (two.exr, report/): the 2-rank run's JSON summary, after checking it is the same image.
// `relative`: how far a value may be from one process's (0: bit for bit).
nlohmann::json MpiRun::reported_against_one_process(const std::vector<std::string>& args, double relative) {
    std::vector<std::string> a = args;
    a.insert(a.end(), {"-q", "-o", path("one.exr")});
    auto one = testing::crex_cli(a);
    EXPECT_EQ(one.exit_code, 0) << one.err;
    a = args;
    a.insert(a.end(), {"--reference", path("one.exr"), "--report", path("report"), "--format", "json", "-o", path("two.exr")});
    auto two = mpirun(2, a);
    EXPECT_EQ(two.exit_code, 0) << two.err;
    const std::vector<float> a2 = pixels(path("two.exr")), a1 = pixels(path("one.exr"));
    if (relative == 0) {
        EXPECT_EQ(a2, a1);
    }
    EXPECT_EQ(a2.size(), a1.size());
    for (size_t i = 0; relative > 0 && i < std::min(a1.size(), a2.size()); ++i) EXPECT_NEAR(a2[i], a1[i], relative * std::fabs(a1[i]) + 1e-12) << i;
    EXPECT_TRUE(fs::exists(path("report/index.html")));
    return nlohmann::json::parse(two.out, nullptr, false);
}

TEST_F(MpiRun, RankZeroWritesTheReportWithTheErrorAtTheEnd) {
    const auto j = reported_against_one_process({"run", "--size", "24x18", "--spp", "2"});
    ASSERT_TRUE(j.is_object());
    ASSERT_EQ(j["error_curve"].size(), 1u) << j.dump();
    EXPECT_EQ(j["error_curve"][0]["stage"], "end");
    EXPECT_EQ(j["error_curve"][0]["rmse"].get<double>(), 0.0);
    std::ifstream in(path("report/checkpoints.json"));
    const auto cj = nlohmann::json::parse(in, nullptr, false);
    ASSERT_TRUE(cj.is_object());
    EXPECT_EQ(cj["checkpoints"].size(), 1u);
}

// The points of a report of sel_rp in 2 rounds: the preview, round 1's exchange, the end.
void expect_preview_round_end(const nlohmann::json& points) {
    EXPECT_EQ(points[0]["stage"], "preselective");
    EXPECT_EQ(points[1]["stage"], "selective");
    EXPECT_EQ(points[2]["stage"], "end");
}

// A pipeline exchanges rows after its preview and after each round but the last: there rank
// 0's film holds every rank's rows, and each exchange is a point of the error curve before
// the end. sel_rp in 2 rounds: the preview, round 1, the end, with the error falling to 0
// (the reference is the single-process image). Its selective stages go in progressive passes,
// one sample index each, and after round 1 a pixel's later passes may land on another rank
// than in one process: the image is one process's up to the order of the film's sums (1e-6
// relative; measured RMSE 2e-10).
TEST_F(MpiRun, RankZeroReportsTheErrorAtEveryExchangeOfRows) {
    const auto j = reported_against_one_process({"run", CREX_SOURCE_DIR "/stdlib/pipelines/sel_rp.pipe", "--size", "24x18", "--rounds", "2"}, 1e-6);
    ASSERT_TRUE(j.is_object());
    const auto& curve = j["error_curve"];
    ASSERT_EQ(curve.size(), 3u) << j.dump();
    expect_preview_round_end(curve);
    // The preview is far from the final image, round 1 nearer, the end is it.
    EXPECT_GT(curve[0]["rmse"].get<double>(), curve[1]["rmse"].get<double>()) << j.dump();
    EXPECT_GT(curve[1]["rmse"].get<double>(), 0.0);
    EXPECT_LT(curve[2]["rmse"].get<double>(), 1e-6);
    EXPECT_LE(curve[0]["seconds"].get<double>(), curve[1]["seconds"].get<double>());
}

// Without a reference a report under mpirun still names every exchange and the end (rank 0
// keeps no image of them: nothing would read it).
TEST_F(MpiRun, AReportWithoutAReferenceNamesEveryExchange) {
    auto r = mpirun(2, {"run", CREX_SOURCE_DIR "/stdlib/pipelines/sel_rp.pipe", "--size", "24x18", "--rounds", "2", "--report",
                        path("report"), "-q", "-o", path("x.exr")});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream in(path("report/checkpoints.json"));
    const auto cj = nlohmann::json::parse(in, nullptr, false);
    ASSERT_TRUE(cj.is_object());
    const auto& cps = cj["checkpoints"];
    ASSERT_EQ(cps.size(), 3u) << cj.dump();
    expect_preview_round_end(cps);
    EXPECT_FALSE(cps[2].contains("rmse"));
    EXPECT_TRUE(fs::exists(path("report/index.html")));
}

// Still refused under mpirun (once, exit 2): each rank would render the whole image again.
// A sequence's frames split among the ranks (issue 36), each a run of consecutive frames:
// without a cache every frame is the single-process frame, pixel for pixel; rank 0 says every
// frame, and saves the cache file alone.
TEST_F(MpiRun, AFrameRangeRendersTheSingleProcessFrames) {
    const std::string walk = CREX_SOURCE_DIR "/examples/paths/corridor_walk.json";
    const std::string corridor = CREX_SOURCE_DIR "/examples/scenes/corridor/scene.json";
    auto args = [&](const std::string& out) {
        return std::vector<std::string>{"run", "--scene", corridor, "--camera-path", walk, "--frames", "0..4", "--size", "24x16",
                                        "--spp", "2", "-o", path(out)};
    };
    auto one_args = args("one.exr");
    one_args.push_back("-q");
    auto one = testing::crex_cli(one_args);
    ASSERT_EQ(one.exit_code, 0) << one.err;
    for (int ranks : {2, 3}) {
        const std::string stem = "n" + std::to_string(ranks);
        auto n_args = args(stem + ".exr");
        n_args.insert(n_args.end(), {"--format", "json"});
        auto n = mpirun(ranks, n_args);
        ASSERT_EQ(n.exit_code, 0) << ranks << " ranks: " << n.err;
        const auto j = nlohmann::json::parse(n.out, nullptr, false);
        ASSERT_TRUE(j.is_object()) << n.out;
        EXPECT_EQ(j["processes"].get<int>(), ranks);
        ASSERT_EQ(j["frames"].size(), 5u);
        for (int f = 0; f <= 4; ++f) {
            EXPECT_EQ(j["frames"][f]["frame"].get<int>(), f);
            const std::string name = fmt::format(".{:04d}.exr", f);
            EXPECT_EQ(pixels(path(stem + name)), pixels(path("one" + name))) << ranks << " ranks, frame " << f;
        }
    }
    // With a cache, the ranks share each frame's records after every step of their shares
    // (0-1 and 2-4 here): frame 1 starts from frames 0 and 2's records, frame 4 from those of
    // 0 to 3. The file is rank 0's, written whole.
    auto cached = args("c.exr");
    cached.insert(cached.end(), {"--ic", "--ic-file", path("walk.ic"), "--format", "json"});
    auto c = mpirun(2, cached);
    ASSERT_EQ(c.exit_code, 0) << c.err;
    const auto cj = nlohmann::json::parse(c.out, nullptr, false);
    ASSERT_TRUE(cj.is_object()) << c.out;
    auto made = [&](int f) { return cj["frames"][f]["records_made"].get<size_t>(); };
    auto reused = [&](int f) { return cj["frames"][f]["records_reused"].get<size_t>(); };
    EXPECT_EQ(reused(0), 0u);
    EXPECT_EQ(reused(2), 0u);
    EXPECT_EQ(reused(1), made(0) + made(2));
    EXPECT_EQ(reused(3), made(0) + made(2));
    EXPECT_EQ(reused(4), made(0) + made(1) + made(2) + made(3));
    auto again = args("x.exr");
    *std::find(again.begin(), again.end(), "0..4") = "0";
    again.insert(again.end(), {"--ic", "--ic-file", path("walk.ic"), "--format", "json"});
    auto check = testing::crex_cli(again);
    ASSERT_EQ(check.exit_code, 0) << check.err;
    const auto reread = nlohmann::json::parse(check.out, nullptr, false);
    ASSERT_TRUE(reread.is_object()) << check.out;
    EXPECT_GT(reread["frames"][0]["records_reused"].get<size_t>(), 0u) << check.out;
}

TEST_F(MpiRun, ComparingPoliciesIsRefusedOnceWithExitTwo) {
    auto ref = testing::crex_cli({"run", "--size", "8x8", "-q", "-o", path("ref.exr")});
    ASSERT_EQ(ref.exit_code, 0) << ref.err;
    auto r = mpirun(2, {"run", "--size", "8x8", "-q", "--budget", "1s", "--reference", path("ref.exr"), "--compare-policies", "-o", path("x.exr")});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(count(r.err, "--compare-policies is not supported yet"), 1u) << r.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
}

TEST_F(MpiRun, AnUnknownSharingModeIsAUsageError) {
    auto r = testing::crex_cli({"run", "--size", "8x8", "--ic", "--ic-share", "gossip", "-q", "-o", path("x.exr")});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("--ic-share"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
}

}  // namespace
}  // namespace crex
