/// \file tiled_copy_oiio.h
/// In the image plugin: a tiled, MIP-mapped copy of an image file that has no tiles, made in
/// bounded memory (issue 36's textured walks, and a user's 8K PNG: OpenImageIO reads an image
/// without tiles whole and makes its MIP levels whole, whatever its cache's limit).
#pragma once

#include <functional>
#include <string>

namespace crex::oiio {

/// Writes `target` (a TIFF with 64x64 tiles and every MIP level, as maketx's .tx) from image
/// file `source` (its first subimage, whose pixels must fill its display window), texels as
/// stored: the same pixel type, channels and alpha channel, alpha left unassociated. Level 0 is
/// copied exactly; each level below is the 2x2 box average of the one above (sizes halved and
/// rounded down, at least 1). The source is read once, from the top in bands of 64 rows; each
/// level below is kept in a temporary file beside `target` until it is written: memory holds a
/// band of rows, not the image. False with `error` on failure, and `target` is then not
/// written. `progress` (if set) is called after each band with the fraction of all levels'
/// rows written.
bool write_tiled_copy(const std::string& source, const std::string& target, std::string& error,
                      const std::function<void(double)>& progress = {});

}  // namespace crex::oiio
