/// \file data_table.h
/// What a DataTable (scene.h) means: a number at any point of its grid's space, interpolated
/// linearly along each dimension between the two grid points around it (RADIANCE's data
/// files and pictures). Beyond the grid the line through the last two points goes on for one
/// more step, then falls off harmonically towards zero, as RADIANCE has it, so a table's
/// value never runs away however far a coordinate strays.
#pragma once

#include <string>

#include "runtime/scene/scene.h"

namespace crex {

/// The value at `point` (one coordinate per axis). The table must be well formed
/// (data_table_problem() empty).
double data_value(const DataTable& table, const double* point);

/// Why `table` cannot be used ("" when it can): no axes, an axis of fewer than two points,
/// uneven points not monotonic, a zero span, or the wrong number of values.
std::string data_table_problem(const DataTable& table);

}  // namespace crex
