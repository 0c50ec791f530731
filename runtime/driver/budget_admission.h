/// \file budget_admission.h
/// Under a time budget, camera samples are scheduled work (issue 15): each pass (one sample
/// index of every pixel) is admitted on the cost per camera sample measured so far, the last
/// one cut to the band of rows that fits, so the last decision lands within a band's error of
/// the budget. The render's first pass always runs: there is always an image. The cost is
/// smoothed over passes (the thesis's continuous profiling): a camera sample and all its rays.
#pragma once

#include <optional>

#include "runtime/driver/sample_passes.h"

namespace crex {

class BudgetAdmission {
public:
    /// `budget_seconds` 0: no budget, everything is admitted.
    explicit BudgetAdmission(double budget_seconds) : budget_(budget_seconds) {}

    bool budgeted() const { return budget_ > 0; }

    /// What of `pass` runs at time `now`: all of it without a budget or when it is the render's
    /// `first` pass; else the rows predicted to fit the time left (nullopt: none).
    std::optional<SamplePass> admit(const SamplePass& pass, const SampleRanges& ranges, int width, double now, bool first) const {
        if (!budgeted() || first) return pass;
        return pass_within(pass, ranges, width, seconds_per_sample_, budget_ - now);
    }

    /// A pass of `samples` camera samples took `seconds`.
    void measured(double seconds, uint64_t samples) {
        const double cost = seconds / static_cast<double>(samples);
        seconds_per_sample_ = seconds_per_sample_ > 0 ? 0.5 * seconds_per_sample_ + 0.5 * cost : cost;
    }

    /// Whether work predicted to take `seconds` more, from `now`, fits.
    bool fits(double now, double seconds) const { return !budgeted() || now + seconds <= budget_; }
    /// Whether the budget is spent at `now`.
    bool spent(double now) const { return budgeted() && now >= budget_; }

private:
    double budget_;
    double seconds_per_sample_ = 0;
};

}  // namespace crex
