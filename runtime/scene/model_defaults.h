/// \file model_defaults.h
/// What a model file (OBJ, glTF: formats for one object, not for a lit scene) gets where it
/// says nothing: a camera that frames it, and light when nothing in it lights it.
#pragma once

#include <optional>

#include "base/diagnostic.h"
#include "runtime/scene/scene.h"

namespace crex {

/// A camera that frames the scene's bounds (45-degree vertical field of view, the bounding
/// sphere within it): from +z when the model is flat and faces z (a picture, a glTF test
/// card), else from the front, right and above (direction (0.5, 0.4, 1)), which sees three
/// faces of a box and no flat thing edge-on (a panel in the yz plane was invisible from +z).
void frame_model(Scene& scene);

/// A model file rendered on its own in which direct lighting samples nothing (OBJ has no
/// lights, and most glTF models ship without any: they rendered black with W302) is lit as a
/// model viewer lights it, with W313 in W302's place:
///  - a uniform grey environment of radiance 0.5, the scene's background, which every ray that
///    leaves the scene sees (the camera's behind the model too). A background rather than a
///    sampled sky: a ray leaving an unoccluded point carries exactly its weight, where a sky's
///    light samples fell behind the surface half the time (assimp's 2CylinderEngine, 16 spp:
///    RMSE 0.033 against 0.101, the same mean; measured before wide skies were sampled above
///    the surface, render_scene.h's sample_above);
///  - a key light, a sun 5 degrees wide above, right of and behind the camera, giving a white
///    surface facing it 0.9 more radiance: under the environment alone a convex white model is
///    the background's colour everywhere and cannot be seen.
/// A scene file that names the model (a JSON scene's mesh `file`) lights it as that file says.
std::optional<Scene> light_unlit_model(std::optional<Scene> scene, DiagnosticSink& sink);

/// Places the studio's key light (if the scene has one) above, right of and behind the
/// scene's camera as it is now: after --camera or --view replaced the camera the model was
/// loaded with (from another side the key stayed behind the first camera and lit the model's
/// back). A camera path leaves it where its first frame's camera put it: light that moved
/// between frames would make every record of a carried cache wrong.
void aim_studio_key(Scene& scene);

}  // namespace crex
