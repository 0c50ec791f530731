/// \file light_tree.h
/// A bounding tree over many emitters (pbrt-v4's BVH light sampler, after Conty and Kulla's
/// "Importance Sampling of Many Lights"): each node bounds its emitters' positions, the
/// directions they face and their power, and a shading point descends from the root choosing a
/// child by an upper estimate of what it brings there (power, distance, the emitters' facing and
/// the surface's horizon). A hall of a hundred ceiling panels then spends its shadow rays on the
/// panels above the point, not on each panel by its share of the power.
#pragma once

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
        uint32_t index = 0;      ///< into the lights built from
        double probability = 0;  ///< 0: no emitter can light x
        double rescaled = 0;     ///< u's place within the chosen emitter's share, in [0, 1)
    };
    /// An emitter for x by u in [0, 1): down the tree by the nodes' importance, then, among the
    /// few emitters of the leaf reached, by `weight(i)`: emitter i's own estimate at x, 0 where it
    /// cannot light x at all (x behind it, beyond its reach, below the horizon). Weighing
    /// the last few one by one is both cheaper than more levels of cones and exact.
    template <class Weight>
    Choice choose(const Vec3& x, const Vec3* normal, double u, const Weight& weight) const {
        Choice c;
        if (nodes_.empty()) return c;
        double p = 1;
        uint32_t at = 0;
        while (nodes_[at].count == 0) {
            const uint32_t first = nodes_[at].first;
            const double wa = importance(nodes_[first], x, normal), wb = importance(nodes_[first + 1], x, normal);
            const double total = wa + wb;
            if (!(total > 0) || !std::isfinite(total)) return c;
            const double pa = wa / total;
            if (u < pa) {
                u = pa > 0 ? u / pa : 0;
                p *= pa;
                at = first;
            } else {
                u = pa < 1 ? (u - pa) / (1 - pa) : 0;
                p *= wb / total;  // as probability() has it, to the last bit
                at = first + 1;
            }
            u = std::fmin(std::fmax(u, 0.0), 0x1.fffffffffffffp-1);
        }
        const Node& leaf = nodes_[at];
        double w[kLeafMax], total = 0;
        for (uint32_t k = 0; k < leaf.count; ++k) total += w[k] = weight(order_[leaf.first + k]);
        if (!(total > 0) || !std::isfinite(total)) return c;
        const double target = u * total;
        double acc = 0;
        uint32_t k = 0;
        for (; k + 1 < leaf.count && !(target < acc + w[k]); ++k) acc += w[k];
        while (!(w[k] > 0) && k > 0) acc -= w[--k];  // rounding past the last emitter that can light x
        const double rescaled = w[k] > 0 ? std::fmin(std::fmax((target - acc) / w[k], 0.0), 0x1.fffffffffffffp-1) : 0;
        return {order_[leaf.first + k], p * (w[k] / total), rescaled};
    }

    /// The probability that choose() picks emitter i at x (0 if it never does): the product of
    /// the choices down the path to its leaf and its share there. For tests and for weighing a
    /// hit emitter.
    template <class Weight>
    double probability(uint32_t i, const Vec3& x, const Vec3* normal, const Weight& weight) const {
        if (i >= trails_.size()) return 0;
        double p = 1;
        uint32_t at = 0;
        for (uint64_t trail = trails_[i]; nodes_[at].count == 0; trail >>= 1) {
            const uint32_t first = nodes_[at].first;
            const double wa = importance(nodes_[first], x, normal), wb = importance(nodes_[first + 1], x, normal);
            if (!(wa + wb > 0)) return 0;
            const bool second = trail & 1;
            p *= (second ? wb : wa) / (wa + wb);
            at = first + (second ? 1 : 0);
        }
        const Node& leaf = nodes_[at];
        double total = 0, mine = 0;
        for (uint32_t k = 0; k < leaf.count; ++k) {
            const double w = weight(order_[leaf.first + k]);
            total += w;
            if (order_[leaf.first + k] == i) mine = w;
        }
        return total > 0 && std::isfinite(total) ? p * (mine / total) : 0;
    }

private:
    static constexpr uint32_t kLeafMax = 8;  ///< emitters a leaf holds at most
    struct Node {
        Vec3 lo, hi, axis;
        double cos_spread = 1;
        double power = 0;
        // Made once from the above for importance(): the box's centre and half diagonal (its
        // bounding sphere), and the sine of the normals' spread.
        Vec3 centre;
        double radius = 0, sin_spread = 0;
        uint32_t first = 0;  ///< a leaf: its first emitter in order_; else its first child (the second follows it)
        uint32_t count = 0;  ///< a leaf: its emitters (1 to kLeafMax); 0 for an inner node
    };
    static void finish(Node& n);
    static double importance(const Node& n, const Vec3& x, const Vec3* normal);
    void build(uint32_t at, size_t begin, size_t end, const std::vector<LightBound>& lights, uint64_t trail, int depth);
    std::vector<Node> nodes_;
    std::vector<uint32_t> order_;   ///< the emitters, each leaf's side by side
    std::vector<uint64_t> trails_;  ///< per emitter: the choices (bit d: second child at depth d) down to its leaf
};

}  // namespace crex
