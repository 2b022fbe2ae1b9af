// Binned SAH BVH build (Wald, "On fast construction of SAH-based bounding volume hierarchies",
// 2007). The top of the tree is split on one thread with the binning spread over the workers; the
// subtrees below a size fixed by the triangle count (not by the threads) are then built in
// parallel, each into its own depth-first array, and spliced in order: the result does not depend
// on which thread built what. Where the SAH cannot split (every centroid in one point) or the tree
// grows too deep, an object median split takes over, so degenerate scenes terminate quickly.
#include "bvh_build.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>

namespace clvis::detail {

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();

struct Box {
    float lo[3] = {inf, inf, inf};
    float hi[3] = {-inf, -inf, -inf};

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

/// One triangle as the build sees it: its box and its centroid (the box's centre).
struct Prim {
    Box box;
    float c[3];
};

/// A range of the id array with its bounds and its centroids' bounds.
struct Range {
    std::uint32_t begin = 0, end = 0;
    Box box, cbox;
    std::uint32_t count() const { return end - begin; }
};

constexpr int max_bins = 256;

struct Bins {
    Box box[3][max_bins];
    std::uint32_t count[3][max_bins] = {};

    void merge(const Bins& o, int bins)
    {
        for (int a = 0; a < 3; ++a)
            for (int k = 0; k < bins; ++k) {
                box[a][k].grow(o.box[a][k]);
                count[a][k] += o.count[a][k];
            }
    }
};

/// Maps a centroid coordinate to its bin, in double so that huge finite extents do not overflow.
struct BinMap {
    double lo[3], scale[3];
    bool valid[3];
    int bins;

    BinMap(const Box& cbox, int bins_) : bins(bins_)
    {
        for (int a = 0; a < 3; ++a) {
            double extent = double(cbox.hi[a]) - double(cbox.lo[a]);
            lo[a] = cbox.lo[a];
            valid[a] = extent > 0;
            scale[a] = valid[a] ? bins * (1 - 1e-9) / extent : 0;
        }
    }
    int bin(int axis, float c) const
    {
        long k = long((double(c) - lo[axis]) * scale[axis]);
        return int(std::clamp<long>(k, 0, bins - 1));
    }
};

class Builder {
public:
    Builder(const std::vector<Prim>& prims, std::vector<std::uint32_t>& ids, const BvhBuildOptions& o)
        : prims_(prims), ids_(ids), opt_(o)
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
        int bins = opt_.sah_bins;
        BinMap map(r.cbox, bins);
        Bins binned = bin(r, map, workers);
        // Sweep each axis: cost of splitting after bin k = areas times counts of both sides.
        double best = std::numeric_limits<double>::infinity();
        int best_axis = -1, best_k = 0;
        for (int a = 0; a < 3; ++a) {
            if (!map.valid[a]) continue;
            double right_cost[max_bins];
            Box acc;
            std::uint32_t cnt = 0;
            for (int k = bins - 1; k > 0; --k) {
                acc.grow(binned.box[a][k]);
                cnt += binned.count[a][k];
                right_cost[k] = acc.half_area() * cnt;
            }
            acc = Box();
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

    Bins bin(const Range& r, const BinMap& map, unsigned workers) const
    {
        int bins = map.bins;
        auto bin_part = [&](std::uint32_t b, std::uint32_t e, Bins& out) {
            for (std::uint32_t i = b; i < e; ++i) {
                const Prim& p = prims_[ids_[i]];
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
            Bins out;
            bin_part(r.begin, r.end, out);
            return out;
        }
        // Bins merge by min, max and sums: exact and order-free, so the split does not depend
        // on the number of parts.
        std::vector<Bins> partial(parts);
        std::vector<std::thread> pool;
        for (unsigned t = 0; t < parts; ++t) {
            std::uint32_t b = r.begin + std::uint32_t(std::uint64_t(n) * t / parts);
            std::uint32_t e = r.begin + std::uint32_t(std::uint64_t(n) * (t + 1) / parts);
            pool.emplace_back(bin_part, b, e, std::ref(partial[t]));
        }
        for (auto& th : pool) th.join();
        for (unsigned t = 1; t < parts; ++t) partial[0].merge(partial[t], bins);
        return partial[0];
    }

    void bounds(std::uint32_t b, std::uint32_t e, Range& out) const
    {
        out.begin = b;
        out.end = e;
        out.box = Box();
        out.cbox = Box();
        for (std::uint32_t i = b; i < e; ++i) {
            const Prim& p = prims_[ids_[i]];
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
            const Prim& p = prims_[ids_[i]];
            if (map.bin(axis, p.c[axis]) <= k) {
                left.box.grow(p.box);
                left.cbox.grow(p.c);
                ++i;
            } else {
                right.box.grow(p.box);
                right.cbox.grow(p.c);
                std::swap(ids_[i], ids_[--j]);
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
        std::nth_element(ids_.begin() + r.begin, ids_.begin() + mid, ids_.begin() + r.end,
                         [&](std::uint32_t x, std::uint32_t y) {
                             float cx = prims_[x].c[axis], cy = prims_[y].c[axis];
                             return cx < cy || (cx == cy && x < y);
                         });
        bounds(r.begin, mid, left);
        bounds(mid, r.end, right);
    }

    const std::vector<Prim>& prims_;
    std::vector<std::uint32_t>& ids_;
    BvhBuildOptions opt_;
};

/// The top of the tree, split serially; its leaves are the subtrees built in parallel.
struct TopNode {
    Box box;
    int left = -1, right = -1; ///< top nodes, or -1 for a task
    int task = -1;
};

struct Task {
    Range range;
    int depth = 0;
    std::vector<clvis_bvh_node> nodes;
    int max_depth = 0;
};

int expand_top(const Builder& builder, const Range& r, int depth, std::uint32_t cutoff, unsigned workers,
               std::vector<TopNode>& top, std::vector<Task>& tasks)
{
    int self = int(top.size());
    top.push_back({r.box});
    Range left, right;
    if (r.count() <= cutoff || !builder.split(r, depth, left, right, workers)) {
        top[self].task = int(tasks.size());
        tasks.push_back({r, depth, {}, 0});
        return self;
    }
    int l = expand_top(builder, left, depth + 1, cutoff, workers, top, tasks);
    int rr = expand_top(builder, right, depth + 1, cutoff, workers, top, tasks);
    top[self].left = l;
    top[self].right = rr;
    return self;
}

void splice(const std::vector<TopNode>& top, int t, std::vector<Task>& tasks, std::vector<clvis_bvh_node>& out)
{
    const TopNode& n = top[t];
    if (n.task >= 0) {
        auto& sub = tasks[n.task].nodes;
        std::uint32_t offset = std::uint32_t(out.size());
        for (clvis_bvh_node node : sub) {
            if (node.count == 0) node.first += offset;
            out.push_back(node);
        }
        sub = {};
        return;
    }
    std::size_t self = out.size();
    clvis_bvh_node node{};
    node.lo_x = n.box.lo[0]; node.lo_y = n.box.lo[1]; node.lo_z = n.box.lo[2];
    node.hi_x = n.box.hi[0]; node.hi_y = n.box.hi[1]; node.hi_z = n.box.hi[2];
    out.push_back(node);
    splice(top, n.left, tasks, out);
    out[self].first = std::uint32_t(out.size());
    splice(top, n.right, tasks, out);
}

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
    std::vector<std::uint32_t> ids(triangle_count);
    parallel_for(triangle_count, threads, [&](std::size_t i) {
        Prim& p = prims[i];
        for (int v = 0; v < 3; ++v) p.box.grow(positions + std::size_t(indices[i * 3 + v]) * 3);
        // Halves first: the sum of two huge finite coordinates would overflow.
        for (int a = 0; a < 3; ++a) p.c[a] = p.box.lo[a] * 0.5f + p.box.hi[a] * 0.5f;
        ids[i] = std::uint32_t(i);
    });
    Range root;
    root.begin = 0;
    root.end = std::uint32_t(triangle_count);
    for (const Prim& p : prims) {
        root.box.grow(p.box);
        root.cbox.grow(p.c);
    }

    Builder builder(prims, ids, options);
    // Subtrees of at most 1/64 of the triangles (at least 4096) become tasks: a fixed cut, so
    // the tree is the same for any number of threads.
    std::uint32_t cutoff = std::max<std::uint32_t>(4096, std::uint32_t(triangle_count / 64));
    std::vector<TopNode> top;
    std::vector<Task> tasks;
    expand_top(builder, root, 1, cutoff, threads, top, tasks);

    // Largest tasks first, handed out by an atomic counter: which thread builds which subtree
    // varies, the subtrees do not.
    std::vector<std::size_t> order(tasks.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return tasks[a].range.count() > tasks[b].range.count(); });
    std::atomic<std::size_t> next{0};
    auto worker = [&] {
        for (std::size_t i; (i = next.fetch_add(1)) < order.size();) {
            Task& t = tasks[order[i]];
            t.nodes.reserve(std::size_t(t.range.count()) * 2 / std::max(1, options.max_leaf_size / 2) + 1);
            t.max_depth = builder.build_serial(t.range, t.depth, t.nodes);
        }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < std::min<std::size_t>(threads, tasks.size()); ++t) pool.emplace_back(worker);
    worker();
    for (auto& th : pool) th.join();

    std::size_t total = top.size();
    for (const Task& t : tasks) {
        total += t.nodes.size();
        out.depth = std::max(out.depth, t.max_depth);
    }
    out.nodes.reserve(total);
    splice(top, 0, tasks, out.nodes);

    out.tris.resize(triangle_count);
    parallel_for(triangle_count, threads, [&](std::size_t i) { out.tris[i] = make_tri(positions, indices, ids[i]); });
    for (const clvis_bvh_node& n : out.nodes) out.leaves += n.count > 0;
    out.sah_cost = bvh_sah_cost(out.nodes);
    return out;
}

void refit_bvh(Bvh& bvh, const float* positions, const std::uint32_t* indices)
{
    for (clvis_bvh_tri& t : bvh.tris) t = make_tri(positions, indices, t.id);
    // Depth-first order puts children after their parent: one backward pass sees children first.
    for (std::size_t i = bvh.nodes.size(); i-- > 0;) {
        clvis_bvh_node& n = bvh.nodes[i];
        Box b;
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
