/// \file profile.h
/// The profiler of time-constrained rendering (thesis 5.4, spec/crex.md §3): measured cost per
/// ray of each component (and of camera rays), kept as an exponentially weighted average so it
/// follows changes during a render (e.g. while a cache fills). A profile can be saved and
/// loaded (a profile cache reused across frames of an animation and across runs).
#pragma once

#include <array>
#include <optional>
#include <string>

#include "base/components.h"

namespace crex {

class Profile {
public:
    /// Seconds per ray of component c, if measured or loaded.
    std::optional<double> cost(Component c) const { return cost_[static_cast<size_t>(c)]; }
    std::optional<double> camera_cost() const { return camera_; }

    /// Folds in a measurement of `rays` rays taking `seconds`.
    void record(Component c, uint64_t rays, double seconds) { fold(cost_[static_cast<size_t>(c)], rays, seconds); }
    void record_camera(uint64_t rays, double seconds) { fold(camera_, rays, seconds); }

    /// JSON text of the profile; `load` reads it back. Returns "" on success, else why not.
    std::string to_json_text() const;
    static std::string from_json_text(const std::string& text, Profile& out);

private:
    static void fold(std::optional<double>& slot, uint64_t rays, double seconds) {
        if (rays == 0 || !(seconds >= 0)) return;
        double c = seconds / static_cast<double>(rays);
        slot = slot ? 0.5 * *slot + 0.5 * c : c;  // decay: the latest batches weigh most
    }
    std::array<std::optional<double>, kComponentCount> cost_{};
    std::optional<double> camera_;
};

}  // namespace crex
