// One node's binned SAH split (Wald, "On fast construction of SAH-based bounding volume
// hierarchies", 2007) for bvh_build.cpp: binning, the sweep over the bins of all three axes at
// once without data-dependent branches, and the in-place partition.
#include "ray/bvh_build_split.hpp"

#include <limits>

// On x86-64 Linux the three passes are compiled twice, for AVX2 and for the baseline, and the
// loader picks one by the CPU (GCC's and Clang's target_clones): the double-precision areas of
// the sweep take one instruction per four lanes instead of two. Same operations, same bits.
#if defined(__x86_64__) && defined(__linux__) && ((defined(__clang__) && __clang_major__ >= 14) || (!defined(__clang__) && defined(__GNUC__)))
#define CLVIS_SPLIT_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define CLVIS_SPLIT_CLONES
#endif

namespace clvis::detail {

CLVIS_SPLIT_CLONES void bin_prims(const Prim* prims, std::uint32_t b, std::uint32_t e, const BinMap& map, Bins& out)
{
    // A block's bins are mapped first, then its boxes and counts added: the bins' addresses are
    // known ahead of the stores, where computing them one primitive at a time between them left
    // each primitive's loads of the bins waiting on the last one's stores. An axis without extent bins everything into bin 0 ((c - lo) is 0 there)
    // and is never swept: no branch per axis.
    constexpr std::uint32_t block = 64;
    v4i k[block];
    for (std::uint32_t s = b; s < e; s += block) {
        std::uint32_t m = std::min(block, e - s);
        for (std::uint32_t i = 0; i < m; ++i) k[i] = map.bins3(centroid(prims[s + i].box()));
        for (std::uint32_t i = 0; i < m; ++i) {
            VBox box = prims[s + i].box();
            for (int a = 0; a < 3; ++a) {
                out.box[a][k[i][a]].grow(box);
                ++out.count[a][k[i][a]];
            }
        }
    }
}

CLVIS_SPLIT_CLONES BinSplit sweep_bins(const Bins& bins, const BinMap& map, std::uint32_t n)
{
    // Cost of splitting after bin k = areas times counts of both sides. A side that holds no
    // centroid costs nothing and is never chosen. An empty bin grows nothing (its box is none),
    // so its cost repeats the bin before it bit for bit and, compared strictly, never wins: every
    // bin is swept alike, with selects instead of branches.
    constexpr double inf = std::numeric_limits<double>::infinity();
    int nb = map.bins;
    double right_cost[3][max_bins]; // [a][k]: the side of bins k..nb-1
    VBox acc[3] = {VBox::none(), VBox::none(), VBox::none()};
    std::uint32_t cnt[3] = {0, 0, 0};
    for (int k = nb - 1; k > 0; --k)
        for (int a = 0; a < 3; ++a) {
            acc[a].grow(bins.box[a][k]);
            cnt[a] += bins.count[a][k];
            double cost = acc[a].half_area() * cnt[a];
            right_cost[a][k] = cnt[a] != 0 ? cost : 0.0;
        }
    double best[3] = {inf, inf, inf};
    int best_k[3] = {0, 0, 0};
    for (int a = 0; a < 3; ++a) {
        acc[a] = VBox::none();
        cnt[a] = 0;
    }
    for (int k = 0; k < nb - 1; ++k)
        for (int a = 0; a < 3; ++a) {
            acc[a].grow(bins.box[a][k]);
            cnt[a] += bins.count[a][k];
            double cost = acc[a].half_area() * cnt[a] + right_cost[a][k + 1];
            bool better = cnt[a] != 0 && cnt[a] != n && cost < best[a];
            best[a] = better ? cost : best[a];
            best_k[a] = better ? k : best_k[a];
        }
    BinSplit s;
    double cheapest = inf;
    for (int a = 0; a < 3; ++a)
        if (map.valid[a] && best[a] < cheapest) {
            cheapest = best[a];
            s.axis = a;
            s.k = best_k[a];
        }
    s.cost = cheapest;
    return s;
}

BinSplit sweep_pair(const Prim* pair, const BinMap& map)
{
    // The sweep would see each in a bin of its own on such an axis: from the lower one's bin on,
    // every split costs the same (a + b), so the first wins, and so does the lowest axis.
    VBox a = pair[0].box(), b = pair[1].box();
    v4i ka = map.bins3(centroid(a)), kb = map.bins3(centroid(b));
    BinSplit s;
    for (int x = 0; x < 3; ++x)
        if (map.valid[x] && ka[x] != kb[x]) {
            s.axis = x;
            s.k = std::min(ka[x], kb[x]);
            s.cost = a.half_area() + b.half_area();
            break;
        }
    return s;
}

namespace {

typedef float v8f __attribute__((vector_size(32)));
typedef std::int32_t v8i __attribute__((vector_size(32)));

/// partition_prims on `Axis`. Both sides' centroid bounds are kept as (lo, -hi) in one 8-lane
/// register each, grown by one minimum: -max(h, c) is min(-h, -c), and on ties (signed zeros
/// included) both keep the value they hold, so the bounds have Box::grow's bits.
template <int Axis>
inline __attribute__((always_inline)) void partition_on(Prim* prims, const Range& r, const BinMap& map, int k,
                                                        Range& left, Range& right)
{
    constexpr float inf = std::numeric_limits<float>::infinity();
    const v8f none{inf, inf, inf, inf, inf, inf, inf, inf};
    const v8f flip{1, 1, 1, 1, -1, -1, -1, -1};
    const v4i kk = v4i{k, k, k, k};
    std::uint32_t j = r.begin;
    v8f lacc = none, racc = none;
    for (std::uint32_t i = r.begin; i < r.end; ++i) {
        Prim p = prims[i];
        v4f c = centroid(p.box());
        v4i m = map.bins3(c) <= kk;
        v8i m8 = __builtin_shufflevector(m, m, Axis, Axis, Axis, Axis, Axis, Axis, Axis, Axis); // -1 left, 0 right
        v8f c8 = __builtin_shufflevector(c, c, 0, 1, 2, 3, 0, 1, 2, 3) * flip;
        v8i ci = reinterpret_cast<v8i>(c8), ni = reinterpret_cast<v8i>(none);
        v8f lv = reinterpret_cast<v8f>((ci & m8) | (ni & ~m8)); // the side not taken grows by none
        v8f rv = reinterpret_cast<v8f>((ni & m8) | (ci & ~m8));
        lacc = lv < lacc ? lv : lacc;
        racc = rv < racc ? rv : racc;
        prims[i] = prims[j];
        prims[j] = p;
        j -= std::uint32_t(m8[0]);
    }
    for (int a = 0; a < 3; ++a) {
        left.cbox.lo[a] = lacc[a];
        left.cbox.hi[a] = -lacc[4 + a];
        right.cbox.lo[a] = racc[a];
        right.cbox.hi[a] = -racc[4 + a];
    }
    left.begin = r.begin;
    left.end = j;
    right.begin = j;
    right.end = r.end;
}

} // namespace

CLVIS_SPLIT_CLONES void partition_prims(Prim* prims, const Range& r, const BinMap& map, int axis, int k, Range& left, Range& right)
{
    // Lomuto's scheme without a branch on the side (which a split makes a coin toss): every
    // primitive is swapped with the first of the right side so far, which moves on only past a
    // left one, and both sides' centroid bounds grow by selects (a side not taken grows by the
    // empty box). The side is tested in the registers: the three bins compared with k, the
    // axis' lane broadcast (the axis a template argument, so the broadcast is one shuffle).
    if (axis == 0) partition_on<0>(prims, r, map, k, left, right);
    else if (axis == 1) partition_on<1>(prims, r, map, k, left, right);
    else partition_on<2>(prims, r, map, k, left, right);
}

void range_bounds(const Prim* prims, std::uint32_t b, std::uint32_t e, Range& out)
{
    out.begin = b;
    out.end = e;
    VBox box = VBox::none(), cbox = VBox::none();
    for (std::uint32_t i = b; i < e; ++i) {
        VBox p = prims[i].box();
        box.grow(p);
        cbox.grow(centroid(p));
    }
    out.box = box.box();
    out.cbox = cbox.box();
}

} // namespace clvis::detail
