/// \file row_bands.h
/// Distributed rendering (issue 19): which contiguous band of rows each process renders in a
/// stage. A split is the bands' row bounds, `bands + 1` of them from 0 to the image's height:
/// band b is rows [bounds[b], bounds[b + 1]). Every process computes the split of a stage from
/// data they all hold alike (the film after an exchange of rows, the maps of guidance), so the
/// splits agree without a message.
#pragma once

#include <cstdint>
#include <vector>

#include "runtime/driver/sample_passes.h"

namespace crex {

/// Band b of `bands` starts at row b height / bands, rounded to the nearest row (halves down):
/// for a stage nothing is known about yet (the preview, a plain crex).
std::vector<int> equal_row_bands(int height, int bands);

/// The camera samples `ranges` asks for in each row (a stage's cost, as balancing counts it).
std::vector<uint64_t> samples_per_row(const SampleRanges& ranges, int width, int height);

/// Bands carrying about the same cost each, `row_cost` a row's (one entry per row): band b
/// starts at the row where the cost of the rows before it is nearest b shares of the total,
/// so each boundary is within half a row's cost of where it would ideally fall. A band has
/// at least one row when there are as many rows as bands. Equal costs, and no cost at all,
/// give equal_row_bands. Integer arithmetic only: the same split on every process.
std::vector<int> balanced_row_bands(const std::vector<uint64_t>& row_cost, int bands);

/// Bands carrying about the same number of the camera samples `ranges` asks for.
std::vector<int> balanced_row_bands(const SampleRanges& ranges, int width, int height, int bands);

}  // namespace crex
