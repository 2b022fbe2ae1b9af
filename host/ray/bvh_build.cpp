// Binned SAH BVH build (Wald, "On fast construction of SAH-based bounding volume hierarchies",
// 2007). Near the root the binning of a node is spread over the threads and its two children are
// built as separate tasks on the process's thread pool (runtime/thread_pool.hpp), each into its
// own depth-first array, then spliced in order; a build given the whole pool cuts its top into
// about 16 such tasks, taken by whichever thread is free. Splits depend only on the triangles
// (bins and bounds merge exactly), so the result does not depend on the threads. Where the SAH
// cannot split (every centroid in one point) or the tree grows too deep, an object median split
// takes over, so degenerate scenes terminate quickly. One node's split is bvh_build_split.cpp.
#include "ray/bvh_build.hpp"

#include "ray/bvh_box.hpp"
#include "ray/bvh_build_split.hpp"
#include "ray/bvh_full.hpp"
#include "runtime/thread_pool.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>
#include <thread>

namespace clvis::detail {

namespace {

class Builder {
public:
    /// `task_grain`: 0, or the size down to which ranges become tasks whatever `threads` says
    /// (build_parallel).
    Builder(std::vector<Prim>& prims, const BvhBuildOptions& o, std::uint32_t task_grain)
        : prims_(prims), opt_(o), task_grain_(task_grain)
    {
    }

    /// Builds the subtree of `r` at `depth` (root: 1) into `out`, depth-first; interior nodes name
    /// their right child by its index in `out`. Returns the deepest leaf's depth.
    int build_serial(const Range& r, int depth, std::vector<clvis_bvh_node>& out) const
    {
        std::size_t self = out.size();
        out.push_back(make_node(r.box));
        Range left, right;
        if (!split(r, depth, left, right, 1)) {
            out[self].first = r.begin;
            out[self].count = r.count();
            return depth;
        }
        int d = build_serial(left, depth + 1, out);
        out[self].first = std::uint32_t(out.size());
        return std::max(d, build_serial(right, depth + 1, out));
    }

    /// The same subtree as build_serial, with the two children of each node above `min_parallel`
    /// triangles built on two threads (`threads` shared between them) into separate arrays and
    /// spliced in depth-first order: the same bits as build_serial. With a task grain (a build
    /// that may use the whole pool), every range above the grain hands its right child to the
    /// pool, so whichever thread is free takes it: an uneven split (the bunny's top one is 62:38)
    /// does not leave a thread idle.
    int build_parallel(const Range& r, int depth, unsigned threads, std::vector<clvis_bvh_node>& out) const
    {
        if (threads <= 1 || r.count() < std::max(min_parallel, task_grain_)) return build_serial(r, depth, out);
        std::size_t self = out.size();
        out.push_back(make_node(r.box));
        Range left, right;
        if (!split(r, depth, left, right, threads)) {
            out[self].first = r.begin;
            out[self].count = r.count();
            return depth;
        }
        unsigned threads_right = std::max(1u, unsigned(std::uint64_t(threads) * right.count() / r.count()));
        threads_right = task_grain_ ? threads : std::min(threads_right, threads - 1);
        unsigned threads_left = task_grain_ ? threads : threads - threads_right;
        std::vector<clvis_bvh_node> right_nodes;
        right_nodes.reserve(std::size_t(right.count()) * 2);
        int depth_right = 0;
        TaskGroup group;
        group.run([&] { depth_right = build_parallel(right, depth + 1, threads_right, right_nodes); });
        int depth_left = build_parallel(left, depth + 1, threads_left, out);
        group.wait();
        std::uint32_t offset = std::uint32_t(out.size());
        out[self].first = offset;
        for (clvis_bvh_node node : right_nodes) {
            if (node.count == 0) node.first += offset;
            out.push_back(node);
        }
        return std::max(depth_left, depth_right);
    }

    /// Ranges smaller than this are built on one thread: below, handing a half to a pool thread
    /// costs about what it saves.
    static constexpr std::uint32_t min_parallel = 1024;

    /// Splits `r` into two non-empty halves (returns false for a leaf); `workers` threads bin.
    bool split(const Range& r, int depth, Range& left, Range& right, unsigned workers) const
    {
        std::uint32_t n = r.count();
        if (n <= 1) return false;
        bool centroids_apart = false;
        for (int a = 0; a < 3; ++a) centroids_apart |= r.cbox.hi[a] > r.cbox.lo[a];
        bool must_split = n > std::uint32_t(opt_.max_leaf_size);
        if (opt_.full_leaves) {
            if (!must_split) return false;
            if (n <= full_sweep * std::uint32_t(opt_.max_leaf_size)) {
                split_full(r, left, right);
                return true;
            }
        }
        if (!must_split && leaf_beats_any_split(r)) return false;
        if (!centroids_apart) {
            if (!must_split) return false;
            split_in_order(r, left, right);
            return true;
        }
        if (opt_.split == BvhSplit::Median || depth >= bvh_max_sah_depth) {
            if (!must_split) return false;
            split_median(r, left, right);
            return true;
        }
        // A bin per 8 triangles at most, and at least 2: near the leaves the sweep would cost more
        // than the binning. Finer bins find splits of a barely lower SAH cost (under a percent)
        // for a clearly slower build; the measurements are in the commit messages that set these.
        int bins = int(std::min<std::uint32_t>(std::uint32_t(opt_.sah_bins), std::max<std::uint32_t>(n / 8, 2)));
        BinMap map(r.cbox, bins);
        BinSplit best;
        Bins binned; // set up for `bins` below, except for a pair
        if (n == 2) { // most of a soup's splits: the sweep's answer without the bins
            best = sweep_pair(prims_.data() + r.begin, map);
        } else {
            binned.reset(bins);
            bin(r, map, workers, binned);
            best = sweep_bins(binned, map, n);
        }
        if (best.axis < 0) { // every centroid in one bin on every axis: only rounding apart
            if (!must_split) return false;
            split_median(r, left, right);
            return true;
        }
        double area = r.box.half_area();
        double leaf_cost = area * leaf_test_cost(n);
        double split_cost = traversal_cost * area + best.cost;
        if (!must_split && leaf_cost <= split_cost) return false;
        partition_prims(prims_.data(), r, map, best.axis, best.k, left, right);
        if (n == 2) {
            left.box = prims_[r.begin].box().box();
            right.box = prims_[r.begin + 1].box().box();
        } else {
            binned.sides(best.axis, best.k, bins, left.box, right.box);
        }
        return true;
    }

    /// Cost of one traversal step relative to one triangle test, in the SAH.
    static constexpr double traversal_cost = 1.0;

    /// A leaf's cost in the SAH, in triangle tests: its triangles are tested four at a time
    /// (ray_query.cl's single rays: shared/tri4.h; the packets test 16 rays per triangle), and a
    /// test of four costs about two of one (the triangles' loads, the trust check and the lanes'
    /// answers). Leaves then hold 3.2 triangles on average on the bunny, not 1.8, in 44 % fewer
    /// nodes; measured against the per-triangle cost (docs/architecture.md, issue 37): AO rays
    /// 10-15 % less time for closest and any hit, packets 3-10 % less, random rays through a
    /// soup of large triangles up to 9 % more for closest hits.
    static constexpr std::uint32_t leaf_block = 4;
    static constexpr double leaf_block_cost = 2.0;
    static double leaf_test_cost(std::uint32_t n)
    {
        return leaf_block_cost * double((n + leaf_block - 1) / leaf_block);
    }

private:
    /// True where no split can cost less than the leaf: a split costs at least the node's area
    /// plus each triangle's own (every triangle lies in its side's box), all terms positive, so a
    /// relative margin far above the rounding of either sum keeps the decision the sweep's.
    bool leaf_beats_any_split(const Range& r) const
    {
        double own = 0;
        for (std::uint32_t i = r.begin; i < r.end; ++i) own += prims_[i].box().half_area();
        double area = r.box.half_area();
        return area * leaf_test_cost(r.count()) <= (traversal_cost * area + own) * (1 - 1e-9);
    }

    static clvis_bvh_node make_node(const Box& b)
    {
        clvis_bvh_node n{};
        n.lo_x = b.lo[0]; n.lo_y = b.lo[1]; n.lo_z = b.lo[2];
        n.hi_x = b.hi[0]; n.hi_y = b.hi[1]; n.hi_z = b.hi[2];
        return n;
    }

    /// Bins the centroids of `r` into `out` (set up for map.bins bins).
    void bin(const Range& r, const BinMap& map, unsigned workers, Bins& out) const
    {
        int bins = map.bins;
        std::uint32_t n = r.count();
        unsigned parts = std::min<unsigned>(workers, std::max<std::uint32_t>(1, n / 16384));
        if (parts <= 1) {
            bin_prims(prims_.data(), r.begin, r.end, map, out);
            return;
        }
        std::vector<Bins> partial(parts, Bins(bins));
        parallel_slices(n, parts, [&](unsigned part, std::size_t b, std::size_t e) {
            bin_prims(prims_.data(), r.begin + std::uint32_t(b), r.begin + std::uint32_t(e), map, partial[part]);
        });
        for (unsigned t = 0; t < parts; ++t) out.merge(partial[t], bins);
    }

    /// With full_leaves, ranges of up to this many leaves split by split_full (larger ones by the
    /// binned SAH, as without): a full wide subtree of two levels (16 at width 4; 256 there packed
    /// 10,000 instances 1.4 bytes each tighter, but its sorts doubled the top level's rebuild).
    static constexpr std::uint32_t full_sweep = std::uint32_t(bvh_width * bvh_width);

    /// full_leaves_split (bvh_full.hpp) on `r`.
    void split_full(const Range& r, Range& left, Range& right) const
    {
        auto less = [](int a) {
            return [a](const Prim& x, const Prim& y) {
                float cx = centroid(x.box())[a], cy = centroid(y.box())[a];
                return cx < cy || (cx == cy && x.id() < y.id());
            };
        };
        std::size_t k = full_leaves_split(prims_.begin() + r.begin, prims_.begin() + r.end,
                                          std::size_t(opt_.max_leaf_size), [](const Prim& p) { return p.box().box(); }, less);
        range_bounds(prims_.data(), r.begin, r.begin + std::uint32_t(k), left);
        range_bounds(prims_.data(), r.begin + std::uint32_t(k), r.end, right);
    }

    void split_in_order(const Range& r, Range& left, Range& right) const
    {
        std::uint32_t mid = r.begin + r.count() / 2;
        range_bounds(prims_.data(), r.begin, mid, left);
        range_bounds(prims_.data(), mid, r.end, right);
    }

    void split_median(const Range& r, Range& left, Range& right) const
    {
        int axis = 0;
        double widest = -1;
        for (int a = 0; a < 3; ++a) {
            double e = double(r.cbox.hi[a]) - double(r.cbox.lo[a]);
            if (e > widest) {
                widest = e;
                axis = a;
            }
        }
        std::uint32_t mid = r.begin + r.count() / 2;
        // Ties broken by id: the order, and so the tree, is fully determined.
        std::nth_element(prims_.begin() + r.begin, prims_.begin() + mid, prims_.begin() + r.end,
                         [&](const Prim& x, const Prim& y) {
                             float cx = centroid(x.box())[axis], cy = centroid(y.box())[axis];
                             return cx < cy || (cx == cy && x.id() < y.id());
                         });
        range_bounds(prims_.data(), r.begin, mid, left);
        range_bounds(prims_.data(), mid, r.end, right);
    }

    std::vector<Prim>& prims_;
    BvhBuildOptions opt_;
    std::uint32_t task_grain_;
};

clvis_bvh_tri make_tri(const float* positions, const std::uint32_t* indices, std::uint32_t id)
{
    const float* a = positions + std::size_t(indices[std::size_t(id) * 3]) * 3;
    const float* b = positions + std::size_t(indices[std::size_t(id) * 3 + 1]) * 3;
    const float* c = positions + std::size_t(indices[std::size_t(id) * 3 + 2]) * 3;
    clvis_bvh_tri t{};
    t.v0_x = a[0]; t.v0_y = a[1]; t.v0_z = a[2];
    t.v1_x = b[0]; t.v1_y = b[1]; t.v1_z = b[2];
    t.v2_x = c[0]; t.v2_y = c[1]; t.v2_z = c[2];
    t.id = id;
    return t;
}

/// Sets tris[i] to triangle id_of(i) for every i, on `threads` threads: a gather through the
/// indices, at random where the tree's order is not the mesh's (a soup). Each triangle's indices
/// are fetched ahead of use, and its vertices a little less far ahead, so the misses of several
/// triangles overlap.
template <class IdOf>
void gather_tris(const float* positions, const std::uint32_t* indices, unsigned threads, IdOf id_of,
                 clvis_bvh_tri* tris, std::size_t n)
{
    constexpr std::size_t index_ahead = 16, vertex_ahead = 8;
    unsigned parts = unsigned(std::min<std::size_t>(threads, std::max<std::size_t>(1, n / 16384)));
    auto slice = [&](unsigned, std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
            if (i + index_ahead < e) __builtin_prefetch(indices + std::size_t(id_of(i + index_ahead)) * 3);
            if (i + vertex_ahead < e) {
                const std::uint32_t* v = indices + std::size_t(id_of(i + vertex_ahead)) * 3;
                for (int c = 0; c < 3; ++c) __builtin_prefetch(positions + std::size_t(v[c]) * 3);
            }
            tris[i] = make_tri(positions, indices, id_of(i));
        }
    };
    if (parts <= 1) slice(0, 0, n);
    else parallel_slices(n, parts, slice);
}

} // namespace

Bvh build_bvh(const float* positions, const std::uint32_t* indices, std::size_t triangle_count,
              const BvhBuildOptions& options, BvhWide* wide)
{
    Bvh out;
    if (wide) *wide = BvhWide();
    if (triangle_count == 0) return out;
    unsigned threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());

    std::vector<Prim> prims(triangle_count);
    // The root's bounds come with the boxes, per slice, merged exactly (min and max).
    unsigned parts = unsigned(std::min<std::size_t>(threads, std::max<std::size_t>(1, triangle_count / 16384)));
    std::vector<VBox> boxes(parts, VBox::none()), cboxes(parts, VBox::none());
    parallel_slices(triangle_count, parts, [&](unsigned part, std::size_t b, std::size_t e) {
        VBox box = VBox::none(), cbox = VBox::none();
        for (std::size_t i = b; i < e; ++i) {
            Box t = Box::none();
            for (int v = 0; v < 3; ++v) t.grow(positions + std::size_t(indices[i * 3 + v]) * 3);
            std::int32_t id = std::int32_t(std::uint32_t(i));
            v4i lo_bits = reinterpret_cast<v4i>(v4f{t.lo[0], t.lo[1], t.lo[2], 0.0f});
            lo_bits[3] = id;
            prims[i] = Prim(reinterpret_cast<v4f>(lo_bits), v4f{t.hi[0], t.hi[1], t.hi[2], 0.0f});
            box.grow(prims[i].box());
            cbox.grow(centroid(prims[i].box()));
        }
        boxes[part] = box;
        cboxes[part] = cbox;
    });
    for (unsigned part = 1; part < parts; ++part) {
        boxes[0].grow(boxes[part]);
        cboxes[0].grow(cboxes[part]);
    }
    Range root;
    root.begin = 0;
    root.end = std::uint32_t(triangle_count);
    root.box = boxes[0].box();
    root.cbox = cboxes[0].box();

    // A build given every thread of the pool (the caller's included) lets the pool balance about
    // 16 tasks; one given fewer divides its threads by the split ratio.
    std::uint32_t grain = threads >= pool_workers() + 1 ? std::uint32_t(triangle_count / 16) : 0;
    Builder builder(prims, options, grain);
    // Room for the most nodes n triangles can make (2n - 1, a leaf each): the vector never
    // reallocates, which would touch the nodes twice, and the room a tree of fuller leaves leaves
    // unused is never touched, so costs no page faults (a soup's tree has 2n - 1 nodes, and the
    // former guess of n + 1 moved 32 MB of a 1M soup's nodes).
    out.nodes.reserve(2 * triangle_count);
    out.depth = builder.build_parallel(root, 1, threads, out.nodes);

    // The tree's totals (one pass over the nodes) and its collapse on the pool, beside the leaf
    // triangles' copy, past the size where the handover costs more.
    auto totals_of = [&out, wide, aligned = options.full_leaves] {
        for (const clvis_bvh_node& n : out.nodes) out.leaves += n.count > 0;
        out.sah_cost = bvh_sah_cost(out.nodes);
        if (wide) *wide = collapse_wide(out, aligned);
    };
    if (!options.gather) {
        // The ids alone, the scratch freed, then the collapse: the leaf triangles (40 bytes each)
        // are the caller's to gather where it keeps them.
        out.ids.resize(triangle_count);
        parallel_slices(triangle_count, parts, [&](unsigned, std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) out.ids[i] = prims[i].id();
        });
        std::vector<Prim>().swap(prims);
        totals_of();
        return out;
    }
    TaskGroup totals;
    if (triangle_count >= Builder::min_parallel) totals.run(totals_of);
    else totals_of();
    out.tris.resize(triangle_count);
    gather_tris(positions, indices, threads, [&](std::size_t i) { return prims[i].id(); }, out.tris.data(),
                out.tris.size());
    totals.wait();
    return out;
}

void gather_bvh_tris(const float* positions, const std::uint32_t* indices, const std::uint32_t* ids,
                     std::size_t count, clvis_bvh_tri* out, unsigned threads)
{
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    gather_tris(positions, indices, threads, [ids](std::size_t i) { return ids[i]; }, out, count);
}

void refit_bvh(Bvh& bvh, const float* positions, const std::uint32_t* indices)
{
    gather_tris(positions, indices, std::max(1u, std::thread::hardware_concurrency()),
                [&](std::size_t i) { return bvh.tris[i].id; }, bvh.tris.data(), bvh.tris.size());
    // Depth-first order puts children after their parent: one backward pass sees children first.
    for (std::size_t i = bvh.nodes.size(); i-- > 0;) {
        clvis_bvh_node& n = bvh.nodes[i];
        Box b = Box::none();
        if (n.count > 0) {
            for (std::uint32_t k = n.first; k < n.first + n.count; ++k) {
                const clvis_bvh_tri& t = bvh.tris[k];
                float v[3][3] = {{t.v0_x, t.v0_y, t.v0_z}, {t.v1_x, t.v1_y, t.v1_z}, {t.v2_x, t.v2_y, t.v2_z}};
                for (auto& p : v) b.grow(p);
            }
        } else {
            for (std::size_t c : {i + 1, std::size_t(n.first)}) {
                const clvis_bvh_node& m = bvh.nodes[c];
                Box cb;
                cb.lo[0] = m.lo_x; cb.lo[1] = m.lo_y; cb.lo[2] = m.lo_z;
                cb.hi[0] = m.hi_x; cb.hi[1] = m.hi_y; cb.hi[2] = m.hi_z;
                b.grow(cb);
            }
        }
        n.lo_x = b.lo[0]; n.lo_y = b.lo[1]; n.lo_z = b.lo[2];
        n.hi_x = b.hi[0]; n.hi_y = b.hi[1]; n.hi_z = b.hi[2];
    }
    bvh.sah_cost = bvh_sah_cost(bvh.nodes);
}

double bvh_sah_cost(const std::vector<clvis_bvh_node>& nodes)
{
    if (nodes.empty()) return 0;
    double root = node_area(nodes[0]);
    double sum = 0;
    for (const clvis_bvh_node& n : nodes)
        sum += n.count > 0 ? node_area(n) * n.count : Builder::traversal_cost * node_area(n);
    return root > 0 ? sum / root : double(nodes.size());
}

} // namespace clvis::detail
