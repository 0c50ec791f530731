#include "runtime/report/error_curve.h"

#include <fmt/format.h>

namespace crex {

std::vector<CurvePoint> error_curve(const std::vector<Checkpoint>& checkpoints, const metrics::Image& reference,
                                    const metrics::DisplayView& view, double perr_threshold) {
    std::vector<CurvePoint> out;
    metrics::Image ref_display = metrics::display_view(reference, view);
    for (const auto& c : checkpoints) {
        metrics::Image img{reference.width, reference.height, c.image};
        metrics::Image disp = metrics::display_view(img, view);
        std::vector<float> flip = metrics::flip_map(disp, ref_display);
        out.push_back({c.seconds, c.stage, c.event, c.rays, metrics::rmse(img, reference), metrics::relmse(img, reference),
                       metrics::mean(flip), metrics::perr(flip, perr_threshold), metrics::ssim(disp, ref_display)});
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
