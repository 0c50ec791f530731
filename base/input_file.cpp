#include "base/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cerrno>
#include <cstring>

namespace crex {
namespace {

// What a file that is not a regular file is, for "it is ..., not a file".
std::string kind_of(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISFIFO(mode)) return "a named pipe (FIFO)";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

// `size`: the file's, when known (a stream has none until it passes the limit).
std::string too_large(const std::string& path, size_t limit, double size = 0) {
    return size > 0 ? fmt::format("cannot read '{}': it is {}, more than the {} crex reads from one input", path, byte_size_text(size),
                                  byte_size_text(double(limit)))
                    : fmt::format("cannot read '{}': it holds more than the {} crex reads from one input", path, byte_size_text(double(limit)));
}

// Opens `path` for reading without blocking on a FIFO and checks that it is a regular file of
// at most `limit` bytes: the descriptor (and its size in `size`, when given), or -1 with `error` set.
int open_regular(const std::string& path, size_t limit, std::string& error, size_t* size = nullptr) {
    int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        error = fmt::format("cannot read '{}': {}", path, std::strerror(errno));
        return -1;
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        error = fmt::format("cannot read '{}': {}", path, std::strerror(errno));
        ::close(fd);
        return -1;
    }
    if (!S_ISREG(st.st_mode)) {
        error = S_ISDIR(st.st_mode) ? fmt::format("cannot read '{}': it is a directory", path)
                                    : fmt::format("cannot read '{}': it is {}, not a file; give a file (or '-' for standard input "
                                                  "where a command reads it)",
                                                  path, kind_of(st.st_mode));
        ::close(fd);
        return -1;
    }
    if (static_cast<unsigned long long>(st.st_size) > limit) {
        error = too_large(path, limit, double(st.st_size));
        ::close(fd);
        return -1;
    }
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    if (size) *size = static_cast<size_t>(st.st_size);
    return fd;
}

}  // namespace

std::string byte_size_text(double bytes) {
    const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
    int u = 0;
    while (bytes >= 1024 && u < 4) bytes /= 1024, ++u;
    return u == 0 ? fmt::format("{:.0f} bytes", bytes) : fmt::format("{:.3g} {}", bytes, units[u]);
}

std::string check_input_file(const std::string& path, size_t limit) {
    std::string error;
    int fd = open_regular(path, limit, error);
    if (fd >= 0) ::close(fd);
    return error;
}

std::optional<std::string> read_input_file(const std::string& path, std::string& error, size_t limit) {
    const bool stdin_ = path == "-";
    size_t size = 0;
    int fd = stdin_ ? STDIN_FILENO : open_regular(path, limit, error, &size);
    if (fd < 0) return std::nullopt;
    std::string text;
    // Room for the whole file at once: grown by appends, a 100 MB OBJ was copied about twice.
    text.reserve(size);
    char buffer[1 << 16];
    for (;;) {
        ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            error = fmt::format("cannot read '{}': {}", stdin_ ? "<stdin>" : path, std::strerror(errno));
            if (!stdin_) ::close(fd);
            return std::nullopt;
        }
        if (n == 0) break;
        // A file may grow while it is read (or be /proc's, which says 0 bytes): the limit holds.
        if (text.size() + static_cast<size_t>(n) > limit) {
            error = too_large(stdin_ ? "<stdin>" : path, limit);
            if (!stdin_) ::close(fd);
            return std::nullopt;
        }
        text.append(buffer, static_cast<size_t>(n));
    }
    if (!stdin_) ::close(fd);
    return text;
}

}  // namespace crex
