#include "base/install_paths.h"

#include <dlfcn.h>

#include <filesystem>
#include <vector>

namespace crex {
namespace {

namespace fs = std::filesystem;

// The folders of the code running: the executable's, and the shared object's holding this
// function (the Python module, when crex runs inside python3).
std::vector<fs::path> code_folders() {
    std::vector<fs::path> out;
    std::error_code ec;
    if (fs::path exe = fs::canonical("/proc/self/exe", ec); !ec) out.push_back(exe.parent_path());
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&code_folders), &info) && info.dli_fname)
        if (fs::path object = fs::canonical(info.dli_fname, ec); !ec) out.push_back(object.parent_path());
    return out;
}

// `folder` less its trailing `subdir` (both normalised), or "" when it does not end so.
fs::path strip(const fs::path& folder, const fs::path& subdir) {
    fs::path f = folder.lexically_normal(), s = subdir.lexically_normal();
    std::vector<fs::path> fp(f.begin(), f.end()), sp(s.begin(), s.end());
    while (!sp.empty() && sp.back().empty()) sp.pop_back();
    if (sp.empty() || sp.size() >= fp.size() || !std::equal(sp.rbegin(), sp.rend(), fp.rbegin())) return {};
    fs::path prefix;
    for (size_t i = 0; i + sp.size() < fp.size(); ++i) prefix /= fp[i];
    return prefix;
}

}  // namespace

std::string installed_path(const std::string& relative) {
    // Where `cmake --install` puts code that runs (CMakeLists.txt says so).
    const std::vector<fs::path> code_dirs = {CREX_INSTALL_BINDIR, CREX_INSTALL_PYTHONDIR};
    std::error_code ec;
    for (const fs::path& folder : code_folders())
        for (const fs::path& subdir : code_dirs)
            if (fs::path prefix = strip(folder, subdir); !prefix.empty() && fs::exists(prefix / relative, ec))
                return (prefix / relative).string();
    return {};
}

}  // namespace crex
