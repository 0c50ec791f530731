/// \file cache_folder.h
/// crex's cache folder, where what can be made again is kept between runs: converged
/// references (`crex reference`, --reference auto) and tiled copies of large textures.
#pragma once

#include <string>

namespace crex {

/// $CREX_CACHE, else $XDG_CACHE_HOME/crex, else ~/.cache/crex (./.cache/crex without a HOME).
std::string crex_cache_folder();

}  // namespace crex
