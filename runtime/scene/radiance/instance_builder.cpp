// RADIANCE's `instance` primitive: a frozen octree's scene (oconv -f) placed by its transform.
// Its objects keep their own names among themselves (the octree is a scope of its own: it
// neither sees the including file's materials nor defines any for it); a modifier other than
// void replaces every material inside, as RADIANCE renders it.
#include <fmt/format.h>

#include "runtime/scene/radiance/compiled_mesh.h"
#include "runtime/scene/radiance/primitive_types.h"
#include "runtime/scene/radiance/scene_builder.h"
#include "runtime/scene/radiance/xform.h"

namespace crex::radiance {
namespace {
constexpr int kMaxInstanceDepth = 8;  // an octree holding an instance of itself ends here
// Objects all instances may add together: an xform array of a large octree must end in an
// error, not in all the machine's memory (the expander's own limit is 4 million primitives).
constexpr size_t kMaxInstancedObjects = size_t{1} << 24;
}  // namespace

Primitive SceneBuilder::from_binary(const BinaryObject& o, const std::string& modifier, const Primitive& placed) {
    const SourceSpan at = placed.strings.empty() ? placed.type.span : placed.strings[0].span;
    Primitive q;
    q.modifier = {modifier, at};
    q.type = {o.type, at};
    q.id = {o.name, at};
    if (o.type == "alias") {
        if (!o.strings.empty()) q.alias_of = {o.strings[0], at};
    } else {
        for (const std::string& s : o.strings) q.strings.push_back({s, at});
        q.reals = o.reals;
        q.real_spans.assign(o.reals.size(), at);
    }
    q.span = at;
    q.via = placed.via;
    return q;
}

void SceneBuilder::instance(const Primitive& p, const std::optional<Tag>& tag) {
    if (p.strings.empty()) {
        report("E303", p.type.span, fmt::format("instance '{}' needs its octree file as a string argument", p.id.text), &p);
        return;
    }
    const Word& file = p.strings[0];
    const std::string path = find_named_file(file);
    auto cached = octrees_.find(path);
    if (cached == octrees_.end()) {
        auto objects = std::make_shared<std::vector<BinaryObject>>();
        std::vector<std::string> files;
        std::string error;
        bool ok = !path.empty() && read_octree(path, *objects, files, error);
        std::string help = "it is looked for next to the file that names it, then in the RAYPATH directories";
        if (ok && !files.empty()) {
            ok = false;
            std::string list;
            for (const std::string& f : files) list += (list.empty() ? "" : ", ") + f;
            error = fmt::format("it is not frozen: it names its scene files ({}) instead of holding them", list);
            help = "make it with 'oconv -f', or read those files with '!xform' and the instance's transform";
        }
        if (!ok) {
            // Once per place it is written, not once per copy an xform array makes of it.
            if (refused_places_.insert({file.span.file, file.span.begin}).second)
                report("E308", file.span, fmt::format("instance '{}': cannot read the octree '{}': {}", p.id.text, file.text,
                                                      path.empty() ? "no such file" : error), &p)
                    .help = help;
            return;
        }
        cached = octrees_.emplace(path, std::move(objects)).first;
    }
    const std::vector<BinaryObject>& objects = *cached->second;
    std::optional<Transform> xf = function_transform(p, 1);
    if (!xf) return;
    if (instance_depth_ >= kMaxInstanceDepth) {
        report("E307", p.type.span, fmt::format("instance '{}': instances nest more than {} deep (does the octree hold an instance of "
                                                "itself?)", p.id.text, kMaxInstanceDepth), &p);
        return;
    }
    instanced_objects_ += objects.size();
    if (instanced_objects_ > kMaxInstancedObjects) {
        if (refused_places_.insert({p.type.span.file, p.type.span.begin}).second)
            report("E303", p.type.span, fmt::format("instance '{}': the scene's instances add more than {} objects", p.id.text,
                                                    kMaxInstancedObjects), &p);
        return;
    }
    DefPtr replacement;
    if (p.modifier.text != "void") {
        replacement = lookup(p.modifier, p, "the modifier");
        if (!replacement) return;
    }

    XformContext context;
    context.xf = *xf;
    std::vector<std::string> words;
    for (size_t k = 1; k < p.strings.size(); ++k) words.push_back(p.strings[k].text);
    context.xf_words = XformContext::appended_words(words);
    if (replacement) context.modifier = p.modifier;

    // The octree's own scope; every surface inside gets the instance's tag.
    std::map<std::string, DefPtr> outer = std::move(defs_);
    defs_.clear();
    if (replacement) defs_[p.modifier.text] = replacement;
    command_tags_.push_back(tag ? std::optional<TagScope>(TagScope{*tag, p.type.span, 0}) : std::nullopt);
    ++instance_depth_;
    for (const BinaryObject& o : objects) {
        const PrimitiveTypeInfo* info = find_primitive_type(o.type);
        if (replacement && info && info->kind != PrimitiveKind::kSurface) continue;  // replaced anyway
        Primitive q = from_binary(o, o.modifier >= 0 ? objects[static_cast<size_t>(o.modifier)].name : "void", p);
        apply_xform(context, q);
        primitive(std::move(q));
    }
    --instance_depth_;
    command_tags_.pop_back();
    defs_ = std::move(outer);
}

}  // namespace crex::radiance
