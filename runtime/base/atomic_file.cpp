#include "runtime/base/atomic_file.h"

#include <fcntl.h>
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

}  // namespace

std::string write_atomically_via(const std::string& path, const std::function<std::string(const std::string&)>& write_to) {
    std::string tmp = temp_path_for(path);
    std::string error = write_to(tmp);
    if (error.empty() && std::rename(tmp.c_str(), path.c_str()) != 0)
        error = "cannot rename into place: " + std::string(std::strerror(errno));
    if (!error.empty()) std::filesystem::remove(tmp);
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
