/// \file light_tree.h
/// A bounding tree over many emitters (pbrt-v4's BVH light sampler, after Conty and Kulla's
/// "Importance Sampling of Many Lights"): each node bounds its emitters' positions, the
/// directions they face and their power, and a shading point descends from the root choosing a
/// child by an upper estimate of what it brings there (power, distance, the emitters' facing and
/// the surface's horizon). A hall of a hundred ceiling panels then spends its shadow rays on the
/// panels above the point, not on each panel by its share of the power.
///
/// Nodes have up to four children, whose bounds a node holds side by side in single precision:
/// the four estimates of a level are one pass of vector arithmetic, and a descent visits half as
/// many levels as down a binary tree (a ceiling of 12,000 LED triangles: the choice of emitter
/// was over half of the render, one node of two children at a time in double precision).
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
    /// The emitters in the order of the tree's leaves, each leaf's side by side: `weight` below
    /// is given a place in this order (a slot), so that a leaf's emitters can be read from
    /// consecutive memory; emitter_at(slot) is the index into the lights built from.
    size_t slots() const { return order_.size(); }
    uint32_t emitter_at(uint32_t slot) const { return order_[slot]; }

    /// Upper estimate of what the tree's emitters bring to x (`normal`: the unit normal of a
    /// surface that only reflects, or null): the root's importance, in the units of power / distance^2.
    double importance_at(const Vec3& x, const Vec3* normal) const {
        if (nodes_.empty()) return 0.0;
        double w[kWidth];
        importances(top_, x, normal, w);
        return w[0] * power_scale_;
    }

    struct Choice {
        uint32_t index = 0;      ///< into the lights built from
        uint32_t slot = 0;       ///< its place in the leaves' order (emitter_at(slot) == index)
        double probability = 0;  ///< 0: no emitter can light x
        double rescaled = 0;     ///< u's place within the chosen emitter's share, in [0, 1)
    };
    /// An emitter for x by u in [0, 1): down the tree by the children's importance, then, among
    /// the few emitters of the leaf reached, by `weight(slot)`: the emitter in that slot's own
    /// estimate at x, 0 where it cannot light x at all (x behind it, beyond its reach, below the
    /// horizon). Weighing the last few one by one is both cheaper than more levels of cones and
    /// exact.
    template <class Weight>
    Choice choose(const Vec3& x, const Vec3* normal, double u, const Weight& weight) const {
        Choice c;
        if (nodes_.empty()) return c;
        double p = 1;
        uint32_t at = 0;
        for (;;) {
            const Node& n = nodes_[at];
            double w[kWidth], total = 0;
            importances(n, x, normal, w);
            for (int k = 0; k < kWidth; ++k) total += w[k];
            const int k = pick(w, total, u, kWidth);
            if (k < 0) return c;
            p *= w[k] / total;
            if (n.count[k] == 0) {
                at = n.child[k];
                continue;
            }
            double lw[kLeafMax], leaf_total = 0;
            for (uint32_t e = 0; e < n.count[k]; ++e) leaf_total += lw[e] = weight(n.child[k] + e);
            const int e = pick(lw, leaf_total, u, static_cast<int>(n.count[k]));
            if (e < 0) return c;
            const uint32_t slot = n.child[k] + static_cast<uint32_t>(e);
            return {order_[slot], slot, p * (lw[e] / leaf_total), u};
        }
    }

    /// The probability that choose() picks emitter i at x (0 if it never does): the product of
    /// the choices down the path to its leaf and its share there. For tests and for weighing a
    /// hit emitter.
    template <class Weight>
    double probability(uint32_t i, const Vec3& x, const Vec3* normal, const Weight& weight) const {
        if (i >= trails_.size()) return 0;
        double p = 1;
        uint32_t at = 0;
        for (uint64_t trail = trails_[i];; trail >>= 2) {
            const Node& n = nodes_[at];
            double w[kWidth], total = 0;
            importances(n, x, normal, w);
            for (int k = 0; k < kWidth; ++k) total += w[k];
            if (!(total > 0) || !std::isfinite(total)) return 0;
            const int k = static_cast<int>(trail & 3u);
            p *= w[k] / total;
            if (n.count[k] == 0) {
                at = n.child[k];
                continue;
            }
            double leaf_total = 0, mine = 0;
            for (uint32_t e = 0; e < n.count[k]; ++e) {
                const double we = weight(n.child[k] + e);
                leaf_total += we;
                if (order_[n.child[k] + e] == i) mine = we;
            }
            return leaf_total > 0 && std::isfinite(leaf_total) ? p * (mine / leaf_total) : 0;
        }
    }

private:
    static constexpr int kWidth = 4;          ///< children a node has at most
    static constexpr uint32_t kLeafMax = 8;   ///< emitters a leaf holds at most
    /// A node: the bounds of its up to four children, each a group of emitters or a leaf of
    /// them. For importances(): each child's bounding sphere (its box's centre and half
    /// diagonal), the cone of its emitters' normals (axis, cosine and sine of its half angle)
    /// and its power over the whole tree's. A missing child has power 0.
    struct alignas(64) Node {
        float cx[kWidth] = {}, cy[kWidth] = {}, cz[kWidth] = {}, radius[kWidth] = {};
        float ax[kWidth] = {}, ay[kWidth] = {}, az[kWidth] = {};
        float cos_spread[kWidth] = {1, 1, 1, 1}, sin_spread[kWidth] = {}, power[kWidth] = {};
        uint32_t child[kWidth] = {};  ///< a group: its node; a leaf: its first emitter in order_
        uint32_t count[kWidth] = {};  ///< a leaf: its emitters (1 to kLeafMax); 0 for a group or a missing child
    };
    /// A group of emitters' bound as it is built (double precision).
    struct Bound {
        Vec3 lo, hi, axis;
        double cos_spread = 1, power = 0;
        /// Grows to hold `other` as well: box, power and cone of normals.
        void add(const Bound& other);
    };
    /// The importance of each child of n at x (0 for a missing one), upper bounds of what it brings
    /// there in units of the tree's power / distance^2.
    static void importances(const Node& n, const Vec3& x, const Vec3* normal, double w[kWidth]);
    /// Which of the first `count` weights u falls in, by their shares of `total`, skipping those
    /// of weight 0; u becomes its place within that share, in [0, 1). -1 when none weighs.
    static int pick(const double* w, double total, double& u, int count) {
        if (!(total > 0) || !std::isfinite(total)) return -1;
        const double target = u * total;
        double acc = 0;
        int k = 0;
        for (; k + 1 < count && !(target < acc + w[k]); ++k) acc += w[k];
        while (!(w[k] > 0) && k > 0) acc -= w[--k];  // rounding past the last one that weighs
        if (!(w[k] > 0)) return -1;
        u = min_of(max_of((target - acc) / w[k], 0.0), 0x1.fffffffffffffp-1);
        return k;
    }
    Bound build(uint32_t at, size_t begin, size_t end, const std::vector<LightBound>& lights, uint64_t trail, int depth);
    Bound leaf_bound(size_t begin, size_t end, const std::vector<LightBound>& lights, uint64_t trail);
    size_t split(size_t begin, size_t end, const std::vector<LightBound>& lights);
    void set_lane(Node& n, int k, const Bound& b) const;
    std::vector<Node> nodes_;
    Node top_;                      ///< lane 0: the whole tree's bound, for importance_at()
    double power_scale_ = 1;        ///< the whole tree's power: lanes hold powers over it
    std::vector<uint32_t> order_;   ///< the emitters, each leaf's side by side
    std::vector<uint64_t> trails_;  ///< per emitter: the children chosen (2 bits a level, the root's lowest) down to its leaf
};

}  // namespace crex
