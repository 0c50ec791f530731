/// \file scene_builder.h
/// Expanded RADIANCE primitives -> crex's scene model, with RADIANCE's rules for names: a
/// modifier is the most recent definition of its name before the primitive that uses it (a
/// later definition applies only to what follows), `alias` copies a definition (with
/// `inherit` or another modifier), and `void` as a surface's modifier makes it invisible.
///
/// Modifiers are converted when a surface first uses them, so a file may define types crex
/// does not render as long as no surface needs them (as RADIANCE only complains about what it
/// uses); every refusal names the type, where it is defined and the surface that needs it.
///
/// Also reads crex's own `#@crex` comments:
///   #@crex view -vp ...                       the camera (RADIANCE view options)
///   #@crex tag name=N [task=0..3] [distractor=true|false] [scope]
/// where scope says which surfaces get the tag: nothing (the next surface, or everything the
/// next `!` command makes), `begin` (every surface up to `#@crex tag end`), `object=NAME`
/// (surfaces named NAME or NAME.* - what `xform -n NAME` makes), `prefix=TEXT` (names starting
/// with TEXT) or `modifier=NAME` (surfaces written with that modifier).
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "base/diagnostic.h"
#include "runtime/scene/radiance/expand.h"
#include "runtime/scene/radiance/transform.h"
#include "runtime/scene/scene.h"

namespace crex::radiance {

struct CompiledMesh;
struct BinaryObject;

class SceneBuilder : public PrimitiveConsumer {
public:
    /// `library_dirs`: where function files are looked for after the scene file's directory.
    SceneBuilder(Scene& scene, std::vector<std::string> library_dirs, DiagnosticSink& sink)
        : scene_(scene), sink_(sink), library_dirs_(std::move(library_dirs)) {}

    void primitive(Primitive p) override;
    void directive(const Directive& d) override;
    void command_begins(const SourceSpan& command) override;
    void command_ends() override;

    /// Applies the tag rules (object=, prefix=, modifier=); reports tags that tagged nothing.
    void finish();

    /// Where each shape of the scene was written (for later diagnostics).
    const std::vector<SourceSpan>& shape_spans() const { return shape_spans_; }
    /// True when a `#@crex view` line set the camera.
    bool view_seen() const { return view_seen_; }

    struct Definition;

private:
    using DefPtr = std::shared_ptr<Definition>;

    void define(Primitive p);
    void alias(Primitive p);
    void surface(Primitive p);
    /// A compiled mesh (mesh_builder.cpp).
    void mesh(const Primitive& p, const std::optional<Tag>& tag);
    /// An octree's scene placed by its transform (instance_builder.cpp).
    void instance(const Primitive& p, const std::optional<Tag>& tag);
    /// A binary object (a compiled mesh's material, an octree's object) as a primitive written
    /// where `placed` names its file.
    /// RADIANCE's smoothed triangles (obj2rad, oconv'd meshes): a `texfunc` over tmesh.cal's
    /// dx dy dz with 10 real arguments gives a triangle normals interpolated across it; true
    /// when `texture` is one, with the normal at each of `vertices` in `normals` (empty after a
    /// reported error).
    bool mesh_normals(const Definition& texture, const Primitive& user, const std::vector<Vec3>& vertices, std::vector<Vec3>& normals);
    static Primitive from_binary(const BinaryObject& o, const std::string& modifier, const Primitive& placed);
    /// A surface bounding a mist (mist_builder.cpp): never rendered; finish_mists() makes a
    /// mist with coefficients the scene's medium when its surfaces are an axis-aligned box.
    void mist_surface(const DefPtr& d, const Primitive& p);
    void finish_mists();
    struct MistBoundary {
        DefPtr def;
        Primitive first;  ///< its first surface (where errors point)
        std::vector<std::vector<Vec3>> polygons;
        bool other = false;  ///< a surface other than a polygon
    };
    std::vector<MistBoundary> mists_;
    void distant_light(const Primitive& p, const Material& m, const std::optional<SkyModel>& sky);
    std::optional<SkyModel> sky_of(const Definition& pattern, const Primitive& user);
    /// The crex material of `d` (converted once); nullopt after a reported error; "" when the
    /// surfaces it modifies are invisible.
    std::optional<std::string> material_of(const DefPtr& d, const Primitive& user);
    std::optional<Material> convert(const Definition& d, const Primitive& user);
    std::optional<std::string> alternate_of(const Definition& d, const Primitive& user);
    bool orientation(const Definition& d, Vec3& out);
    std::optional<Transform> function_transform(const Primitive& p, size_t first);
    // Patterns on emitters (pattern_builder.cpp).
    static bool is_emitter_pattern(const std::string& type);
    /// The text of the function file `file` names ("" for "."): next to the file that names
    /// it, on RAYPATH, else crex's built-in copy; nullopt after a reported error.
    std::optional<std::string> function_file_text(const Word& file, const Primitive& p);
    /// Where the file `name` names is: next to the file it is written in, then on RAYPATH
    /// ("" when neither has it).
    std::string find_named_file(const Word& name) const;
    std::optional<FunctionPattern> pattern_of(const Definition& d);
    /// A text pattern's font and lines (strings from `font_at`: font file, then a text file or
    /// '.' and the words); false after a reported error.
    bool text_of(const Primitive& p, size_t font_at, FunctionPattern& out);
    /// Reads the function file at string `file_at` into `out`, checks the expressions at
    /// `expressions` and the function names at `names`, and the transform from `transform_at`.
    bool complete_functions(const Primitive& p, FunctionPattern& out, size_t file_at, const std::vector<size_t>& expressions,
                            const std::vector<size_t>& names, size_t transform_at);
    /// RADIANCE's BRTDfunc as a trans with SurfaceFunctions; nullopt after a reported error.
    std::optional<Material> brtd_function(const Definition& d, const Primitive& user);
    /// RADIANCE's plasfunc, metfunc, transfunc: a plastic or trans with a DirectionalFunction;
    /// nullopt after a reported error.
    std::optional<Material> directional_function(const Definition& d, const Primitive& user);
    /// RADIANCE's prism1, prism2: a trans with Redirections; nullopt after a reported error.
    std::optional<Material> redirecting(const Definition& d, const Primitive& user);
    /// RADIANCE's mixfunc: its foreground material with a Mixture; nullopt after an error.
    std::optional<Material> mixture(const Definition& d, const Primitive& user);
    /// The material of a mixture's void part (added once): rays pass straight through.
    std::string see_through_material();
    /// The patterns modifying emitter `d`, nearest first; false after a reported refusal.
    bool patterns_of(const Definition& d, const Primitive& user, std::vector<FunctionPattern>& out);
    std::string unique_material_name(const std::string& id);
    DefPtr lookup(const Word& name, const Primitive& user, const char* role);
    void refuse(const Definition& d, const Primitive& user, const std::string& message, const std::string& help = "");
    void refuse(const Definition& d, SourceSpan at, const Primitive& user, const std::string& message, const std::string& help = "");
    Diagnostic& report(const char* code, SourceSpan span, std::string message, const Primitive* via = nullptr);

    struct TagScope {
        Tag tag;
        SourceSpan where;
        size_t surfaces = 0;
    };
    struct TagRule {
        enum class Kind { kObject, kPrefix, kModifier } kind;
        std::string text;
        TagScope scope;
    };
    void read_tag(const std::vector<Word>& words, const Directive& d);
    std::optional<Tag> tag_for_next_surface();

    Scene& scene_;
    DiagnosticSink& sink_;
    std::vector<std::string> library_dirs_;
    std::map<std::string, DefPtr> defs_;  ///< the latest definition of each name
    std::map<std::string, int> material_name_uses_;
    std::vector<SourceSpan> shape_spans_;
    std::vector<std::string> shape_modifiers_;  ///< each shape's modifier as written
    bool view_seen_ = false;

    std::optional<TagScope> pending_tag_;     ///< for the next surface or command
    std::vector<std::optional<TagScope>> command_tags_;  ///< per open command: its tag, if any
    std::optional<TagScope> block_tag_;       ///< `#@crex tag ... begin` .. `end`
    std::vector<TagRule> rules_;
    std::vector<TagScope> finished_scopes_;   ///< for "tagged nothing" warnings
    std::vector<bool> shape_tag_explicit_;
    std::set<std::pair<const SourceFile*, uint32_t>> refused_places_;  ///< instances and meshes reported
    std::map<std::string, std::shared_ptr<const CompiledMesh>> meshes_;  ///< by path, read once
    std::map<std::string, std::optional<std::string>> mesh_materials_;      ///< "path#k" -> crex material
    std::map<std::string, std::shared_ptr<const std::vector<BinaryObject>>> octrees_;  ///< by path, read once
    int instance_depth_ = 0;  ///< instances inside instances being read
    size_t instanced_objects_ = 0;  ///< objects all instances added so far
    size_t smooth_shape_ = SIZE_MAX;  ///< the shape smoothed triangles last went into (they join it)
};

/// A definition as the builder keeps it (RADIANCE resolves modifiers where they are written).
struct SceneBuilder::Definition {
    Primitive p;
    DefPtr modifier;  ///< its modifier when it was defined (nullptr: void)
    DefPtr alternate;  ///< mirror, illum: the alternate material when it was defined
    bool alternate_void = false;
    bool converted = false;
    std::optional<std::string> material;  ///< after conversion: the crex name ("" = invisible)
    std::optional<std::string> unpatterned;  ///< a sky's glow without its pattern (the sky is the source's)
};

}  // namespace crex::radiance
