#include "runtime/base/atomic_file.h"

#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <random>

namespace crex {
namespace {

std::string temp_path_for(const std::string& path) {
    std::random_device rd;
    std::filesystem::path p(path);
    std::string name = ".";
    name.append(p.filename().string()).append(".tmp").append(std::to_string(rd() % 1000000));
    name.append(p.extension().string());
    return (p.parent_path() / name).string();
}

// A writer's error about the temporary file, said about `path`; and when the file stopped at
// the process's file-size limit (ulimit -f: SIGXFSZ is ignored, so the write failed with
// EFBIG, which image writers do not always pass on), that reason.
std::string in_terms_of(std::string error, const std::string& tmp, const std::string& path) {
    const std::string name = std::filesystem::path(tmp).filename().string();
    for (size_t at = error.find(tmp); at != std::string::npos; at = error.find(tmp, at + path.size())) error.replace(at, tmp.size(), path);
    for (size_t at = error.find(name); at != std::string::npos; at = error.find(name, at + path.size())) error.replace(at, name.size(), path);
    struct rlimit limit {};
    std::error_code ec;
    const auto size = std::filesystem::file_size(tmp, ec);
    if (!ec && ::getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY && size >= limit.rlim_cur &&
        error.find("File too large") == std::string::npos)
        error += " (File too large: it reached the file-size limit of " + std::to_string(static_cast<unsigned long long>(limit.rlim_cur)) +
                 " bytes, ulimit -f)";
    return error;
}

}  // namespace

std::string write_atomically_via(const std::string& path, const std::function<std::string(const std::string&)>& write_to) {
    std::string tmp = temp_path_for(path);
    std::string error = write_to(tmp);
    if (error.empty() && std::rename(tmp.c_str(), path.c_str()) != 0)
        error = "cannot rename into place: " + std::string(std::strerror(errno));
    if (!error.empty()) {
        error = in_terms_of(error, tmp, path);
        std::filesystem::remove(tmp);
    }
    return error;
}

std::string write_file_atomically(const std::string& path, const std::string& bytes) {
    return write_atomically_via(path, [&](const std::string& tmp) -> std::string {
        int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
        if (fd < 0) return "cannot create " + tmp + ": " + std::strerror(errno);
        size_t done = 0;
        while (done < bytes.size()) {
            ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                std::string e = std::strerror(errno);
                ::close(fd);
                return "write failed: " + e;
            }
            done += static_cast<size_t>(n);
        }
        if (::fsync(fd) != 0 || ::close(fd) != 0) return "cannot flush: " + std::string(std::strerror(errno));
        return "";
    });
}

}  // namespace crex
