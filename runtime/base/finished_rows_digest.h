/// \file finished_rows_digest.h
/// A digest of a partial image's finished rows: the partial writer (runtime/distributed/
/// partial_rows.h) puts it in the file's header as crex:finished_rows_digest and --resume
/// (runtime/api/resume.h) checks it, so a header naming rows its pixels do not hold (edited, or
/// another image's) is refused instead of resuming into black rows.
#pragma once

#include <string>
#include <vector>

namespace crex {

/// FNV-1a over the float bits of the rows marked in `rows`, as 16 hex digits.
std::string finished_rows_digest(const std::vector<float>& rgb, int width, const std::vector<char>& rows);

}  // namespace crex
