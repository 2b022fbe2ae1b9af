// Binned SAH BVH build (Wald, "On fast construction of SAH-based bounding volume hierarchies",
// 2007). Near the root the binning of a node is spread over the threads and its two children are
// built on separate threads, each into its own depth-first array, then spliced in order; splits
// depend only on the triangles (bins merge exactly), so the result does not depend on the threads. Where the SAH cannot split (every centroid in one point) or the tree
// grows too deep, an object median split takes over, so degenerate scenes terminate quickly.
#include "ray/bvh_build.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <thread>

namespace clvis::detail {

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();

/// An axis-aligned box of floats: trivial (arrays of them cost nothing to declare); Box::none()
/// has lo = +inf, hi = -inf.
struct Box {
    float lo[3], hi[3];

    static Box none() { return {{inf, inf, inf}, {-inf, -inf, -inf}}; }

    void grow(const Box& b)
    {
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], b.lo[a]);
            hi[a] = std::max(hi[a], b.hi[a]);
        }
    }
    void grow(const float p[3])
    {
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
        }
    }
    bool empty() const { return !(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]); }
    /// Half the surface area, in double: float boxes of huge finite coordinates do not overflow.
    double half_area() const
    {
        if (empty()) return 0;
        double dx = double(hi[0]) - lo[0], dy = double(hi[1]) - lo[1], dz = double(hi[2]) - lo[2];
        return dx * dy + dy * dz + dz * dx;
    }
};

/// One triangle as the build sees it: its box, its centroid (the box's centre) and its id. The
/// build reorders these themselves (not indices to them), so every pass reads memory in order.
struct Prim {
    Box box;
    float c[3];
    std::uint32_t id;
};

/// A range of the id array with its bounds and its centroids' bounds.
struct Range {
    std::uint32_t begin = 0, end = 0;
    Box box = Box::none(), cbox = Box::none();
    std::uint32_t count() const { return end - begin; }
};

constexpr int max_bins = 256;

/// Per-axis bins; only the first `bins` of each axis are set up and used (a node's split must not
/// pay for clearing all max_bins).
struct Bins {
    Box box[3][max_bins];
    std::uint32_t count[3][max_bins];

    explicit Bins(int bins)
    {
        for (int a = 0; a < 3; ++a)
            for (int k = 0; k < bins; ++k) {
                box[a][k] = Box::none();
                count[a][k] = 0;
            }
    }
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
    float lo[3], scale[3];
    bool valid[3];
    int bins;

    BinMap(const Box& cbox, int bins_) : bins(bins_)
    {
        for (int a = 0; a < 3; ++a) {
            double extent = double(cbox.hi[a]) - double(cbox.lo[a]);
            lo[a] = cbox.lo[a];
            valid[a] = extent > 0;
            scale[a] = valid[a] ? float(std::min<double>(bins * (1 - 1e-6) / extent, FLT_MAX)) : 0.0f;
        }
    }
    int bin(int axis, float c) const
    {
        float k = (c - lo[axis]) * scale[axis];
        return int(std::min(std::max(k, 0.0f), float(bins - 1)));
    }
};

class Builder {
public:
    Builder(std::vector<Prim>& prims, const BvhBuildOptions& o) : prims_(prims), opt_(o)
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
    /// spliced in depth-first order: the same bits as build_serial.
    int build_parallel(const Range& r, int depth, unsigned threads, std::vector<clvis_bvh_node>& out) const
    {
        if (threads <= 1 || r.count() < min_parallel) return build_serial(r, depth, out);
        std::size_t self = out.size();
        out.push_back(make_node(r.box));
        Range left, right;
        if (!split(r, depth, left, right, threads)) {
            out[self].first = r.begin;
            out[self].count = r.count();
            return depth;
        }
        unsigned threads_right = std::max(1u, unsigned(std::uint64_t(threads) * right.count() / r.count()));
        threads_right = std::min(threads_right, threads - 1);
        std::vector<clvis_bvh_node> right_nodes;
        right_nodes.reserve(std::size_t(right.count()) * 2);
        int depth_right = 0;
        std::thread worker([&] { depth_right = build_parallel(right, depth + 1, threads_right, right_nodes); });
        int depth_left = build_parallel(left, depth + 1, threads - threads_right, out);
        worker.join();
        std::uint32_t offset = std::uint32_t(out.size());
        out[self].first = offset;
        for (clvis_bvh_node node : right_nodes) {
            if (node.count == 0) node.first += offset;
            out.push_back(node);
        }
        return std::max(depth_left, depth_right);
    }

    /// Ranges smaller than this are built on one thread.
    static constexpr std::uint32_t min_parallel = 8192;

    /// Splits `r` into two non-empty halves (returns false for a leaf); `workers` threads bin.
    bool split(const Range& r, int depth, Range& left, Range& right, unsigned workers) const
    {
        std::uint32_t n = r.count();
        if (n <= 1) return false;
        bool centroids_apart = false;
        for (int a = 0; a < 3; ++a) centroids_apart |= r.cbox.hi[a] > r.cbox.lo[a];
        bool must_split = n > std::uint32_t(opt_.max_leaf_size);
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
        // No more bins than triangles: near the leaves the sweep would cost more than the binning.
        int bins = int(std::min<std::uint32_t>(std::uint32_t(opt_.sah_bins), std::max<std::uint32_t>(n, 4)));
        BinMap map(r.cbox, bins);
        Bins binned(bins);
        bin(r, map, workers, binned);
        // Sweep each axis: cost of splitting after bin k = areas times counts of both sides.
        double best = std::numeric_limits<double>::infinity();
        int best_axis = -1, best_k = 0;
        for (int a = 0; a < 3; ++a) {
            if (!map.valid[a]) continue;
            double right_cost[max_bins];
            Box acc = Box::none();
            std::uint32_t cnt = 0;
            for (int k = bins - 1; k > 0; --k) {
                acc.grow(binned.box[a][k]);
                cnt += binned.count[a][k];
                right_cost[k] = acc.half_area() * cnt;
            }
            acc = Box::none();
            cnt = 0;
            for (int k = 0; k < bins - 1; ++k) {
                acc.grow(binned.box[a][k]);
                cnt += binned.count[a][k];
                if (cnt == 0 || cnt == n) continue;
                double cost = acc.half_area() * cnt + right_cost[k + 1];
                if (cost < best) {
                    best = cost;
                    best_axis = a;
                    best_k = k;
                }
            }
        }
        if (best_axis < 0) { // every centroid in one bin on every axis: only rounding apart
            if (!must_split) return false;
            split_median(r, left, right);
            return true;
        }
        double area = r.box.half_area();
        double leaf_cost = area * n;
        double split_cost = traversal_cost * area + best;
        if (!must_split && leaf_cost <= split_cost) return false;
        partition(r, map, best_axis, best_k, left, right);
        return true;
    }

    /// Cost of one traversal step relative to one triangle test, in the SAH.
    static constexpr double traversal_cost = 1.0;

private:
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
        auto bin_part = [&](std::uint32_t b, std::uint32_t e, Bins& out) {
            for (std::uint32_t i = b; i < e; ++i) {
                const Prim& p = prims_[i];
                for (int a = 0; a < 3; ++a) {
                    if (!map.valid[a]) continue;
                    int k = map.bin(a, p.c[a]);
                    out.box[a][k].grow(p.box);
                    ++out.count[a][k];
                }
            }
        };
        std::uint32_t n = r.count();
        unsigned parts = std::min<unsigned>(workers, std::max<std::uint32_t>(1, n / 65536));
        if (parts <= 1) {
            bin_part(r.begin, r.end, out);
            return;
        }
        // Bins merge by min, max and sums: exact and order-free, so the split does not depend
        // on the number of parts.
        std::vector<Bins> partial(parts, Bins(bins));
        std::vector<std::thread> pool;
        for (unsigned t = 0; t < parts; ++t) {
            std::uint32_t b = r.begin + std::uint32_t(std::uint64_t(n) * t / parts);
            std::uint32_t e = r.begin + std::uint32_t(std::uint64_t(n) * (t + 1) / parts);
            pool.emplace_back(bin_part, b, e, std::ref(partial[t]));
        }
        for (auto& th : pool) th.join();
        for (unsigned t = 0; t < parts; ++t) out.merge(partial[t], bins);
    }

    void bounds(std::uint32_t b, std::uint32_t e, Range& out) const
    {
        out.begin = b;
        out.end = e;
        out.box = Box::none();
        out.cbox = Box::none();
        for (std::uint32_t i = b; i < e; ++i) {
            const Prim& p = prims_[i];
            out.box.grow(p.box);
            out.cbox.grow(p.c);
        }
    }

    void partition(const Range& r, const BinMap& map, int axis, int k, Range& left, Range& right) const
    {
        std::uint32_t i = r.begin, j = r.end;
        left = Range();
        right = Range();
        while (i < j) {
            const Prim& p = prims_[i];
            if (map.bin(axis, p.c[axis]) <= k) {
                left.box.grow(p.box);
                left.cbox.grow(p.c);
                ++i;
            } else {
                right.box.grow(p.box);
                right.cbox.grow(p.c);
                std::swap(prims_[i], prims_[--j]);
            }
        }
        left.begin = r.begin;
        left.end = i;
        right.begin = i;
        right.end = r.end;
    }

    void split_in_order(const Range& r, Range& left, Range& right) const
    {
        std::uint32_t mid = r.begin + r.count() / 2;
        bounds(r.begin, mid, left);
        bounds(mid, r.end, right);
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
                             return x.c[axis] < y.c[axis] || (x.c[axis] == y.c[axis] && x.id < y.id);
                         });
        bounds(r.begin, mid, left);
        bounds(mid, r.end, right);
    }

    std::vector<Prim>& prims_;
    BvhBuildOptions opt_;
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

/// Runs body(i) for i in [0, n) on `threads` threads, in contiguous chunks.
template <class F> void parallel_for(std::size_t n, unsigned threads, F body)
{
    unsigned parts = unsigned(std::min<std::size_t>(threads, std::max<std::size_t>(1, n / 16384)));
    if (parts <= 1) {
        for (std::size_t i = 0; i < n; ++i) body(i);
        return;
    }
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < parts; ++t)
        pool.emplace_back([&, t] {
            for (std::size_t i = n * t / parts; i < n * (t + 1) / parts; ++i) body(i);
        });
    for (auto& th : pool) th.join();
}

} // namespace

Bvh build_bvh(const float* positions, const std::uint32_t* indices, std::size_t triangle_count,
              const BvhBuildOptions& options)
{
    Bvh out;
    if (triangle_count == 0) return out;
    unsigned threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());

    std::vector<Prim> prims(triangle_count);
    parallel_for(triangle_count, threads, [&](std::size_t i) {
        Prim& p = prims[i];
        p.box = Box::none();
        for (int v = 0; v < 3; ++v) p.box.grow(positions + std::size_t(indices[i * 3 + v]) * 3);
        // Halves first: the sum of two huge finite coordinates would overflow.
        for (int a = 0; a < 3; ++a) p.c[a] = p.box.lo[a] * 0.5f + p.box.hi[a] * 0.5f;
        p.id = std::uint32_t(i);
    });
    Range root;
    root.begin = 0;
    root.end = std::uint32_t(triangle_count);
    for (const Prim& p : prims) {
        root.box.grow(p.box);
        root.cbox.grow(p.c);
    }

    Builder builder(prims, options);
    out.nodes.reserve(triangle_count * 2 / std::size_t(std::max(1, options.max_leaf_size / 2)) + 1);
    out.depth = builder.build_parallel(root, 1, threads, out.nodes);

    out.tris.resize(triangle_count);
    parallel_for(triangle_count, threads, [&](std::size_t i) { out.tris[i] = make_tri(positions, indices, prims[i].id); });
    for (const clvis_bvh_node& n : out.nodes) out.leaves += n.count > 0;
    out.sah_cost = bvh_sah_cost(out.nodes);
    return out;
}

void refit_bvh(Bvh& bvh, const float* positions, const std::uint32_t* indices)
{
    parallel_for(bvh.tris.size(), std::max(1u, std::thread::hardware_concurrency()),
                 [&](std::size_t i) { bvh.tris[i] = make_tri(positions, indices, bvh.tris[i].id); });
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

namespace {

double node_area(const clvis_bvh_node& n)
{
    Box b;
    b.lo[0] = n.lo_x; b.lo[1] = n.lo_y; b.lo[2] = n.lo_z;
    b.hi[0] = n.hi_x; b.hi[1] = n.hi_y; b.hi[2] = n.hi_z;
    return b.half_area();
}

/// Appends the 4-wide node for binary node `n` (interior) and its subtree; returns its depth.
int collapse(const Bvh& bvh, std::uint32_t n, Bvh4& out)
{
    std::uint32_t kids[4] = {n + 1, bvh.nodes[n].first, 0, 0};
    int count = 2;
    while (count < 4) {
        int open = -1;
        double largest = -1;
        for (int k = 0; k < count; ++k) {
            const clvis_bvh_node& c = bvh.nodes[kids[k]];
            if (c.count == 0 && node_area(c) > largest) {
                largest = node_area(c);
                open = k;
            }
        }
        if (open < 0) break;
        std::uint32_t c = kids[open];
        // the opened node's children take its slot and the next one, keeping the left-to-right order
        for (int k = count; k > open + 1; --k) kids[k] = kids[k - 1];
        kids[open] = c + 1;
        kids[open + 1] = bvh.nodes[c].first;
        ++count;
    }
    std::size_t self = out.nodes.size();
    out.nodes.emplace_back();
    out.source.insert(out.source.end(), {~0u, ~0u, ~0u, ~0u});
    int depth = 1;
    for (int k = 0; k < 4; ++k) {
        clvis_bvh4_node& w = out.nodes[self];
        if (k >= count) {
            w.lo_x[k] = w.lo_y[k] = w.lo_z[k] = inf;
            w.hi_x[k] = w.hi_y[k] = w.hi_z[k] = -inf;
            w.child[k] = 0;
            w.count[k] = 0;
            continue;
        }
        const clvis_bvh_node& c = bvh.nodes[kids[k]];
        out.source[self * 4 + std::size_t(k)] = kids[k];
        w.lo_x[k] = c.lo_x; w.lo_y[k] = c.lo_y; w.lo_z[k] = c.lo_z;
        w.hi_x[k] = c.hi_x; w.hi_y[k] = c.hi_y; w.hi_z[k] = c.hi_z;
        w.count[k] = c.count;
        if (c.count > 0) {
            w.child[k] = c.first;
        } else {
            std::uint32_t index = std::uint32_t(out.nodes.size());
            int d = collapse(bvh, kids[k], out); // may move out.nodes: w is not used after this
            out.nodes[self].child[k] = index;
            depth = std::max(depth, d + 1);
        }
    }
    return depth;
}

} // namespace

Bvh4 collapse_bvh4(const Bvh& bvh)
{
    Bvh4 out;
    if (bvh.nodes.empty()) return out;
    out.nodes.reserve(bvh.nodes.size() / 3 + 1);
    out.source.reserve(out.nodes.capacity() * 4);
    const clvis_bvh_node& root = bvh.nodes[0];
    if (root.count > 0) { // a single leaf: one 4-wide node with one child
        clvis_bvh4_node w{};
        for (int k = 0; k < 4; ++k) {
            w.lo_x[k] = w.lo_y[k] = w.lo_z[k] = inf;
            w.hi_x[k] = w.hi_y[k] = w.hi_z[k] = -inf;
        }
        w.lo_x[0] = root.lo_x; w.lo_y[0] = root.lo_y; w.lo_z[0] = root.lo_z;
        w.hi_x[0] = root.hi_x; w.hi_y[0] = root.hi_y; w.hi_z[0] = root.hi_z;
        w.child[0] = root.first;
        w.count[0] = root.count;
        out.nodes.push_back(w);
        out.source = {0, ~0u, ~0u, ~0u};
        out.depth = 1;
        return out;
    }
    out.depth = collapse(bvh, 0, out);
    return out;
}

void refit_bvh4(Bvh4& wide, const Bvh& bvh)
{
    for (std::size_t i = 0; i < wide.nodes.size(); ++i) {
        clvis_bvh4_node& w = wide.nodes[i];
        for (int k = 0; k < 4; ++k) {
            std::uint32_t src = wide.source[i * 4 + std::size_t(k)];
            if (src == ~0u) continue;
            const clvis_bvh_node& c = bvh.nodes[src];
            w.lo_x[k] = c.lo_x; w.lo_y[k] = c.lo_y; w.lo_z[k] = c.lo_z;
            w.hi_x[k] = c.hi_x; w.hi_y[k] = c.hi_y; w.hi_z[k] = c.hi_z;
        }
    }
}

double bvh_sah_cost(const std::vector<clvis_bvh_node>& nodes)
{
    if (nodes.empty()) return 0;
    auto area = [](const clvis_bvh_node& n) {
        Box b;
        b.lo[0] = n.lo_x; b.lo[1] = n.lo_y; b.lo[2] = n.lo_z;
        b.hi[0] = n.hi_x; b.hi[1] = n.hi_y; b.hi[2] = n.hi_z;
        return b.half_area();
    };
    double root = area(nodes[0]);
    double sum = 0;
    for (const clvis_bvh_node& n : nodes)
        sum += n.count > 0 ? area(n) * n.count : Builder::traversal_cost * area(n);
    return root > 0 ? sum / root : double(nodes.size());
}

} // namespace clvis::detail
