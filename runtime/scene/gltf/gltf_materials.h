/// \file gltf_materials.h
/// glTF materials onto crex's (docs/scene-format.md, "glTF 2.0", has the table): one place
/// that says which glTF lobe becomes which crex parameter, and so (through the census,
/// runtime/scene/material.h) which component bins a glTF material can ever fill:
///
///   glTF                                   crex                                       bins
///   baseColor x (1 - metallic)             colour, metallic (D scaled by 1 - metallic)  D
///   F0 = ((ior - 1) / (ior + 1))^2         specularity (0.04 at ior 1.5)                G / S
///   metallic                               metallic: specular lobe tinted by colour     G / S
///   roughness r (perceptual)               roughness r^2 (0: ideal specular S, else G;   G / S
///                                          a roughness texture is always G)
///   KHR_materials_transmission t           type trans, transmissivity t, all specular    T
///                                          (thin-walled: undeviated)
///   KHR_materials_ior                      F0 above; ior
///   emissive x KHR_materials_emissive_     a constant one: a sampled `light`; a textured -
///     strength                             one: `emission` (seen, not sampled)
///   alphaMode MASK / BLEND, alpha          opacity, alpha_mode, alpha_cutoff (cut-outs)
///   normalTexture (scale)                  normal map                                     -
///   KHR_materials_pbrSpecularGlossiness    colour = diffuse, specularity = max(specular),
///                                          roughness = (1 - glossiness)^2
///   KHR_materials_unlit                    black, emission = base colour                 -
///   occlusionTexture, other extensions     not rendered (a warning names them)
#pragma once

#include <string>
#include <vector>

#include "runtime/scene/gltf/gltf_document.h"
#include "runtime/scene/scene.h"

namespace crex::gltf {

/// Materials converted: one per glTF material, then the glTF default material (white,
/// metallic 1, roughness 1) for primitives without one.
struct ConvertedMaterials {
    std::vector<Material> materials;
    std::vector<int> tex_coord;  ///< per material: the TEXCOORD set its textures read (0 or 1)
    size_t default_index = 0;    ///< the default material's index
};

/// Converts every material of `doc`; embedded images the textures use go to `images`.
ConvertedMaterials convert_materials(const Document& doc, const std::string& prefix, std::vector<EmbeddedImage>& images,
                                     DiagnosticSink& sink);

}  // namespace crex::gltf
