/// \file function_patterns.h
/// The patterns of emitters (scene.h's FunctionPattern: RADIANCE's luminaire distributions
/// and photographed skies) ready to evaluate while rendering: expressions parsed once,
/// pictures read once. A pattern whose expressions read nothing of the ray but its direction
/// (a sky, most luminaire tables without a flat-source correction) is tabulated once over
/// the sphere of directions, so a lookup is an interpolation; the others are evaluated per
/// ray.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "base/diagnostic.h"
#include "runtime/base/vec3.h"
#include "runtime/scene/scene.h"

namespace crex {

/// The ray that meets an emitter, in the renderer's coordinates.
struct PatternRay {
    Vec3 direction;  ///< unit, along the ray (towards the emitter, or out to a distant source)
    Vec3 normal;     ///< unit, the emitter's front-side normal (a distant source: -direction)
    Vec3 point;      ///< where it meets the emitter (local coordinates: world = local + offset)
    double distance = 0;   ///< how far the ray travelled to it
    bool distant = false;  ///< a distant source: no point (RADIANCE gives P = 0 there)
    double u = 0, v = 0;   ///< a mesh's texture coordinates there (RADIANCE's Lu, Lv)
    Vec3 light;            ///< a directional function's light direction (unit, towards the light)
};

/// One material's patterns, multiplied together.
class PatternChain {
public:
    PatternChain(const std::vector<FunctionPattern>& patterns, const Vec3& origin_offset, std::vector<Diagnostic>& warnings);
    ~PatternChain();
    PatternChain(const PatternChain&) = delete;
    PatternChain& operator=(const PatternChain&) = delete;

    /// The factor for `ray`: finite and >= 0 in every channel (0 where an expression fails,
    /// overflows or is negative: no NaN reaches an image).
    Vec3 value(const PatternRay& ray) const;
    /// Its mean luminance over the directions leaving a surface of normal `n` into its front
    /// side, cosine-weighted (what a power estimate scales by), at `point`.
    double mean_over_hemisphere(const Vec3& n, const Vec3& point) const;
    /// The first pattern's values as its expressions give them (not clamped, never tabulated),
    /// for functions that are no factor (a prism's direction); nullopt where one fails.
    std::optional<Vec3> raw(const PatternRay& ray) const;
    /// A direction in the first pattern's coordinates, in the renderer's (not normalised).
    Vec3 direction_to_world(const Vec3& v) const;

    struct Compiled;

private:
    Vec3 evaluate(const PatternRay& ray) const;
    std::vector<std::unique_ptr<Compiled>> patterns_;
    Vec3 offset_;
    // Direction-only chains: the factor over world directions, (phi, theta) cells at texel
    // centres, bilinear between them.
    int table_w_ = 0, table_h_ = 0;
    std::vector<Vec3> table_;
};

struct Bsdf;

/// A BRTDfunc surface (scene.h's SurfaceFunctions) compiled: its lobes at a hit.
struct SurfaceChains {
    const SurfaceFunctions* functions = nullptr;
    std::unique_ptr<PatternChain> reflection, transmission;
    /// Sets `b`'s lobe weights for the ray meeting the surface (`ray.normal`: its geometric
    /// normal, unflipped, so RADIANCE's Rdot is negative on the back).
    void apply(const PatternRay& ray, Bsdf& b) const;
};

struct Lobe;

/// A prism (scene.h's Redirections) compiled: where the rays meeting it go on.
struct RedirectChains {
    struct Part {
        std::unique_ptr<PatternChain> coefficient, direction;
    };
    std::vector<Part> parts;
    /// Writes a delta T lobe per redirection with a positive coefficient and a direction into
    /// out[n..]; `side`: the unit normal on the side the ray came from. Returns the new n.
    int lobes(const PatternRay& ray, const Vec3& side, Lobe* out, int n, int max) const;
};

/// A mixture (scene.h's Mixture) compiled: which of its two materials a point has.
struct MixtureChain {
    std::unique_ptr<PatternChain> coefficient;
    uint32_t background = 0;  ///< material index
    /// The foreground's share at the ray's hit, in [0, 1].
    double share(const PatternRay& ray) const;
};

/// Every material's emitter patterns, surface functions and mixtures; null where it has none.
class ScenePatterns {
public:
    ScenePatterns(const Scene& scene, const Vec3& origin_offset, std::vector<Diagnostic>& warnings);
    const PatternChain* of(uint32_t material) const { return material < chains_.size() ? chains_[material].get() : nullptr; }
    const PatternChain* of(const Scene& scene, const std::string& material) const;
    const SurfaceChains* surface(uint32_t material) const { return material < surfaces_.size() ? surfaces_[material].get() : nullptr; }
    const MixtureChain* mixture(uint32_t material) const { return material < mixtures_.size() ? mixtures_[material].get() : nullptr; }
    /// A plasfunc, metfunc or transfunc's function of the light's direction.
    const RedirectChains* redirect(uint32_t material) const { return material < redirects_.size() ? redirects_[material].get() : nullptr; }
    const PatternChain* directional(uint32_t material) const {
        return material < directionals_.size() ? directionals_[material].get() : nullptr;
    }

private:
    std::vector<std::unique_ptr<PatternChain>> chains_;
    std::vector<std::unique_ptr<SurfaceChains>> surfaces_;
    std::vector<std::unique_ptr<MixtureChain>> mixtures_;
    std::vector<std::unique_ptr<PatternChain>> directionals_;
    std::vector<std::unique_ptr<RedirectChains>> redirects_;
};

}  // namespace crex
