#include "compiler/pipeline/resolve.h"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <mutex>
#include <set>
#include <unordered_map>

#include "base/input_file.h"
#include "base/install_paths.h"
#include "compiler/pipeline/parse.h"

namespace crex::pipeline {
namespace {

// Stdlib pipeline files, parsed once per process. Their texts stay alive for diagnostics.
struct StdlibEntry {
    std::unique_ptr<SourceFile> source;
    std::optional<ast::File> file;
    std::vector<Diagnostic> parse_errors;  // said to every caller: a broken base is broken each time
};

const ast::File* stdlib_file_of(const std::string& name, DiagnosticSink& sink) {
    static std::map<std::string, StdlibEntry> cache;
    static std::mutex mutex;
    std::lock_guard<std::mutex> lock(mutex);
    auto it = cache.find(name);
    if (it == cache.end()) {
        StdlibEntry e;
        std::filesystem::path path = std::filesystem::path(stdlib_dir()) / "pipelines" / fmt::format("{}.pipe", name);
        std::string error;
        std::error_code ec;
        // Bounded, and only a regular file ($CREX_STDLIB is the user's to set).
        auto text = std::filesystem::exists(path, ec) ? read_input_file(path.string(), error, kMaxTextInputBytes) : std::nullopt;
        if (text) {
            // Named relative to the stdlib's parent, so plans and messages carry no machine paths.
            e.source = std::make_unique<SourceFile>(fmt::format("stdlib/pipelines/{}.pipe", name), std::move(*text));
            DiagnosticSink parse_sink;
            e.file = parse_pipeline_file(*e.source, parse_sink);
            e.parse_errors = parse_sink.diagnostics();
        }
        it = cache.emplace(name, std::move(e)).first;
    }
    for (const auto& d : it->second.parse_errors) sink.add(d);
    return it->second.file ? &*it->second.file : nullptr;
}

const ast::Pipeline* stdlib_pipeline(const std::string& name, DiagnosticSink& sink) {
    const ast::File* file = stdlib_file_of(name, sink);
    if (!file) return nullptr;
    for (const auto& p : file->pipelines)
        if (p.name == name) return &p;
    return nullptr;
}

// `map_at`: where each map of r.maps is (a pipeline of n maps merged in n^2 by scanning).
void merge(ResolvedPipeline& r, const ast::Pipeline& p, std::unordered_map<std::string, size_t>& map_at) {
    for (const auto& s : p.body) {
        using K = ast::Statement::Kind;
        if (s.kind == K::kSetting) {
            r.top[s.key] = s.values;
            continue;
        }
        if (s.kind != K::kSection) continue;
        for (const auto& inner : s.body) {
            if (s.key == "preselective" || s.key == "selective") {
                ResolvedStage& stage = s.key == "preselective" ? r.preselective : r.selective;
                if (inner.kind == K::kSetting && inner.key == "crex" && !inner.values.empty()) {
                    stage.crex = inner.values[0];
                    stage.crex_by.reset();
                    if (inner.has_by) stage.crex_by = inner.expr;
                } else if (inner.kind == K::kSetting && !inner.values.empty()) {
                    stage.settings[inner.key] = inner.values[0];
                } else if (inner.kind == K::kVary) {
                    const std::optional<double> refine = inner.has_refine ? std::optional(inner.refine.number) : std::nullopt;
                    ResolvedVariable v{inner.key, inner.lo, inner.hi, inner.expr, inner.using_fn, inner.component, refine};
                    bool replaced = false;
                    for (auto& old : r.vary)
                        if (old.varied() == v.varied()) old = v, replaced = true;
                    if (!replaced) r.vary.push_back(v);
                }
            } else if (s.key == "guidance" && inner.kind == K::kDefinition) {
                if (auto [at, fresh] = map_at.try_emplace(inner.key, r.maps.size()); fresh) r.maps.emplace_back(inner.key, inner.expr);
                else r.maps[at->second].second = inner.expr;
            } else if (s.key == "output" && inner.kind == K::kSetting && !inner.values.empty()) {
                r.output[inner.key] = inner.values;
            }
        }
    }
}

}  // namespace

const ast::File* stdlib_file(const std::string& name, DiagnosticSink& sink) { return stdlib_file_of(name, sink); }

std::string stdlib_dir() {
    if (const char* env = std::getenv("CREX_STDLIB")) return env;
    if (std::string installed = installed_path(CREX_STDLIB_INSTALL_DIR); !installed.empty()) return installed;
    return CREX_STDLIB_DIR;
}

const ast::Pipeline* find_base(const ast::File& file, const ast::Pipeline& child, DiagnosticSink& sink) {
    for (const auto& p : file.pipelines) {
        if (&p == &child) break;  // only pipelines above it
        if (p.name == child.base) return &p;
    }
    return stdlib_pipeline(child.base, sink);
}

std::optional<ResolvedPipeline> resolve_pipeline(const ast::File& file, const std::string& name, DiagnosticSink& sink) {
    const ast::Pipeline* top = nullptr;
    for (const auto& p : file.pipelines)
        if (name.empty() || p.name == name) top = &p;
    if (!top) return std::nullopt;
    return resolve_from(file, *top, sink);
}

std::optional<ResolvedPipeline> resolve_from(const ast::File& file, const ast::Pipeline& start, DiagnosticSink& sink) {
    const ast::Pipeline* top = &start;
    // The chain child -> base -> ...; a cycle is E210.
    std::vector<const ast::Pipeline*> chain;
    std::set<std::string> seen;
    for (const ast::Pipeline* p = top; p;) {
        if (!seen.insert(p->name).second) {
            sink.report("E210", p->base_span, fmt::format("'{}' extends itself through its bases", top->name));
            return std::nullopt;
        }
        chain.push_back(p);
        if (p->base.empty()) break;
        const ast::Pipeline* base = find_base(file, *p, sink);
        if (!base) {  // a base's own unknown base (a stdlib file's): plan said "the file holds no pipeline"
            sink.report("E210", p->base_span, fmt::format("'{}' extends '{}', which is neither a stdlib pipeline nor defined above it",
                                                          p->name, p->base));
            return std::nullopt;
        }
        p = base;
    }
    ResolvedPipeline r;
    r.name = top->name;
    for (const auto* p : chain) r.chain.push_back(p->name);
    std::unordered_map<std::string, size_t> map_at;
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) merge(r, **it, map_at);
    return r;
}

}  // namespace crex::pipeline
