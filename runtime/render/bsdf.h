/// \file bsdf.h
/// The shading model shared by the bin renderer and the recursive test oracle
/// (spec/crex.md §1): at a hit, which lobes spawn which component rays with which weight
/// (lobe splitting: one ray per lobe, no random lobe choice), what emission a ray sees, and
/// how the non-delta lobes respond to direct light.
///
/// Lobes, with c = colour, s = specularity, t = transmissivity, ts = transmitted specularity,
/// m = metallic (0 unless given; glTF's metallic):
///   plastic, metal, trans  D  diffuse reflection      c(1-s)(1-t)(1-m)      cosine sampled
///                          G  rough specular          ks = (1-m) s k + m c, k = white (plastic,
///                             trans), c (metal) or a specular colour texture's value
///                             (normalised Phong lobe, exponent 2/r^2 - 2, sampled exactly;
///                             with an anisotropy, RADIANCE's anisotropic Ward lobe, its
///                             half vector sampled exactly: weight ks cos_o / (o.h cos_h))
///                          S  ideal specular          ks
///   trans                  D  diffuse transmission    c(1-s) t (1-ts)(1-m)
///                          T  specular transmission   c(1-s) t ts (1-m)      undeviated
///   glass                  R  Fresnel reflection      F;  T refraction (1-F) c; total internal
///                             reflection spawns R only, weight 1
///   dielectric             R  F k;  T (1-F) k, where k = colour^distance of the medium the ray
///                             came through (its colours are per unit length, as RADIANCE's;
///                             vacuum, or the outside medium, on the front side); total
///                             internal reflection R with weight k
///   mirror                 M  c
/// Emission, from the front side only: `light` (within its spotlight cone) on camera rays and
/// rays from delta lobes (direct lighting samples it for the rest); `glow` with radius 0 on
/// every ray, with a positive radius on camera and delta rays and on others that travelled
/// farther than the radius (nearer, direct lighting samples it), with a negative one on camera
/// and delta rays only. A material's `emission` on every ray, both sides. An `illum` surface
/// never shows itself: rays see its alternate material.
#pragma once

#include <array>
#include <optional>

#include "base/components.h"
#include "runtime/base/sampling.h"
#include "runtime/render/function_patterns.h"
#include "runtime/scene/material.h"
#include "runtime/scene/scene.h"

namespace crex {

/// The local geometry of a hit as shading sees it.
struct HitFrame {
    Vec3 position;   ///< local coordinates
    Vec3 geometric;  ///< unit geometric normal as the surface defines it (outward for spheres)
    Vec3 normal;     ///< unit normal on the side the ray came from
    /// The normal lobes are made around, on the same side: `normal`, or the mesh's
    /// interpolated vertex normal and the normal or bump map there (runtime/render/surface.h).
    /// Rays still leave from `normal`'s side, and a lobe that would go below it is not spawned.
    Vec3 shading;
    Vec3 incoming;   ///< unit ray direction
    bool front = true;  ///< the ray hit the side `geometric` points to
    double distance = 0;
    double epsilon = 0;  ///< how far rays leaving here start off the surface (EmbreeScene::epsilon_at)
};

struct Lobe {
    Component component = Component::kD;
    Vec3 direction;
    Vec3 weight;
    bool transmits = false;  ///< leaves on the other side of the surface
    bool delta = false;
    /// T through thin glass or a trans surface: the ray goes on as it came, so shadow rays cross
    /// the surface too and direct lighting brings what lies beyond (shadow_transmittance()).
    bool straight = false;
};

inline constexpr int kMaxLobes = 4;

/// Appends a lobe field by field. Written as `out[n++] = {...}`, the aggregate went through a
/// temporary on the stack whose copy stalled on store forwarding: a third of scatter()'s time.
inline void add_lobe(Lobe* out, int& n, Component component, const Vec3& direction, const Vec3& weight, bool transmits, bool delta,
                     bool straight = false) {
    Lobe& l = out[n++];
    l.component = component;
    l.direction = direction;
    l.weight = weight;
    l.transmits = transmits;
    l.delta = delta;
    l.straight = straight;
}

/// A material prepared for shading: its lobe weights and Phong exponent computed once per
/// scene instead of at every hit.
struct Bsdf {
    const Material* material = nullptr;
    const PatternChain* patterns = nullptr;  ///< an emitter's patterns (runtime/render/function_patterns.h)
    MaterialType type = MaterialType::kVoid;
    Vec3 color;              ///< the colour (textured or not): glass and dielectric transmission, mirror reflectance
    std::optional<Vec3> emission;  ///< a non-emitter's own emission (textured or not)
    Vec3 diffuse;            ///< D reflection (0 unless plastic, metal, trans)
    Vec3 specular;           ///< G or S reflection
    Vec3 diffuse_transmit;   ///< D transmission (trans)
    Vec3 specular_transmit;  ///< T (trans)
    double exponent = 0;     ///< Phong exponent of G (roughness > 0)
    bool anisotropic = false;  ///< G is an anisotropic Ward lobe
    double alpha_u = 0, alpha_v = 0;  ///< its roughness along and across `orientation`
    Vec3 orientation;        ///< world direction of u (projected onto the surface at a hit)
    bool glossy = false;     ///< a G lobe (specular, rough)
    bool mirror_like = false;  ///< an S lobe (specular, smooth)
    bool direct_response = false;  ///< a lobe that direct lighting can reach
    bool emits = false;            ///< light, glow, or an emission of its own
    /// Its emission is sampled by direct lighting here (LightSampler::samples_emission, the
    /// front of the surface): counted where rays hit it by camera rays and rays from delta
    /// lobes only, as a `light`'s.
    bool emission_sampled = false;
    bool lambertian = false;       ///< direct light reaches the D reflection lobe only
    /// Direct light reaches it from the front of f.normal only (no D transmission, no
    /// function transmitting behind): emitters below its horizon need no shadow rays.
    bool reflects_only = false;
    /// trans: its specular transmission is clear (roughness 0: RADIANCE's "pure" transmission),
    /// so shadow rays cross it; a rough one scatters its light, and RADIANCE stops them there.
    bool clear_transmission = false;
    /// RADIANCE's plasfunc, metfunc, transfunc (scene.h's DirectionalFunction): direct light's
    /// response is diffuse parts of their own plus this function of the light's direction,
    /// weighted in front and behind.
    const PatternChain* directional = nullptr;
    /// RADIANCE's prism1, prism2: the T lobe goes where these say (RedirectChains).
    const RedirectChains* redirect = nullptr;
    Vec3 direct_diffuse, direct_diffuse_transmit, directional_reflect, directional_transmit;

    static Bsdf of(const Material& m) { return of(m, constant_values(m)); }
    /// With the material's parameters at a point (its textures' values there).
    static Bsdf of(const Material& m, const MaterialValues& values);
};

/// Fills `out` with the lobes spawned at this hit; returns how many. Random numbers are the
/// hit's own (`random`).
int scatter(const Bsdf& b, const HitFrame& f, const HitRandom& random, std::array<Lobe, kMaxLobes>& out);

/// What a shadow ray crossing this surface along f.incoming keeps: the straight T lobe's weight
/// (thin glass, a trans surface's clear specular transmission; RADIANCE's glass and trans pass
/// shadow rays the same way), zero for every other surface.
Vec3 shadow_transmittance(const Bsdf& b, const HitFrame& f);

/// Mirrors, glass and dielectrics: every lobe they spawn is delta, so a path is followed
/// through them, never shaded there.
inline bool is_delta_material(MaterialType t) {
    return t == MaterialType::kMirror || t == MaterialType::kGlass || t == MaterialType::kDielectric;
}

/// The probability that a single path (a cache's hemisphere ray, a photon) meeting a trans
/// surface passes through its specular transmission: that lobe's share of the surface's lobe
/// weights (0 for other surfaces). The rest of the time the path ends there.
inline double transmission_share(const Bsdf& b) {
    if (b.redirect) return 0;  // a prism's rays are not undeviated: single paths end there
    const double t = max_component(b.specular_transmit);
    if (!(t > 0)) return 0;
    const double rest = max_component(b.diffuse) + max_component(b.diffuse_transmit) + (b.glossy || b.mirror_like ? max_component(b.specular) : 0);
    return t / (t + rest);
}

/// The one lobe a single path follows (the irradiance cache's hemisphere rays, photons):
/// among the first `n`, with probability proportional to the largest component of its
/// weight, by u in [0, 1). Returns its index and sets `probability`; -1 when every weight is
/// 0 (the path is absorbed).
int choose_lobe(const std::array<Lobe, kMaxLobes>& lobes, int n, double u, double& probability);

/// Sum over the non-delta lobes of BRDF x |cos| for light arriving from unit direction `wi`;
/// where `glossy_part` is given, the glossy lobe's share of that sum too (what eval_glossy()
/// would give), so a caller that weighs the two apart evaluates the surface once.
Vec3 eval_direct(const Bsdf& b, const HitFrame& f, const Vec3& wi, bool with_diffuse = true, Vec3* glossy_part = nullptr);
/// eval_direct() without its diffuse terms: what the glossy lobes alone make of light from
/// `wi` (where the irradiance cache answers for the diffuse ones).
inline Vec3 eval_glossy(const Bsdf& b, const HitFrame& f, const Vec3& wi) { return eval_direct(b, f, wi, false); }
/// Whether scatter() draws b's glossy lobe by a density glossy_pdf() gives (Phong's lobe and
/// Ward's; not a RADIANCE function's).
inline bool glossy_pdf_known(const Bsdf& b) { return b.glossy && !b.directional; }
/// The glossy lobe's direction as scatter() draws it from (u1, u2) (where glossy_pdf_known(b)).
Vec3 sample_glossy(const Bsdf& b, const HitFrame& f, double u1, double u2);
/// scatter()'s glossy (G) lobe of b drawn from (u1, u2): its direction and its weight (BRDF x
/// cos / pdf); false where the drawn direction falls below the surface (no lobe). Anisotropic
/// Ward and Phong alike.
bool sample_glossy_lobe(const Bsdf& b, const HitFrame& f, double u1, double u2, Vec3& direction, Vec3& weight);
/// The density per steradian with which scatter() draws the glossy lobe's direction `wi`
/// (where glossy_pdf_known(b)).
double glossy_pdf(const Bsdf& b, const HitFrame& f, const Vec3& wi);

/// Phong exponents below this make a lobe at least as wide as the cosine lobe of a diffuse
/// surface: roughness above about 0.82, a glTF roughness above about 0.9 (crex squares it):
/// plaster, a ceiling, a rug, where every glTF material has a 4 % specular lobe.
inline constexpr double kDiffuseLikeExponent = 1.0;
/// Whether b's glossy lobe is that wide. Under an irradiance cache such a lobe's indirect
/// light is the cache's answer, as the diffuse lobes' is (spawn_children()): RADIANCE folds a
/// specular reflection below its sampling threshold into the ambient the same way (m_normal.c,
/// SP_RBLT). Traced, one ray a sample, it met the bright pools a lamp throws on a ceiling or a
/// floor by chance and left white specks on the walls.
inline bool glossy_like_diffuse(const Bsdf& b) { return b.glossy && !b.anisotropic && !b.directional && b.exponent < kDiffuseLikeExponent; }

/// The ray meeting a surface as patterns see it: along `incoming`, the surface's geometric
/// normal (unflipped), the hit point and distance.
inline PatternRay pattern_ray_at(const HitFrame& f) {
    PatternRay r;
    r.direction = f.incoming;
    r.normal = f.geometric;
    r.point = f.position;
    r.distance = f.distance;
    return r;
}

/// Emission seen by a ray. `camera_or_delta`: a camera ray or a ray from a delta lobe.
Vec3 emitted(const Bsdf& b, const HitFrame& f, bool camera_or_delta, bool camera);

/// Dielectric Fresnel reflectance; `eta` = n_incident / n_transmitted. Returns 1 for total
/// internal reflection.
double fresnel_dielectric(double cos_i, double eta);

/// Phong exponent of a roughness in (0, 1].
double phong_exponent(double roughness);

}  // namespace crex
