#include "runtime/io/video_file.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "runtime/base/atomic_file.h"
#include "runtime/io/image_io.h"
#include "runtime/base/file_extension.h"

extern char** environ;

namespace crex {
namespace {

// ffmpeg's name for the container of an extension ("" for none it is given).
std::string container(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == ".mp4" ? "mp4" : ext == ".mov" ? "mov" : ext == ".mkv" ? "matroska" : "";
}

// A frame as 8-bit sRGB, as a viewer sees it (as_displayed).
std::vector<unsigned char> display_bytes(const std::vector<float>& rgb, bool ldr, double& exposure) {
    const std::vector<float> d = as_displayed(rgb, ldr, exposure);
    std::vector<unsigned char> out(d.size());
    for (size_t i = 0; i < d.size(); ++i) out[i] = static_cast<unsigned char>(std::lround(255 * std::clamp(static_cast<double>(d[i]), 0.0, 1.0)));
    return out;
}

// Writes all of `bytes` to `fd`; false when the reader has gone (EPIPE) or another error.
bool write_all(int fd, const unsigned char* bytes, size_t n) {
    while (n > 0) {
        const ssize_t k = ::write(fd, bytes, n);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) return false;
        bytes += k, n -= static_cast<size_t>(k);
    }
    return true;
}

std::string encode(const std::string& encoder, const std::string& out, const std::string& format, const std::vector<std::string>& frames,
                   double fps) {
    int width = 0, height = 0;
    double exposure = 0;
    std::vector<float> rgb;
    bool ldr = false;
    if (std::string error = read_image(frames.front(), width, height, rgb, &ldr); !error.empty()) return error;
    const std::string log = out + ".log";
    std::vector<std::string> args = {encoder, "-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgb24",
                                     "-s", fmt::format("{}x{}", width, height), "-r", fmt::format("{:g}", fps), "-i", "-",
                                     "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt", "yuv420p",
                                     "-f", format, out};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    int pipe_fds[2];
    if (::pipe(pipe_fds) != 0) return fmt::format("cannot make a pipe to {}: {}", encoder, std::strerror(errno));
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[0], 0);
    posix_spawn_file_actions_addclose(&actions, pipe_fds[1]);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, encoder.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(pipe_fds[0]);
    if (spawned != 0) {
        ::close(pipe_fds[1]);
        return fmt::format("cannot start {}: {}", encoder, std::strerror(spawned));
    }
    // An encoder that ends early must not end crex with SIGPIPE: its write fails instead.
    struct sigaction ignore {}, saved {};
    ignore.sa_handler = SIG_IGN;
    sigaction(SIGPIPE, &ignore, &saved);
    std::string error;
    for (size_t i = 0; i < frames.size() && error.empty(); ++i) {
        int w = 0, h = 0;
        if (i > 0) {
            if (std::string e = read_image(frames[i], w, h, rgb, &ldr); !e.empty()) {
                error = e;
                break;
            }
            if (w != width || h != height) {
                error = fmt::format("{} is {}x{}, the first frame {}x{}", frames[i], w, h, width, height);
                break;
            }
        }
        const std::vector<unsigned char> bytes = display_bytes(rgb, ldr, exposure);
        if (!write_all(pipe_fds[1], bytes.data(), bytes.size())) error = fmt::format("{} stopped taking frames", encoder);
    }
    ::close(pipe_fds[1]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    sigaction(SIGPIPE, &saved, nullptr);
    std::ifstream said(log);
    std::stringstream text;
    text << said.rdbuf();
    std::error_code ec;
    std::filesystem::remove(log, ec);
    if (error.empty() && !(WIFEXITED(status) && WEXITSTATUS(status) == 0))
        error = fmt::format("{} failed (exit {}){}", encoder, WIFEXITED(status) ? WEXITSTATUS(status) : -1,
                            text.str().empty() ? "" : ": " + text.str().substr(0, 400));
    return error;
}

}  // namespace

std::string find_video_encoder() {
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path ? path : "/usr/bin:/bin");
    for (std::string dir; std::getline(dirs, dir, ':');) {
        const std::filesystem::path candidate = std::filesystem::path(dir.empty() ? "." : dir) / "ffmpeg";
        if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    }
    return "";
}

std::string check_video_path(const std::string& path) {
    if (container(path).empty())
        return fmt::format("'{}': a video is written as .mp4, .mov or .mkv (H.264)", path);
    return "";
}

std::string write_video(const std::string& path, const std::vector<std::string>& frames, double fps) {
    if (frames.empty()) return "no frames to make a video of";
    if (std::string error = check_video_path(path); !error.empty()) return error;
    const std::string encoder = find_video_encoder();
    if (encoder.empty()) return "ffmpeg is not installed (Debian package ffmpeg): no video";
    return write_atomically_via(path, [&](const std::string& temp) { return encode(encoder, temp, container(path), frames, fps); });
}

}  // namespace crex
