/// \file run_pictures.h
/// `crex run --maps DIR`: every map a run computed as a grey PNG (0 black, 1 white), the
/// preview, and pictures of what each pixel received (camera samples, rays of every kind,
/// how many components), as viridis heat maps with their raw counts in an EXR beside them.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "runtime/render/film.h"
#include "stdlib/guidance/raster.h"

namespace crex {

struct PictureSummary {
    std::vector<std::string> written;
    /// Heat pictures among `written`: path -> the value the ramp's end stands for, and its unit.
    std::map<std::string, std::pair<double, std::string>> heat_scale;
    double max_rays_per_pixel = 0, mean_rays_per_pixel = 0;
};

/// Writes into `dir` (created); returns "" or the first error (files already written stay).
std::string write_run_pictures(const std::string& dir, const Film& film, const std::vector<float>* preview,
                               const std::vector<std::pair<std::string, guidance::Raster>>& maps, PictureSummary& summary);

}  // namespace crex
