/// \file transform.h
/// RADIANCE's transforms (the options of xform and of every function file's transform):
/// -t x y z, -rx/-ry/-rz degrees, -s factor, -mx/-my/-mz, and -i count, which repeats the
/// transform written since the previous -i. They apply in the order written. Like xform, a
/// transform keeps its overall scale (negative when it mirrors), which scales radii and
/// tells whether a polygon's vertex order must be reversed to keep its front side.
#pragma once

#include <string>
#include <vector>

#include "runtime/base/vec3.h"

namespace crex::radiance {

class Transform {
public:
    Transform();  ///< the identity

    /// Points and directions, as xform moves them (row vectors: this transform's first
    /// operation applies first).
    Vec3 point(const Vec3& p) const;
    Vec3 vector(const Vec3& v) const;
    /// The scale factor, negative when the transform mirrors.
    double scale() const { return scale_; }
    bool mirrors() const { return scale_ < 0; }
    bool identity() const { return identity_; }

    /// This transform, then `next`.
    Transform then(const Transform& next) const;

    static Transform translate(const Vec3& t);
    static Transform rotate(int axis, double degrees);
    static Transform scaling(double s);
    static Transform mirror(int axis);

private:
    double m_[4][4];
    double scale_ = 1;
    bool identity_ = true;
};

/// The transform options starting at words[first]. Stops at the first word that is not a
/// transform option; `consumed` says how many words were read. Returns false with `error` and
/// the index of the bad word in `bad_word` when an option's numbers are missing or malformed.
bool parse_transform(const std::vector<std::string>& words, size_t first, Transform& out, size_t& consumed, std::string& error,
                     size_t& bad_word);

/// True when `word` starts a transform option (-t, -rx, -ry, -rz, -s, -mx, -my, -mz, -i).
bool is_transform_option(const std::string& word);

}  // namespace crex::radiance
