/// \file light_tree.h
/// A bounding tree over many emitters (pbrt-v4's BVH light sampler, after Conty and Kulla's
/// "Importance Sampling of Many Lights"): each node bounds its emitters' positions, the
/// directions they face and their power, and a shading point descends from the root choosing a
/// child by an upper estimate of what it brings there (power, distance, the emitters' facing and
/// the surface's horizon). A hall of a hundred ceiling panels then spends its shadow rays on the
/// panels above the point, not on each panel by its share of the power.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "runtime/base/vec3.h"

namespace crex {

/// One emitter as the tree sees it.
struct LightBound {
    Vec3 lo, hi;           ///< its points' box
    Vec3 axis;             ///< the unit direction it faces (a one-sided planar emitter)
    double cos_spread = 1; ///< cosine of the half angle of the normals about `axis`: 1 for a flat one, -1 for a ball
    double power = 0;      ///< area x luminance
};

class LightTree {
public:
    LightTree() = default;
    /// The tree over `lights`; a chosen index is into this list.
    explicit LightTree(const std::vector<LightBound>& lights);
    bool empty() const { return nodes_.empty(); }

    /// Upper estimate of what the tree's emitters bring to x (`normal`: the unit normal of a
    /// surface that only reflects, or null): the root's importance, in the units of power / distance^2.
    double importance_at(const Vec3& x, const Vec3* normal) const { return nodes_.empty() ? 0.0 : importance(nodes_[0], x, normal); }

    struct Choice {
        uint32_t index = 0;   ///< into the lights built from
        double probability = 0;  ///< 0: no emitter can light x
        double rescaled = 0;  ///< u's place within the chosen emitter's share, in [0, 1)
    };
    /// An emitter for x by u in [0, 1), descending by importance. `exact(i)` tells whether
    /// emitter i can light x at all (its exact test: x behind it, beyond its reach, below the
    /// horizon): a leaf that cannot has importance 0.
    template <class Exact>
    Choice choose(const Vec3& x, const Vec3* normal, double u, const Exact& exact) const {
        Choice c;
        if (nodes_.empty()) return c;
        double p = 1;
        uint32_t at = 0;
        while (!nodes_[at].leaf) {
            const Node& a = nodes_[nodes_[at].first];
            const Node& b = nodes_[nodes_[at].first + 1];
            const double wa = weigh(a, x, normal, exact), wb = weigh(b, x, normal, exact);
            const double total = wa + wb;
            if (!(total > 0) || !std::isfinite(total)) return c;
            const double pa = wa / total;
            if (u < pa) {
                u = pa > 0 ? u / pa : 0;
                p *= pa;
                at = nodes_[at].first;
            } else {
                u = pa < 1 ? (u - pa) / (1 - pa) : 0;
                p *= wb / total;  // as probability() has it, to the last bit
                at = nodes_[at].first + 1;
            }
            u = std::fmin(std::fmax(u, 0.0), 0x1.fffffffffffffp-1);
        }
        if (!exact(nodes_[at].first)) return c;
        return {nodes_[at].first, p, u};
    }

    /// The probability that choose() picks emitter i at x (0 if it never does): the product of
    /// the choices down the path to its leaf. For tests and for weighing a hit emitter.
    template <class Exact>
    double probability(uint32_t i, const Vec3& x, const Vec3* normal, const Exact& exact) const {
        if (i >= trails_.size() || !exact(i)) return 0;
        double p = 1;
        uint32_t at = 0;
        for (uint64_t trail = trails_[i]; !nodes_[at].leaf; trail >>= 1) {
            const Node& a = nodes_[nodes_[at].first];
            const Node& b = nodes_[nodes_[at].first + 1];
            const double wa = weigh(a, x, normal, exact), wb = weigh(b, x, normal, exact);
            if (!(wa + wb > 0)) return 0;
            const bool second = trail & 1;
            p *= (second ? wb : wa) / (wa + wb);
            at = nodes_[at].first + (second ? 1 : 0);
        }
        return p;
    }

private:
    struct Node {
        Vec3 lo, hi, axis;
        double cos_spread = 1;
        double power = 0;
        // Made once from the above for importance(): the box's centre and half diagonal (its
        // bounding sphere), and the sine of the normals' spread.
        Vec3 centre;
        double radius = 0, sin_spread = 0;
        uint32_t first = 0;  ///< a leaf: its light; else its first child (the second follows it)
        bool leaf = false;
    };
    static void finish(Node& n);
    static double importance(const Node& n, const Vec3& x, const Vec3* normal);
    template <class Exact>
    static double weigh(const Node& n, const Vec3& x, const Vec3* normal, const Exact& exact) {
        return n.leaf && !exact(n.first) ? 0.0 : importance(n, x, normal);
    }
    void build(uint32_t at, std::vector<uint32_t>& order, size_t begin, size_t end, const std::vector<LightBound>& lights, uint64_t trail, int depth);
    std::vector<Node> nodes_;
    std::vector<uint64_t> trails_;  ///< per light: the choices (bit d: second child at depth d) down to its leaf
};

}  // namespace crex
