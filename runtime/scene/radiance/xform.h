/// \file xform.h
/// What xform does to each primitive passing through it: surfaces are moved (radii scaled,
/// polygon vertex order reversed when the transform mirrors, so the front stays in front),
/// renamed with the -n prefix ("prefix.id"), given the -m modifier, turned inside out by -I;
/// materials and patterns keep their names, and those whose string arguments end in a function
/// file get the transform appended there (so a picture or an orientation vector moves with its
/// surfaces); glow radii, spotlight directions and dielectric absorption follow the scale.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "runtime/scene/radiance/scene_text.h"
#include "runtime/scene/radiance/transform.h"

namespace crex::radiance {

struct XformContext {
    Transform xf;
    std::vector<std::string> xf_words;  ///< the transform as written, appended to function transforms
    std::string prefix;                 ///< -n: surfaces become "prefix.id"
    std::optional<Word> modifier;       ///< -m: every surface's new modifier
    bool invert = false;                ///< -I: every surface inside out

    bool identity() const { return xf.identity() && xf_words.empty() && prefix.empty() && !modifier && !invert; }

    /// The words one xform appends to function transforms: its options, after "-i 1" unless
    /// they start with -i (so a function's own repeated group is not extended).
    static std::vector<std::string> appended_words(const std::vector<std::string>& transform_words);
    /// `inner` first, then `outer`: an xform inside a file that another xform reads.
    static XformContext nest(const XformContext& inner, const XformContext& outer);
};

/// Applies `context` to `p` in place. Arguments whose count does not fit the type are left
/// alone (the scene builder reports them where they are written).
void apply_xform(const XformContext& context, Primitive& p);

}  // namespace crex::radiance
