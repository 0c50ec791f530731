#include "runtime/report/graphviz.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <iostream>
#include <vector>

#include "runtime/base/atomic_file.h"

extern char** environ;

namespace crex {
namespace {

// Runs `dot -T<format> <input> [-o <output>]`; "" or why it failed (its stderr).
std::string run_dot(const std::string& format, const std::string& input, const std::string& output) {
    std::vector<std::string> args = {"dot", "-T" + format, input};
    if (!output.empty()) args.insert(args.end(), {"-o", output});
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    int err[2];
    if (::pipe2(err, O_CLOEXEC) != 0) return std::string("cannot start Graphviz's dot: ") + std::strerror(errno);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, err[1], 2);
    pid_t pid = 0;
    const int spawned = posix_spawnp(&pid, "dot", &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(err[1]);
    if (spawned != 0) {
        ::close(err[0]);
        if (spawned == ENOENT)
            return "drawing a plan as SVG or PNG needs Graphviz's 'dot' program, which is not on PATH (Debian: apt install "
                   "graphviz); --format dot writes the graph as text";
        return std::string("cannot start Graphviz's dot: ") + std::strerror(spawned);
    }
    // dot's input is a file and its output a file or our stdout: only its stderr is read here,
    // to its end, so the two processes cannot wait on each other.
    std::string said;
    char buffer[4096];
    for (ssize_t n; (n = ::read(err[0], buffer, sizeof buffer)) != 0;) {
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) break;
        if (said.size() < 4096) said.append(buffer, static_cast<size_t>(n));
    }
    ::close(err[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
    while (!said.empty() && (said.back() == '\n' || said.back() == ' ')) said.pop_back();
    return "Graphviz's dot failed" + (said.empty() ? std::string() : ": " + said);
}

}  // namespace

std::string draw_graph(const std::string& dot_text, const std::string& format, const std::string& output_path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    std::string input = (fs::temp_directory_path(ec) / "crex-graph-XXXXXX.dot").string();
    const int fd = ::mkstemps(input.data(), 4);
    if (fd < 0) return "cannot make a temporary file for Graphviz: " + std::string(std::strerror(errno));
    ::close(fd);
    std::string error = write_file_atomically(input, dot_text);
    if (output_path.empty()) std::cout.flush();  // what crex said before comes first
    if (error.empty()) {
        error = output_path.empty() ? run_dot(format, input, "")
                                    : write_atomically_via(output_path, [&](const std::string& tmp) { return run_dot(format, input, tmp); });
    }
    fs::remove(input, ec);
    return error;
}

std::string write_plan_files(const std::string& dot_text, const std::string& dir, std::string& svg) {
    svg.clear();
    const std::filesystem::path folder(dir);
    if (std::string error = write_file_atomically((folder / "plan.dot").string(), dot_text); !error.empty()) return error;
    const std::string drawn = (folder / "plan.svg").string();
    if (!draw_graph(dot_text, "svg", drawn).empty()) return "";
    std::ifstream in(drawn, std::ios::binary);
    svg.assign(std::istreambuf_iterator<char>(in), {});
    return "";
}

}  // namespace crex
