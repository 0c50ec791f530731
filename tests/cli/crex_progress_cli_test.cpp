// `crex run` watched as a user watches it (issue 38): off a terminal, progress comes as plain
// lines once a render runs long; Ctrl-C ends it with the image so far as NAME.partial.EXT and
// exit 130 (SIGTERM too, exit 143), the output the user had untouched; a camera path's frames
// stop between frames, a reference keeps its samples so far; --progress none says nothing.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <thread>

#include "runtime/io/image_io.h"
#include "runtime/reference/windowed_image.h"
#include "tests/support/crex_cli.h"
#include "tests/support/scratch_folder.h"

extern char** environ;

namespace crex {
namespace {

using testing::crex_cli;

class CrexProgressCli : public testing::ScratchFolderTest {
protected:
    CrexProgressCli() : ScratchFolderTest("crex_progress_cli_") {}

    // Starts `crex ARGS` with stderr to a file; its pid.
    pid_t start(const std::vector<std::string>& args, const std::string& err_file) {
        std::vector<std::string> argv = {CREX_BINARY};
        argv.insert(argv.end(), args.begin(), args.end());
        std::vector<char*> raw;
        for (auto& a : argv) raw.push_back(a.data());
        raw.push_back(nullptr);
        posix_spawn_file_actions_t files;
        posix_spawn_file_actions_init(&files);
        posix_spawn_file_actions_addopen(&files, STDERR_FILENO, err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
        pid_t pid = -1;
        const int failed = posix_spawn(&pid, raw[0], &files, nullptr, raw.data(), environ);
        posix_spawn_file_actions_destroy(&files);
        return failed ? -1 : pid;
    }
    static std::string text_of(const std::string& file) {
        std::ifstream in(file);
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    }
    // Waits up to 120 s for `file` to hold `text` (a process's stderr saying it got that far).
    static bool waits_to_say(const std::string& file, const std::string& text, int poll_ms = 100) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(120);
        while (text_of(file).find(text) == std::string::npos && std::chrono::steady_clock::now() < until)
            std::this_thread::sleep_for(std::chrono::milliseconds(poll_ms));
        return text_of(file).find(text) != std::string::npos;
    }
    // Waits up to `seconds` for `pid`: its exit code, -1 if it did not end (then it is killed).
    static int wait_for(pid_t pid, double seconds) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        int status = 0;
        while (std::chrono::steady_clock::now() < until) {
            if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
        return -1;
    }
};

TEST_F(CrexProgressCli, CtrlCWritesTheImageSoFarAsAPartialFileAndPlainProgressComesOffATerminal) {
    // An output from before, which must stay as it was.
    const std::string out = path("x.exr");
    std::ofstream(out) << "the user's old file";
    const std::string err = path("err.txt");
    // Far more samples than the test waits for (only Ctrl-C ends it), in short passes.
    const pid_t pid = start({"run", "--scene", "builtin:cornell", "--size", "48x48", "--spp", "1000000", "--pass-samples", "4", "-o", out, "--progress", "plain"}, err);
    ASSERT_GT(pid, 0);
    // Plain lines begin once the render has run 5 s: wait for the first.
    ASSERT_TRUE(waits_to_say(err, "M rays/s")) << text_of(err);
    kill(pid, SIGINT);
    EXPECT_EQ(wait_for(pid, 120), 130) << text_of(err);
    const std::string said = text_of(err);
    EXPECT_NE(said.find("crex: "), std::string::npos) << said;  // a plain progress line: "crex: 5 s: render pass 7/1000000 0%, ..."
    EXPECT_NE(said.find("render"), std::string::npos) << said;
    EXPECT_NE(said.find("interrupted"), std::string::npos) << said;
    EXPECT_NE(said.find("x.partial.exr"), std::string::npos) << said;
    EXPECT_EQ(said.find('\r'), std::string::npos) << "no terminal redraws in a log";
    // The image so far: whole, finite, lit, with fewer samples than asked; the old file kept.
    EXPECT_EQ(text_of(out), "the user's old file");
    int width = 0, height = 0;
    std::vector<float> rgb;
    ASSERT_EQ(read_image(path("x.partial.exr"), width, height, rgb), "") << said;
    EXPECT_EQ(width, 48);
    double sum = 0;
    for (float v : rgb) {
        ASSERT_TRUE(std::isfinite(v));
        sum += v;
    }
    EXPECT_GT(sum, 0);
}

// SIGTERM (kill's default, and a batch scheduler's at a job's time limit) stops a render as
// Ctrl-C does, exit 143: it ended the process at once, the image so far lost, until 2026-12-07.
TEST_F(CrexProgressCli, SigtermWritesTheImageSoFarAsCtrlCDoes) {
    const std::string err = path("err.txt");
    const pid_t pid = start({"run", "--scene", "builtin:cornell", "--size", "48x48", "--spp", "1000000", "--pass-samples", "4", "-o",
                             path("t.exr"), "--progress", "plain"}, err);
    ASSERT_GT(pid, 0);
    ASSERT_TRUE(waits_to_say(err, "M rays/s")) << text_of(err);
    kill(pid, SIGTERM);
    EXPECT_EQ(wait_for(pid, 120), 143) << text_of(err);
    const std::string said = text_of(err);
    EXPECT_NE(said.find("interrupted by SIGTERM"), std::string::npos) << said;
    EXPECT_NE(said.find("t.partial.exr"), std::string::npos) << said;
    EXPECT_FALSE(std::filesystem::exists(path("t.exr")));
    int width = 0, height = 0;
    std::vector<float> rgb;
    ASSERT_EQ(read_image(path("t.partial.exr"), width, height, rgb), "") << said;
    EXPECT_EQ(width, 48);
}

// Ctrl-C during a camera path's frames: the frame under way is dropped, the finished ones are
// kept whole, exit 130, and the same command goes on from the first unfinished frame. Until
// 2026-12-07 it ended the process at once, with no word of what was kept.
TEST_F(CrexProgressCli, CtrlCStopsASequenceBetweenFramesAndTheSameCommandGoesOn) {
    const std::vector<std::string> args = {"run", "--scene", CREX_SOURCE_DIR "/examples/scenes/corridor/scene.json", "--camera-path",
                                           CREX_SOURCE_DIR "/examples/paths/corridor_walk.json", "--frames", "0..3", "--size", "16x12",
                                           "--spp", "256", "-o", path("w.exr")};
    const std::string err = path("err.txt");
    const pid_t pid = start(args, err);
    ASSERT_GT(pid, 0);
    ASSERT_TRUE(waits_to_say(err, "frame 1/4", 20)) << text_of(err);
    kill(pid, SIGINT);
    const int exit = wait_for(pid, 120);
    const std::string said = text_of(err);
    if (exit == 0) GTEST_SKIP() << "the frames ended before the signal: " << said;
    ASSERT_EQ(exit, 130) << said;
    const size_t at = said.find("crex run: interrupted: ");
    ASSERT_NE(at, std::string::npos) << said;
    const int finished = std::atoi(said.c_str() + at + std::strlen("crex run: interrupted: "));
    ASSERT_GE(finished, 1) << said;
    ASSERT_LT(finished, 4) << said;
    EXPECT_NE(said.find(" of 4 frames finished"), std::string::npos) << said;
    for (int f = 0; f < 4; ++f) EXPECT_EQ(std::filesystem::exists(path(fmt::format("w.{:04d}.exr", f))), f < finished) << f << ": " << said;
    // No temporary file left beside them.
    for (const auto& e : std::filesystem::directory_iterator(path("")))
        EXPECT_TRUE(e.path().extension() == ".exr" || e.path().extension() == ".txt") << e.path();
    // The same command goes on: the finished frames are skipped, the rest rendered.
    std::vector<std::string> again = args;
    again.insert(again.end(), {"--format", "json"});
    auto r = crex_cli(again);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["frames"].size(), 4u);
    for (int f = 0; f < 4; ++f) EXPECT_EQ(j["frames"][f]["skipped"].get<bool>(), f < finished) << f;
}

// Ctrl-C during `crex reference` (hours for a converged one) keeps what every pixel got: the
// same pixels as a reference of that many samples, as NAME.partial.exr with that count in its
// header, which --accumulate goes on from; the file asked for is not made. Until 2026-12-07 the
// process ended at once and every sample was lost.
TEST_F(CrexProgressCli, CtrlCKeepsAReferencesSamplesSoFar) {
    const std::string err = path("err.txt");
    const pid_t pid = start({"reference", "builtin:cornell", "--size", "16x12", "--spp", "1000000", "--progress", "plain", "-o", path("ref.exr")}, err);
    ASSERT_GT(pid, 0);
    ASSERT_TRUE(waits_to_say(err, "M rays/s")) << text_of(err);
    kill(pid, SIGINT);
    ASSERT_EQ(wait_for(pid, 120), 130) << text_of(err);
    const std::string said = text_of(err);
    EXPECT_FALSE(std::filesystem::exists(path("ref.exr")));
    EXPECT_FALSE(std::filesystem::exists(path("ref.exr.key")));
    std::optional<ReferenceImage> partial;
    ASSERT_EQ(read_reference_image(path("ref.partial.exr"), partial), "") << said;
    ASSERT_TRUE(partial.has_value());
    const uint32_t spp = partial->header.spp;
    ASSERT_GT(spp, 0u) << said;
    EXPECT_NE(said.find(fmt::format("{} of the 1000000 samples a pixel", spp)), std::string::npos) << said;
    // The same pixels as a reference of that many samples (summed in other passes: to float precision).
    auto whole = crex_cli({"reference", "builtin:cornell", "--size", "16x12", "--spp", std::to_string(spp), "-q", "-o", path("same.exr")});
    ASSERT_EQ(whole.exit_code, 0) << whole.err;
    std::optional<ReferenceImage> same;
    ASSERT_EQ(read_reference_image(path("same.exr"), same), "");
    ASSERT_TRUE(same.has_value());
    ASSERT_EQ(same->rgb.size(), partial->rgb.size());
    for (size_t i = 0; i < same->rgb.size(); ++i) ASSERT_NEAR(partial->rgb[i], same->rgb[i], 1e-4 * (1 + std::fabs(same->rgb[i]))) << i;
    // --accumulate goes on from it.
    auto more = crex_cli({"reference", "--accumulate", path("ref.partial.exr"), "--spp", "2", "-q"});
    ASSERT_EQ(more.exit_code, 0) << more.err;
    std::optional<ReferenceImage> grown;
    ASSERT_EQ(read_reference_image(path("ref.partial.exr"), grown), "");
    ASSERT_TRUE(grown.has_value());
    EXPECT_EQ(grown->header.spp, spp + 2);
}

TEST_F(CrexProgressCli, ProgressNoneAndShortRendersSayNothingOffATerminal) {
    for (const char* mode : {"none", "plain", "auto"}) {
        auto r = crex_cli({"run", "--scene", "builtin:cornell", "--size", "16x16", "--spp", "1", "-o", path("y.png"), "--progress", mode});
        EXPECT_EQ(r.exit_code, 0) << r.err;
        EXPECT_EQ(r.err.find("M rays/s"), std::string::npos) << mode << ": " << r.err;
        EXPECT_EQ(r.err.find("crex: "), std::string::npos) << mode << ": " << r.err;  // no plain progress line either
    }
    auto bad = crex_cli({"run", "--scene", "builtin:cornell", "--progress", "loud"});
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.err.find("--progress"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace crex
