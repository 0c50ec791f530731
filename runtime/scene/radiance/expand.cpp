#include "runtime/scene/radiance/expand.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "runtime/scene/radiance/command_line.h"
#include "runtime/scene/radiance/generators.h"
#include "runtime/scene/radiance/rif.h"
#include "runtime/scene/radiance/xform.h"

namespace crex::radiance {
namespace {

// Files nested deeper than this read themselves, directly or not.
constexpr int kMaxNesting = 32;
// A scene that expands to more primitives than this is a runaway array, not a model: refuse
// it before it exhausts memory.
constexpr size_t kMaxPrimitives = 4000000;
// The copies one xform command's -a arrays make, together.
constexpr double kMaxCopies = 1e6;

struct Place {
    XformContext context;
    std::string dir;  ///< where commands run and relative names start
    std::shared_ptr<const std::vector<SourceSpan>> via;
    int depth = 0;
};

class Expander {
public:
    Expander(SceneSources& sources, const ExpandOptions& options, PrimitiveConsumer& out, DiagnosticSink& sink)
        : sources_(sources), options_(options), out_(out), sink_(sink) {}

    void file(const SourceFile& f) {
        Place place;
        place.dir = std::filesystem::path(f.name()).parent_path().string();
        items(read_scene_text(f, sink_), place);
    }

private:
    void items(const std::vector<Item>& items, const Place& place) {
        for (const Item& item : items) {
            if (stopped_) return;
            if (const auto* p = std::get_if<Primitive>(&item)) {
                emit(*p, place.context, place.via);
            } else if (const auto* d = std::get_if<Directive>(&item)) {
                out_.directive(*d);
            } else {
                const Command& c = std::get<Command>(item);
                out_.command_begins(c.span);
                command(c, place);
                out_.command_ends();
            }
        }
    }

    void emit(Primitive p, const XformContext& context, const std::shared_ptr<const std::vector<SourceSpan>>& via) {
        if (++emitted_ > kMaxPrimitives) {
            sink_.report("E303", p.span, fmt::format("the scene expands to more than {} primitives (an array too large?)", kMaxPrimitives));
            stopped_ = true;
            return;
        }
        apply_xform(context, p);
        if (via) p.via = via;
        out_.primitive(std::move(p));
    }

    static std::shared_ptr<const std::vector<SourceSpan>> extend(const std::shared_ptr<const std::vector<SourceSpan>>& via,
                                                                 const SourceSpan& command) {
        auto v = std::make_shared<std::vector<SourceSpan>>();
        v->push_back(command);
        if (via) v->insert(v->end(), via->begin(), via->end());
        return v;
    }

    void command(const Command& c, const Place& place) {
        std::vector<CommandWords> stages;
        if (!split_command_line(c, stages, sink_)) return;
        // Stages after the first transform what the first one makes (xform reading its input).
        XformContext downstream;
        for (size_t s = stages.size(); s-- > 1;) {
            const CommandWords& w = stages[s];
            if (w[0].text != "xform") {
                unsupported(w[0], "after a '|'");
                return;
            }
            for (const Word& word : w)
                if (word.text == "-a") {
                    sink_.report("E307", word.span, "an xform -a array after a '|' is not supported: put what comes before the '|' "
                                                    "in a file and make an array of that");
                    return;
                }
            XformContext x;
            std::vector<Word> files;
            if (!xform_options(w, x, files)) return;
            if (!files.empty()) {
                sink_.report("E307", files.front().span, "an xform after a '|' transforms its input; naming files too is not supported");
                return;
            }
            downstream = XformContext::nest(x, downstream);
        }
        Place inner = place;
        inner.context = XformContext::nest(downstream, place.context);
        inner.via = extend(place.via, c.span);
        const CommandWords& first = stages[0];
        const std::string& program = first[0].text;
        if (program == "xform") {
            xform(first, inner, stages.size() > 1);
            return;
        }
        if (is_generator(program)) {
            std::vector<Primitive> made;
            GeneratorFiles files{place.dir, options_.library_dirs, &sources_};
            if (!run_generator(first, files, made, sink_)) return;
            for (Primitive& p : made) {
                if (stopped_) return;
                emit(std::move(p), inner.context, inner.via);
            }
            return;
        }
        unsupported(first[0], "");
    }

    void unsupported(const Word& program, const std::string& where) {
        std::string name = program.text;
        Diagnostic& d = sink_.report("E307", program.span, fmt::format("the command '{}'{} is not supported in a scene file", name,
                                                                       where.empty() ? "" : " " + where));
        if (name == "pkgBSDF" || name == "mkillum" || name == "oconv" || name == "obj2rad" || name == "obj2mesh" || name == "ies2rad")
            d.help = fmt::format("run {} yourself and read its output (crex carries out xform, genbox, genprism, genrev "
                                 "and gensky itself)", name);
        else
            d.help = "crex carries out xform, genbox, genprism, genrev and gensky itself (alone, or piped into xform) "
                     "and runs no other program";
    }

    // xform's options in order: -m -n -c -e -I, then the transform, then the files.
    bool xform_options(const CommandWords& w, XformContext& x, std::vector<Word>& files) {
        size_t i = 1;
        for (; i < w.size(); ++i) {
            const std::string& o = w[i].text;
            if ((o == "-m" || o == "-n") && i + 1 < w.size()) {
                if (o == "-m") {
                    if (!x.modifier) x.modifier = w[i + 1];
                } else {
                    x.prefix = x.prefix.empty() ? w[i + 1].text : x.prefix + "." + w[i + 1].text;
                }
                ++i;
            } else if (o == "-c" || o == "-e") {
                // -c leaves commands for later; they are carried out all the same.
            } else if (o == "-I") {
                x.invert = !x.invert;
            } else if (o == "-f") {
                sink_.report("E307", w[i].span, "xform -f (arguments from a file) is not supported");
                return false;
            } else {
                break;
            }
        }
        const std::vector<std::string> words = texts(w);
        size_t consumed = 0, bad = 0;
        std::string error;
        if (!parse_transform(words, i, x.xf, consumed, error, bad)) {
            sink_.report("E302", w[std::min(bad, w.size() - 1)].span, "xform: " + error);
            return false;
        }
        x.xf_words = XformContext::appended_words(std::vector<std::string>(words.begin() + static_cast<long>(i),
                                                                           words.begin() + static_cast<long>(i + consumed)));
        for (i += consumed; i < w.size(); ++i) {
            if (!w[i].text.empty() && w[i].text[0] == '-') {
                sink_.report("E303", w[i].span, fmt::format("xform: '{}' is not an option here: options come before the "
                                                            "transform, and files after it", w[i].text));
                return false;
            }
            files.push_back(w[i]);
        }
        return true;
    }

    // `xform ...` as the first stage: its -a arrays repeat it; each copy reads its files.
    void xform(const CommandWords& w, const Place& place, bool piped) {
        // Arrays of arrays multiply: their product is the copies made, refused past kMaxCopies
        // (a command of a few nested arrays ran for hours).
        double copies = 1;
        for (size_t i = 1; i + 1 < w.size(); ++i) {
            double n = 0;
            if (w[i].text == "-a" && parse_real(w[i + 1].text, n) && n >= 1) copies *= n;
        }
        for (size_t i = 1; i < w.size(); ++i) {
            if (w[i].text != "-a") continue;
            double n = 0;
            if (i + 1 >= w.size() || !parse_real(w[i + 1].text, n) || n != std::floor(n) || n < 1 || n > kMaxCopies) {
                sink_.report("E303", w[std::min(i + 1, w.size() - 1)].span, "xform -a: expected a count of copies in 1 .. 1000000");
                return;
            }
            if (copies > kMaxCopies) {
                sink_.report("E303", w[i].span, fmt::format("xform: its -a arrays make {:.3g} copies, more than {}", copies, kMaxCopies));
                return;
            }
            // As xform does: copy k replaces "-a n" by "-i k" and is named "<name>.k" (or "a<k>").
            bool named = false;
            for (size_t k = 2; k < w.size(); ++k) named = named || w[k - 1].text == "-n";
            const size_t errors_before = sink_.error_count();
            // A copy that fails (a file that is not there, a bad option) fails in every copy:
            // said once, not a million times.
            for (int k = 0; k < static_cast<int>(n) && !stopped_ && sink_.error_count() == errors_before; ++k) {
                CommandWords copy = w;
                copy[i].text = "-i";
                copy[i + 1].text = std::to_string(k);
                if (named) {
                    for (size_t j = 2; j < copy.size(); ++j)
                        if (w[j - 1].text == "-n") copy[j].text = w[j].text + "." + std::to_string(k);
                } else {
                    copy.insert(copy.begin() + 1, {Word{"-n", w[i].span}, Word{"a" + std::to_string(k), w[i].span}});
                }
                xform(copy, place, piped);
            }
            return;
        }
        XformContext x;
        std::vector<Word> files;
        if (!xform_options(w, x, files)) return;
        if (files.empty()) {
            sink_.report("E301", w[0].span, piped ? "xform first in a pipeline needs files to read"
                                                  : "xform without files would read the standard input, which a scene file's "
                                                    "command does not have");
            return;
        }
        if (place.depth >= kMaxNesting) {
            sink_.report("E301", w[0].span, fmt::format("files nest more than {} deep: does a file read itself?", kMaxNesting));
            stopped_ = true;
            return;
        }
        for (const Word& f : files) {
            if (stopped_) return;
            read_file(f, place, x, "xform: ");
        }
    }

public:
    // A scene file named by a command or a project file, read through `x` (xform's options).
    void read_file(const Word& f, const Place& place, const XformContext& x, const char* who) {
        std::string path = find_file(f.text, place.dir, options_.library_dirs);
        const std::vector<Item>* loaded = path.empty() ? nullptr : load(path);
        if (!loaded) {
            sink_.report("E308", f.span, fmt::format("{}cannot read the scene file '{}'", who, f.text))
                .help = path.empty() ? fmt::format("it is looked for in '{}'{}", place.dir.empty() ? "." : place.dir,
                                                   options_.library_dirs.empty() ? "" : " and the RAYPATH directories")
                                     : "";
            return;
        }
        Place inner;
        inner.context = XformContext::nest(x, place.context);
        inner.dir = std::filesystem::path(path).parent_path().string();
        inner.via = place.via;
        inner.depth = place.depth + 1;
        items(*loaded, inner);
    }

    void project(const RifProject& rif, const SourceFile& file) {
        Place place;
        place.dir = std::filesystem::path(file.name()).parent_path().string();
        for (const RifInput& in : rif.inputs) {
            if (stopped_) return;
            if (in.is_command) {
                out_.command_begins(in.command.span);
                command(in.command, place);
                out_.command_ends();
            } else {
                read_file(in.file, place, XformContext{}, "");
            }
        }
    }

private:

    // A scene file read once (and its words parsed once), however often it is included.
    const std::vector<Item>* load(const std::string& path) {
        std::error_code ec;
        std::string key = std::filesystem::weakly_canonical(path, ec).string();
        if (ec) key = path;
        auto it = files_.find(key);
        if (it != files_.end()) return &it->second;
        std::ifstream in(path, std::ios::binary);
        if (!in) return nullptr;
        std::stringstream text;
        text << in.rdbuf();
        const SourceFile& f = sources_.add(path, text.str());
        return &files_.emplace(key, read_scene_text(f, sink_)).first->second;
    }

    SceneSources& sources_;
    const ExpandOptions& options_;
    PrimitiveConsumer& out_;
    DiagnosticSink& sink_;
    std::map<std::string, std::vector<Item>> files_;
    size_t emitted_ = 0;
    bool stopped_ = false;
};

}  // namespace

void expand_scene(const SourceFile& file, SceneSources& sources, const ExpandOptions& options, PrimitiveConsumer& out,
                  DiagnosticSink& sink) {
    Expander(sources, options, out, sink).file(file);
}

void expand_project(const RifProject& project, const SourceFile& rif, SceneSources& sources, const ExpandOptions& options,
                    PrimitiveConsumer& out, DiagnosticSink& sink) {
    Expander(sources, options, out, sink).project(project, rif);
}

}  // namespace crex::radiance
