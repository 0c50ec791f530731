#include "runtime/scene/gltf/gltf_materials.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include "runtime/scene/material.h"

namespace crex::gltf {
namespace {

using tinygltf::Value;

double number(const Value& object, const char* key, double fallback) {
    if (!object.IsObject() || !object.Has(key)) return fallback;
    const Value& v = object.Get(key);
    const double x = v.IsNumber() ? v.GetNumberAsDouble() : fallback;
    return std::isfinite(x) ? x : fallback;
}

std::array<double, 4> numbers(const Value& object, const char* key, std::array<double, 4> fallback) {
    if (!object.IsObject() || !object.Has(key) || !object.Get(key).IsArray()) return fallback;
    const Value& a = object.Get(key);
    for (int i = 0; i < static_cast<int>(std::min<size_t>(a.ArrayLen(), 4)); ++i)
        if (a.Get(i).IsNumber() && std::isfinite(a.Get(i).GetNumberAsDouble())) fallback[static_cast<size_t>(i)] = a.Get(i).GetNumberAsDouble();
    return fallback;
}

double clamp01(double x) { return std::isfinite(x) ? std::clamp(x, 0.0, 1.0) : 0.0; }

TextureWrap wrap_of(int mode) {
    switch (mode) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return TextureWrap::kClamp;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return TextureWrap::kMirror;
    default: return TextureWrap::kRepeat;
    }
}

// Extensions crex renders (the rest are named in a warning).
const std::set<std::string> kMaterialExtensions = {"KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_emissive_strength",
                                                   "KHR_materials_pbrSpecularGlossiness", "KHR_materials_unlit"};

class MaterialConverter {
public:
    MaterialConverter(const Document& doc, std::vector<EmbeddedImage>& images, DiagnosticSink& sink)
        : doc_(doc), images_(images), sink_(sink) {}

    // A textureInfo at `pointer` (its index, texCoord and extensions) as a texture reference.
    std::optional<TextureRef> texture(int index, int tex_coord, const tinygltf::ExtensionMap& ext, const std::string& pointer) {
        if (index < 0) return std::nullopt;
        const auto& m = doc_.model;
        if (static_cast<size_t>(index) >= m.textures.size()) {
            sink_.report("E303", doc_.at(pointer + "/index"), fmt::format("texture {} does not exist", index));
            return std::nullopt;
        }
        const tinygltf::Texture& t = m.textures[static_cast<size_t>(index)];
        int source = t.source;
        for (const char* name : {"EXT_texture_webp", "KHR_texture_basisu", "MSFT_texture_dds"})
            if (source < 0 && t.extensions.count(name)) source = static_cast<int>(number(t.extensions.at(name), "source", -1));
        if (source < 0 || static_cast<size_t>(source) >= m.images.size()) {
            sink_.report("W311", doc_.at(fmt::format("/textures/{}", index)),
                         fmt::format("texture {} has no image crex can use: the material's constant is used", index));
            return std::nullopt;
        }
        TextureRef ref;
        const size_t image = static_cast<size_t>(source);
        if (!doc_.image_files[image].empty()) {
            ref.file = doc_.image_files[image];
            std::error_code ec;
            if (!std::filesystem::is_regular_file(ref.file, ec) && warned_missing_.insert(image).second)
                sink_.report("W310", doc_.at(fmt::format("/images/{}/uri", image)),
                             fmt::format("cannot find the texture '{}': it renders magenta", ref.file));
        } else if (!doc_.image_bytes[image].empty()) {
            ref.image = fmt::format("{}#image{}", doc_.name, image);
            if (embedded_.insert(image).second) images_.push_back({ref.image, doc_.image_mime[image], doc_.image_bytes[image]});
        } else {
            const std::string& problem = doc_.image_problem[image];
            if (warned_missing_.insert(image).second)
                sink_.report("W310", doc_.at(fmt::format("/images/{}{}", image, problem.empty()                ? ""
                                                                          : m.images[image].bufferView >= 0 ? "/bufferView"
                                                                                                            : "/uri")),
                             problem.empty() ? fmt::format("image {} holds no data: it renders magenta", image)
                                             : fmt::format("image {} cannot be read ({}): it renders magenta", image, problem));
            ref.file = fmt::format("{}#image{}", doc_.name, image);  // not a file: read as missing
        }
        if (t.sampler >= 0 && static_cast<size_t>(t.sampler) < m.samplers.size()) {
            ref.wrap_s = wrap_of(m.samplers[static_cast<size_t>(t.sampler)].wrapS);
            ref.wrap_t = wrap_of(m.samplers[static_cast<size_t>(t.sampler)].wrapT);
            // Magnified texels are what a renderer shows of a pixel-art image; minification
            // filters over the footprint either way.
            if (m.samplers[static_cast<size_t>(t.sampler)].magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST) ref.filter = TextureFilter::kNearest;
        }
        int set = tex_coord;
        if (auto it = ext.find("KHR_texture_transform"); it != ext.end()) {
            const Value& x = it->second;
            const auto offset = numbers(x, "offset", {0, 0, 0, 0}), scale = numbers(x, "scale", {1, 1, 0, 0});
            ref.uv_transform = uv_transform_of(offset[0], offset[1], number(x, "rotation", 0), scale[0], scale[1]);
            set = static_cast<int>(number(x, "texCoord", set));
        }
        sets_.insert(set);
        return ref;
    }

    Material convert(size_t i, const std::string& name) {
        const tinygltf::Material& g = doc_.model.materials[i];
        const std::string at = fmt::format("/materials/{}", i);
        sets_.clear();
        Material m;
        m.name = name;
        m.type = MaterialType::kPlastic;
        const auto& pbr = g.pbrMetallicRoughness;
        std::array<double, 4> base{1, 1, 1, 1};
        for (size_t c = 0; c < std::min<size_t>(pbr.baseColorFactor.size(), 4); ++c) base[c] = pbr.baseColorFactor[c];
        const auto ext = [&](const char* key) -> const Value* {
            auto it = g.extensions.find(key);
            return it == g.extensions.end() ? nullptr : &it->second;
        };
        const double ior = ext("KHR_materials_ior") ? number(*ext("KHR_materials_ior"), "ior", 1.5) : 1.5;
        const double f0 = ior > 0 ? std::pow((ior - 1) / (ior + 1), 2) : 0.04;
        m.color = {clamp01(base[0]), clamp01(base[1]), clamp01(base[2])};
        m.specularity = clamp01(f0);
        m.metallic = clamp01(pbr.metallicFactor);
        m.roughness = std::pow(clamp01(pbr.roughnessFactor), 2);
        if (ior > 0) m.ior = ior;
        MaterialTextures& tex = m.textures;
        tex.color = texture(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, pbr.baseColorTexture.extensions,
                            at + "/pbrMetallicRoughness/baseColorTexture");
        if (tex.color) tex.color->scale = {base[0], base[1], base[2]};
        const auto& mr = pbr.metallicRoughnessTexture;
        if (auto r = texture(mr.index, mr.texCoord, mr.extensions, at + "/pbrMetallicRoughness/metallicRoughnessTexture")) {
            tex.roughness = *r, tex.metallic = *r;
            tex.roughness->channel = 1, tex.roughness->scale = Vec3{1, 1, 1} * pbr.roughnessFactor, tex.roughness->power = 2;
            tex.metallic->channel = 2, tex.metallic->scale = Vec3{1, 1, 1} * pbr.metallicFactor;
            tex.roughness->color_space = tex.metallic->color_space = TextureColorSpace::kLinear;
        }
        if (auto n = texture(g.normalTexture.index, g.normalTexture.texCoord, g.normalTexture.extensions, at + "/normalTexture")) {
            tex.normal = *n;
            tex.normal->scale = Vec3{1, 1, 1} * g.normalTexture.scale;
            tex.normal->color_space = TextureColorSpace::kLinear;
        }
        // Transmission: thin-walled (without KHR_materials_volume), so undeviated: crex's trans
        // with all of its transmission specular.
        if (const Value* t = ext("KHR_materials_transmission")) {
            const double factor = clamp01(number(*t, "transmissionFactor", 0));
            if (factor > 0) {
                m.type = MaterialType::kTrans;
                m.transmissivity = factor;
                m.transmitted_specular = 1;
            }
            if (t->Has("transmissionTexture"))
                sink_.report("W311", doc_.at(at + "/extensions/KHR_materials_transmission/transmissionTexture"),
                             fmt::format("material '{}': a transmission texture is not rendered; its factor {} is", name, factor));
        }
        if (const Value* sg = ext("KHR_materials_pbrSpecularGlossiness")) {
            const auto diffuse = numbers(*sg, "diffuseFactor", {1, 1, 1, 1}), specular = numbers(*sg, "specularFactor", {1, 1, 1, 0});
            m.color = {clamp01(diffuse[0]), clamp01(diffuse[1]), clamp01(diffuse[2])};
            base[3] = diffuse[3];
            m.specularity = clamp01(std::max({specular[0], specular[1], specular[2]}));
            m.metallic = 0;
            m.roughness = std::pow(1 - clamp01(number(*sg, "glossinessFactor", 1)), 2);
            tex.roughness.reset(), tex.metallic.reset();
            if (sg->Has("diffuseTexture")) {
                const Value& d = sg->Get("diffuseTexture");
                tex.color = texture(static_cast<int>(number(d, "index", -1)), static_cast<int>(number(d, "texCoord", 0)), {},
                                    at + "/extensions/KHR_materials_pbrSpecularGlossiness/diffuseTexture");
                if (tex.color) tex.color->scale = {diffuse[0], diffuse[1], diffuse[2]};
            }
            if (sg->Has("specularGlossinessTexture"))
                sink_.report("W311", doc_.at(at + "/extensions/KHR_materials_pbrSpecularGlossiness/specularGlossinessTexture"),
                             fmt::format("material '{}': the specular-glossiness texture is not rendered; its factors are", name));
        }
        const double strength = ext("KHR_materials_emissive_strength") ? number(*ext("KHR_materials_emissive_strength"), "emissiveStrength", 1) : 1;
        Vec3 emissive;
        if (g.emissiveFactor.size() == 3) emissive = Vec3{g.emissiveFactor[0], g.emissiveFactor[1], g.emissiveFactor[2]} * std::max(strength, 0.0);
        emissive = vmax(emissive, Vec3{});
        tex.emission = texture(g.emissiveTexture.index, g.emissiveTexture.texCoord, g.emissiveTexture.extensions, at + "/emissiveTexture");
        if (tex.emission) tex.emission->scale = emissive;
        if (ext("KHR_materials_unlit")) {
            // Unlit: what the base colour says is what is seen.
            tex.emission = tex.color;
            if (!tex.emission) m.emission = m.color;
            m.color = {0, 0, 0};
            tex.color.reset(), tex.roughness.reset(), tex.metallic.reset(), tex.normal.reset();
            m.specularity = 0, m.metallic = 0;
        }
        // Cut-outs: the base colour's alpha.
        if (g.alphaMode == "MASK" || g.alphaMode == "BLEND") {
            m.alpha_mode = g.alphaMode == "MASK" ? AlphaMode::kMask : AlphaMode::kBlend;
            m.alpha_cutoff = clamp01(g.alphaCutoff);
            m.opacity = clamp01(base[3]);
            if (tex.color) {
                tex.opacity = *tex.color;
                tex.opacity->channel = 3, tex.opacity->prefer_alpha = true, tex.opacity->scale = Vec3{1, 1, 1} * base[3], tex.opacity->color_space = TextureColorSpace::kLinear;
            }
        }
        // A constant emission is a sampled emitter (a lamp); a textured one (a screen) glows
        // over a material that still reflects, its texels sampled by direct lighting; an unlit
        // one only shows its image. Material extras {"crex_light": true|false} say which
        // instead (false: a textured emission left to the rays that hit it).
        bool sampled = max_component(emissive) > 0 && !tex.emission && !ext("KHR_materials_unlit");
        m.emission_sampled = !ext("KHR_materials_unlit");
        if (g.extras.IsObject() && g.extras.Has("crex_light") && g.extras.Get("crex_light").IsBool()) {
            sampled = g.extras.Get("crex_light").Get<bool>() && max_component(emissive) > 0;
            m.emission_sampled = m.emission_sampled && g.extras.Get("crex_light").Get<bool>();
        }
        if (!sampled && max_component(emissive) > 0 && !tex.emission && !ext("KHR_materials_unlit")) m.emission = emissive;
        if (sampled) {
            m.type = MaterialType::kLight;
            m.color = vmin(emissive, Vec3{kMaxRadiance, kMaxRadiance, kMaxRadiance});
            m.textures = MaterialTextures{};
            m.opacity = 1;
        }
        for (const auto& [key, value] : g.extensions)
            if (!kMaterialExtensions.count(key))
                sink_.report("W311", doc_.at(at + "/extensions/" + escape_pointer_token(key)),
                             fmt::format("material '{}': extension {} is not rendered", name, key));
        tex_coord_ = sets_.count(1) ? 1 : 0;
        if (sets_.size() > 1)
            sink_.report("W311", doc_.at(at), fmt::format("material '{}': its textures read TEXCOORD_0 and TEXCOORD_1; crex carries one set per "
                                                          "mesh, so all read TEXCOORD_1", name));
        return m;
    }

    int tex_coord() const { return tex_coord_; }

private:
    const Document& doc_;
    std::vector<EmbeddedImage>& images_;
    DiagnosticSink& sink_;
    std::set<size_t> embedded_, warned_missing_;
    std::set<int> sets_;
    int tex_coord_ = 0;
};

}  // namespace

ConvertedMaterials convert_materials(const Document& doc, const std::string& prefix, std::vector<EmbeddedImage>& images,
                                     DiagnosticSink& sink) {
    ConvertedMaterials out;
    MaterialConverter converter(doc, images, sink);
    std::set<std::string> names;
    for (size_t i = 0; i < doc.model.materials.size(); ++i) {
        const std::string& own = doc.model.materials[i].name;
        std::string name = prefix + "/" + (own.empty() ? fmt::format("material{}", i) : own);
        if (!names.insert(name).second) names.insert(name = fmt::format("{}#{}", name, i));
        out.materials.push_back(converter.convert(i, name));
        out.tex_coord.push_back(converter.tex_coord());
    }
    // glTF's default material: white, metallic 1, roughness 1.
    Material d;
    d.name = prefix + "/default";
    d.type = MaterialType::kPlastic;
    d.color = {1, 1, 1};
    d.specularity = 0.04;
    d.metallic = 1;
    d.roughness = 1;
    out.default_index = out.materials.size();
    out.materials.push_back(d);
    out.tex_coord.push_back(0);
    return out;
}

}  // namespace crex::gltf
