// One node's binned SAH split for the BVH build (bvh_build.cpp): the build's primitives, the map of
// centroids to bins, the binning, the sweep that picks the cheapest split and the partition that
// applies it. Boxes, centroids and bins are handled three axes at a time in SSE-sized vectors.
#pragma once

#include "ray/bvh_box.hpp"

#include <algorithm>
#include <cfloat>
#include <cstdint>

namespace clvis::detail {

/// One triangle as the build sees it, 32 bytes: its box, with its id in the bits of lane 3 of lo
/// (masked off before any arithmetic; hi's lane 3 is 0). The build reorders these themselves (not
/// indices to them), so every pass reads memory in order.
struct Prim {
    v4f lo, hi;

    /// Uninitialised: the build's array of millions is written once, in parallel, not zeroed first.
    Prim() {}
    Prim(v4f lo_, v4f hi_) : lo(lo_), hi(hi_) {}

    std::uint32_t id() const
    {
        v4i bits = reinterpret_cast<v4i>(lo);
        return std::uint32_t(bits[3]);
    }
    /// The box, lane 3 of both corners 0.
    VBox box() const
    {
        v4i bits = reinterpret_cast<v4i>(lo) & v4i{-1, -1, -1, 0};
        return {reinterpret_cast<v4f>(bits), hi};
    }
};

/// The centroid of a box: the centre, halves first (the sum of two huge finite coordinates
/// would overflow).
inline v4f centroid(const VBox& b) { return b.lo * 0.5f + b.hi * 0.5f; }

/// A range of the primitive array with its bounds and its centroids' bounds.
struct Range {
    std::uint32_t begin = 0, end = 0;
    Box box = Box::none(), cbox = Box::none();
    std::uint32_t count() const { return end - begin; }
};

constexpr int max_bins = 256;

/// Per-axis bins; only the first `bins` of each axis are set up and used (a node's split must not
/// pay for clearing all max_bins).
struct Bins {
    VBox box[3][max_bins];
    std::uint32_t count[3][max_bins];

    /// Uninitialised: set up by reset before use.
    Bins() {}
    explicit Bins(int bins) { reset(bins); }
    void reset(int bins)
    {
        for (int k = 0; k < bins; ++k) // one loop for the three axes: one exit to predict
            for (int a = 0; a < 3; ++a) {
                box[a][k] = VBox::none();
                count[a][k] = 0;
            }
    }
    /// The boxes of bins 0..k and k+1..bins-1 on `axis`: the boxes of the two sides a split after
    /// bin k makes, exactly (min and max of the same boxes as the primitives').
    void sides(int axis, int k, int bins, Box& left, Box& right) const
    {
        VBox l = VBox::none(), r = VBox::none();
        for (int b = 0; b <= k; ++b) l.grow(box[axis][b]);
        for (int b = k + 1; b < bins; ++b) r.grow(box[axis][b]);
        left = l.box();
        right = r.box();
    }
    /// Bins merge by min, max and sums: exact, so the split does not depend on how the range
    /// was cut into parts.
    void merge(const Bins& o, int bins)
    {
        for (int a = 0; a < 3; ++a)
            for (int k = 0; k < bins; ++k) {
                box[a][k].grow(o.box[a][k]);
                count[a][k] += o.count[a][k];
            }
    }
};

/// Maps a centroid coordinate to its bin. In float: the scale comes from the extent in double
/// (finite even for huge coordinates, at most FLT_MAX for tiny ones), and an overflowing product
/// (+inf) clamps to the last bin; no NaN can arise.
struct BinMap {
    bool valid[3];
    int bins;
    v4f lo, scale, last; ///< in lanes 0-2: the centroids' lower corner, bins per unit, bins - 1

    BinMap(const Box& cbox, int bins_) : bins(bins_)
    {
        float s[3];
        for (int a = 0; a < 3; ++a) {
            double extent = double(cbox.hi[a]) - double(cbox.lo[a]);
            valid[a] = extent > 0;
            s[a] = valid[a] ? float(std::min<double>(bins * (1 - 1e-6) / extent, FLT_MAX)) : 0.0f;
        }
        lo = v4f{cbox.lo[0], cbox.lo[1], cbox.lo[2], 0.0f};
        scale = v4f{s[0], s[1], s[2], 0.0f};
        float l = float(bins - 1);
        last = v4f{l, l, l, l};
    }
    /// The bins of centroid c on the three axes: (c - lo) * scale clamped to [0, bins - 1].
    v4i bins3(v4f c) const
    {
        v4f k = (c - lo) * scale;
        v4f zero{0.0f, 0.0f, 0.0f, 0.0f};
        k = k < zero ? zero : k; // std::max(k, 0.0f)
        k = last < k ? last : k; // std::min(k, bins - 1)
        return __builtin_convertvector(k, v4i);
    }
};

/// The cheapest split the bins offer: left of it, bins 0..k on `axis`; axis -1 when none (every
/// centroid in one bin on every axis). cost: areas times counts of both sides.
struct BinSplit {
    int axis = -1, k = 0;
    double cost = 0;
};

/// Bins the centroids of prims [b, e) into `out` (set up for map.bins bins).
void bin_prims(const Prim* prims, std::uint32_t b, std::uint32_t e, const BinMap& map, Bins& out);

/// Sweeps the bins of a range of `n` primitives on each axis; ties go to the lower axis, then
/// the lower bin.
BinSplit sweep_bins(const Bins& bins, const BinMap& map, std::uint32_t n);

/// sweep_bins' answer for a range of two primitives, without binning them: they part on the
/// lowest valid axis whose bins tell them apart, after the lower one's bin, for the sum of their
/// areas (the same bits); axis -1 when no axis does.
BinSplit sweep_pair(const Prim* pair, const BinMap& map);

/// Moves the primitives of `r` whose centroid falls in bins 0..k on `axis` to its front (in
/// place, an order fixed by the input) and sets both halves' ranges and centroid bounds; their
/// boxes are the caller's (the bins' union on each side: Bins::sides).
void partition_prims(Prim* prims, const Range& r, const BinMap& map, int axis, int k, Range& left, Range& right);

/// The range [b, e) of `prims` with its bounds and centroid bounds.
void range_bounds(const Prim* prims, std::uint32_t b, std::uint32_t e, Range& out);

} // namespace clvis::detail
