#include "runtime/api/sequence_flicker.h"

#include <fmt/format.h>

#include "base/render_text.h"
#include "runtime/io/image_io.h"
#include "runtime/scene/load_scene.h"
#include "runtime/scene/radiance_view.h"

namespace crex {

std::string sequence_flicker(const std::vector<std::string>& files, const std::vector<int64_t>& frame_numbers, const std::string& scene_spec,
                             SequenceFlicker& out) {
    out = {};
    if (files.empty()) return "";
    int width = 0, height = 0;
    ImageMetadata first;
    if (std::string error = read_image_metadata(files.front(), width, height, first); !error.empty()) return error;
    out.scene = scene_spec.empty() ? attribute_text(first, "crex:scene") : scene_spec;
    if (out.scene.empty())
        return fmt::format("{} names no scene (crex:scene): flicker needs the frames of a `crex run --camera-path` (or --flicker-scene)",
                           files.front());
    SceneSources sources;
    DiagnosticSink sink;
    SceneLoadFailure failure;
    std::optional<Scene> scene = load_scene(out.scene, sources, sink, failure);
    if (!scene) return fmt::format("the scene {} does not load: {}", out.scene, failure.message.empty() ? render_text(sink.sorted()) : failure.message);
    const Camera scene_camera = scene->camera;
    const SceneBox box = scene_box(*scene);
    const RenderScene rs(*scene);
    std::optional<FrameGeometry> previous_geometry;
    std::vector<float> previous_image;
    double exposure = 0;  // the first frame's, for all: a changing exposure would count as flicker
    for (size_t i = 0; i < files.size(); ++i) {
        int w = 0, h = 0;
        ImageMetadata metadata;
        std::vector<float> rgb;
        if (std::string error = read_image_metadata(files[i], w, h, metadata); !error.empty()) return error;
        if (std::string error = read_image(files[i], w, h, rgb); !error.empty()) return error;
        const std::string view = attribute_text(metadata, "crex:view");
        if (view.empty()) return fmt::format("{} holds no view (crex:view): it is not a frame of `crex run --camera-path`", files[i]);
        if (w != width || h != height) return fmt::format("{} is {}x{}, the first frame {}x{}", files[i], w, h, width, height);
        const SourceFile view_file(files[i] + " (crex:view)", view);
        DiagnosticSink view_sink;
        Camera camera = scene_camera;
        apply_radiance_view(view_file, view_file_words(view_file), camera, false, view_sink);
        if (view_sink.has_errors()) return render_text(view_sink.sorted());
        if (std::string problem = camera_problem(camera, box); !problem.empty())  // a header can say anything
            return fmt::format("{}: its view (crex:view) puts the camera {}", files[i], problem);
        scene->camera = camera;  // the render scene traces from the scene's camera as it is now
        FrameGeometry geometry = frame_geometry(rs, w, h);
        if (!(exposure > 0)) exposure = display_exposure(rgb);
        std::vector<float> display = to_display(rgb, exposure);
        const bool follows = i > 0 && i < frame_numbers.size() && frame_numbers[i] == frame_numbers[i - 1] + 1;
        out.frames.push_back(follows && previous_geometry
                                 ? frame_flicker(*previous_geometry, previous_image, geometry, display, rs.embree->origin_offset())
                                 : std::nullopt);
        previous_geometry = std::move(geometry);
        previous_image = std::move(display);
    }
    return "";
}

}  // namespace crex
