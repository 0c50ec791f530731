/// \file component_subsample.h
/// capict (thesis 7.4): adaptive sub-sampling per component. `vary subsample(X) A .. B by m`
/// gives component X its own adaptive square grid; in the selective stage the rays a camera
/// hit spawns into X are executed only at the grid's corners. Everywhere else X's branch
/// (all light found below such a first-bounce ray) is interpolated from the corners without
/// the material of the hit, as the thesis's Figure 7.4 shows: each corner gives the radiance
/// its branch brought per unit of first-bounce throughput (branch / throughput), the corners'
/// values are interpolated bilinearly, and the pixel's own first-bounce throughput multiplies
/// the result, so texture, albedo and Fresnel edges stay sharp and only incoming light is
/// smoothed. Corners count only where they see the same surface as the pixel (the same
/// shape, a normal within 25 degrees, a distance within 30 %: the pixel probe's), so light is
/// not carried across an object's silhouette or a crease; the grid is split until every pixel
/// has such a corner. Camera rays, direct light at the camera hit and the components not
/// sub-sampled run in every pixel.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "base/components.h"
#include "runtime/pipeline/pixel_probe.h"
#include "runtime/pipeline/subsample.h"
#include "runtime/render/film.h"

namespace crex {

class ComponentSubsampling {
public:
    /// What each pixel centre sees (shape, normal, distance), for which corners a pixel may
    /// take light from. Without it, any corner of its square.
    void set_surfaces(const PixelProbe& probe);
    bool has_surfaces() const { return !surfaces_.shape.empty(); }
    /// Component c's grid from the spacing each pixel asks for. A pixel where the preview (in
    /// `film`) spawned rays into c but no corner of its square on its surface did has nothing
    /// to interpolate from: its square is split until the pixel is a corner.
    void build(Component c, int width, int height, std::vector<double> spacing, const Film& film);
    /// The thesis's recursive step (7.2, 7.4): every square of c's grid whose corners' light
    /// (per unit throughput, luminance) differs by more than `threshold` times their mean is
    /// split once. Returns, per pixel, 1 where the split made a new corner (whose c branch must
    /// now be rendered for the samples it skipped); empty when nothing was split.
    std::vector<uint8_t> refine(Component c, double threshold, const Film& film);
    bool any() const { return mask_ != 0; }
    uint8_t components() const { return mask_; }  ///< bit c: component c is sub-sampled
    const std::optional<SubsampleGrid>& grid(Component c) const { return grids_[static_cast<size_t>(c)]; }

    /// Per pixel, bit c set if component c's first-bounce rays run there (the executor's gate).
    std::vector<uint8_t> first_bounce_runs(size_t pixels) const;

    /// What interpolation changes, per pixel RGB summed over the pixel's samples like the
    /// film's sums: for every sub-sampled component (or only `only`), the interpolated branch
    /// minus what the film holds of it, in the pixels that are not corners of its grid.
    std::vector<double> stand_ins(const Film& film, std::optional<Component> only = std::nullopt) const;
    /// sums += stand_ins(film), when any component is sub-sampled (the driver's ambient buffer).
    void add_stand_ins(const Film& film, std::vector<double>& sums) const;

private:
    bool same_surface(uint32_t p, uint32_t q) const;
    std::array<std::optional<SubsampleGrid>, kComponentCount> grids_;
    std::array<std::vector<double>, kComponentCount> spacing_;  // what each pixel asks for, after splits
    PixelProbe surfaces_;
    uint8_t mask_ = 0;
};

}  // namespace crex
