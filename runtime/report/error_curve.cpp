#include "runtime/report/error_curve.h"

#include <fmt/format.h>

#include <memory>

#include "base/check.h"

namespace crex {

CheckpointScorer scorer_against(const metrics::Image& reference, const metrics::DisplayView& view, double perr_threshold) {
    // Shared: a scorer is copied into every recorder of a run (each policy's) without the images.
    auto ref = std::make_shared<const metrics::Image>(reference);
    auto ref_display = std::make_shared<const metrics::Image>(metrics::display_view(reference, view));
    return [ref, ref_display, view, perr_threshold](const std::vector<float>& image) {
        CREX_CHECK_EQ(image.size(), ref->rgb.size());
        const metrics::Image img{ref->width, ref->height, image};
        const metrics::Image disp = metrics::display_view(img, view);
        const std::vector<float> flip = metrics::flip_map(disp, *ref_display);
        return CheckpointScore{metrics::rmse(img, *ref), metrics::relmse(img, *ref), metrics::mean(flip),
                               metrics::perr(flip, perr_threshold), metrics::ssim(disp, *ref_display)};
    };
}

std::vector<CurvePoint> error_curve(const std::vector<Checkpoint>& checkpoints, const metrics::Image& reference,
                                    const metrics::DisplayView& view, double perr_threshold) {
    std::vector<CurvePoint> out;
    CheckpointScorer scorer;  // made at the first checkpoint that still holds its image
    for (const auto& c : checkpoints) {
        if (!c.score && !scorer) scorer = scorer_against(reference, view, perr_threshold);
        const CheckpointScore s = c.score ? *c.score : scorer(c.image);
        out.push_back({c.seconds, c.stage, c.event, c.rays, s.rmse, s.relmse, s.flip, s.perr, s.ssim});
    }
    return out;
}

std::string curve_csv(const std::vector<CurvePoint>& curve) {
    std::string out = "seconds,stage,event,rays,rmse,relmse,flip,perr,ssim\n";
    auto quoted = [](std::string s) {
        std::string q = "\"";
        for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
        return q + "\"";
    };
    for (const auto& p : curve)
        out += fmt::format("{:.6f},{},{},{},{:.8g},{:.8g},{:.8g},{:.6g},{}\n", p.seconds, quoted(p.stage), quoted(p.event), p.rays, p.rmse,
                           p.relmse, p.flip, p.perr, p.ssim ? fmt::format("{:.8g}", *p.ssim) : "");
    return out;
}

}  // namespace crex
