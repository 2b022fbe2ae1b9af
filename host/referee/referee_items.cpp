// The referee's triangles without the expansion: the scene's geometry copied as it is held (each
// prototype once, each plain mesh) with the items that place it, every triangle set up from them
// (in parallel, by id) and kept only when a sample position of the image lies inside its bounds;
// any other triangle a judgement asks for is set up again from the items, bit for bit the same.
// A scene of 2000 instances of a 69k-triangle mesh (139 M triangles) keeps what its image can show.
#include "referee/referee_impl.hpp"
#include "scene/instance_transform.hpp"

#include <clvis/error.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <functional>
#include <thread>

namespace clvis {

using namespace detail;

namespace {

/// The world position of vertex v of `src` placed by `it`: transform_positions' bits.
void world_vertex(const RefereeItem& it, const RefereeSource& src, std::size_t v, float out[3])
{
    const float* p = &src.positions[3 * v];
    if (it.identity) {
        std::copy(p, p + 3, out);
        return;
    }
    clvis_vec3 w = clvis_instance_point(it.m.data(), p[0], p[1], p[2]);
    out[0] = w.x;
    out[1] = w.y;
    out[2] = w.z;
}

unsigned threads() { return std::max(1u, std::thread::hardware_concurrency()); }

/// Parts to split n triangles or vertices into: none below 16384 each, a few per thread.
unsigned parts_for(std::size_t n)
{
    return unsigned(std::min<std::size_t>(std::size_t(8) * threads(), std::max<std::size_t>(1, n / 16384)));
}

/// Runs body(part, b, e) on `parts` contiguous near-equal slices [b, e) of [0, n), on the
/// machine's threads (the referee's floor has no thread pool: as Impl::by_rows); the first part's
/// exception, if any, is thrown when all are done.
void run_slices(std::size_t n, unsigned parts, const std::function<void(unsigned, std::size_t, std::size_t)>& body)
{
    std::vector<std::exception_ptr> errors(parts);
    std::atomic<unsigned> next{0};
    auto work = [&] {
        for (unsigned p; (p = next++) < parts;) {
            try {
                body(p, n * p / parts, n * (p + 1) / parts);
            } catch (...) {
                errors[p] = std::current_exception();
            }
        }
    };
    std::vector<std::thread> pool;
    for (unsigned k = 1; k < std::min(threads(), parts); ++k) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    for (const std::exception_ptr& e : errors)
        if (e) std::rethrow_exception(e);
}

} // namespace

void Referee::Impl::copy_items(const Scene& scene)
{
    triangle_count = scene.triangle_count();
    sources.clear();
    items.clear();
    // Prototypes once (those instanced), then each plain mesh.
    std::vector<std::uint32_t> source_of(scene.prototypes().size(), std::uint32_t(-1));
    items.reserve(scene.meshes().size());
    std::vector<std::size_t> vertex_first; // of each item, in the items' vertex order
    std::size_t vertices_total = 0;
    for (std::size_t i = 0; i < scene.meshes().size(); ++i) {
        const Scene::Mesh& m = scene.meshes()[i];
        const MeshData& data = scene.data_of(i);
        RefereeItem it;
        it.first = m.first_triangle;
        it.triangles = std::uint32_t(data.triangle_count());
        it.identity = m.transform.is_identity();
        if (!it.identity) it.m = instance_matrix(m.transform);
        std::uint32_t* known = m.prototype != Scene::no_prototype ? &source_of[m.prototype] : nullptr;
        if (known && *known != std::uint32_t(-1)) {
            it.source = *known;
        } else {
            it.source = std::uint32_t(sources.size());
            sources.push_back({data.positions, data.indices, data.name});
            if (known) *known = it.source;
        }
        items.push_back(it);
        vertex_first.push_back(vertices_total);
        vertices_total += data.vertex_count();
    }

    // world_positions() refuses the first item with a transformed vertex that overflows float32,
    // referenced or not: so does the referee, whichever slice finds it first.
    std::size_t none = items.size();
    unsigned parts = parts_for(vertices_total);
    std::vector<std::size_t> bad(parts, none);
    run_slices(vertices_total, parts, [&](unsigned part, std::size_t b, std::size_t e) {
        if (b == e) return;
        std::size_t item = std::size_t(std::upper_bound(vertex_first.begin(), vertex_first.end(), b) -
                                       vertex_first.begin()) - 1;
        for (std::size_t v = b; v < e; ++v) {
            while (v >= vertex_first[item] + sources[items[item].source].positions.size() / 3) ++item;
            float w[3];
            world_vertex(items[item], sources[items[item].source], v - vertex_first[item], w);
            if (!std::isfinite(w[0]) || !std::isfinite(w[1]) || !std::isfinite(w[2])) {
                bad[part] = item;
                return;
            }
        }
    });
    std::size_t first_bad = *std::min_element(bad.begin(), bad.end());
    if (first_bad != none)
        throw Error(Error::Kind::InvalidArgument,
                    "mesh '" + sources[items[first_bad].source].name + "': a transformed vertex overflows float32");
}

void Referee::Impl::vertices(const RefereeItem& it, std::size_t local, Vec3 world[3], Vec3 cam[3]) const
{
    const RefereeSource& src = sources[it.source];
    for (int k = 0; k < 3; ++k) {
        float w[3];
        world_vertex(it, src, src.indices[3 * local + std::size_t(k)], w);
        world[k] = {w[0], w[1], w[2]};
        Vec3 d = world[k] - camera.eye;
        cam[k] = {dot(d, frame.r), dot(d, frame.u), -dot(d, frame.f)}; // Camera::to_camera
    }
}

namespace {

/// Sources with at most this many vertices have them placed, moved to camera space and projected
/// once per item and slice (about 5 MB a slice), not once per triangle that uses them.
constexpr std::size_t cached_vertices = std::size_t(1) << 16;

/// A vertex of the item being set up, as setup_triangle takes it.
struct CachedVertex {
    Vec3 world, cam;
    double x = 0, y = 0; ///< projected, when within both clip planes
    bool near = false, far = false; ///< within the near and far clip planes
};

} // namespace

void Referee::Impl::set_up_candidates()
{
    // In id order, slice by slice, each slice keeping its own: merged in slice order, the kept
    // triangles are in id order whatever the thread count.
    std::size_t cache_size = 0;
    for (const RefereeSource& src : sources)
        if (src.positions.size() / 3 <= cached_vertices) cache_size = std::max(cache_size, src.positions.size() / 3);
    unsigned parts = parts_for(triangle_count);
    std::vector<std::vector<Triangle>> part_tris(parts);
    std::vector<std::vector<std::uint32_t>> part_ids(parts);
    run_slices(triangle_count, parts, [&](unsigned part, std::size_t b, std::size_t e) {
        if (b == e) return;
        auto at = std::upper_bound(items.begin(), items.end(), b,
                                   [](std::size_t id, const RefereeItem& i) { return id < i.first; });
        std::size_t item = std::size_t(at - items.begin()) - 1;
        std::vector<CachedVertex> cache(cache_size);
        std::vector<std::size_t> stamp(cache_size, std::size_t(-1)); // the item a cached vertex is of
        auto vertex = [&](std::size_t v) -> const CachedVertex& {
            CachedVertex& c = cache[v];
            if (stamp[v] != item) {
                stamp[v] = item;
                const RefereeItem& it = items[item];
                float w[3];
                world_vertex(it, sources[it.source], v, w);
                c.world = {w[0], w[1], w[2]};
                Vec3 d = c.world - camera.eye;
                c.cam = {dot(d, frame.r), dot(d, frame.u), -dot(d, frame.f)}; // as vertices() does
                c.near = within_near(c.cam);
                c.far = within_far(c.cam);
                if (c.near && c.far) project(c.cam, &c.x, &c.y);
            }
            return c;
        };
        for (std::size_t id = b; id < e; ++id) {
            while (id >= std::size_t(items[item].first) + items[item].triangles) ++item;
            const RefereeItem& it = items[item];
            const RefereeSource& src = sources[it.source];
            std::size_t local = id - it.first;
            Triangle t;
            Vec3 w[3], c[3];
            if (src.positions.size() / 3 <= cached_vertices) {
                const CachedVertex* v[3];
                int near = 0, far = 0;
                for (int k = 0; k < 3; ++k) {
                    v[k] = &vertex(src.indices[3 * local + std::size_t(k)]);
                    near += v[k]->near;
                    far += v[k]->far;
                    w[k] = v[k]->world;
                    c[k] = v[k]->cam;
                }
                if (near == 0 || (near == 3 && far == 0)) continue; // clipped whole: n = 0
                if (near == 3 && far == 3) {
                    // Clipped by neither plane: the clip keeps the vertices as they are.
                    t.n = 3;
                    for (int k = 0; k < 3; ++k) {
                        t.px[k] = v[k]->x;
                        t.py[k] = v[k]->y;
                        t.pd[k] = -v[k]->cam.z;
                    }
                    set_bounds(t);
                } else {
                    setup_visible_part(t, c);
                }
            } else {
                vertices(it, local, w, c);
                setup_visible_part(t, c);
            }
            if (!may_be_candidate(t)) continue;
            setup_plane(t, w, c);
            part_tris[part].push_back(t);
            part_ids[part].push_back(std::uint32_t(id));
        }
    });
    std::size_t total = 0;
    for (const auto& p : part_ids) total += p.size();
    kept.clear();
    kept_ids.clear();
    kept.reserve(total);
    kept_ids.reserve(total);
    for (unsigned p = 0; p < parts; ++p) {
        kept.insert(kept.end(), part_tris[p].begin(), part_tris[p].end());
        kept_ids.insert(kept_ids.end(), part_ids[p].begin(), part_ids[p].end());
        std::vector<Triangle>().swap(part_tris[p]);
        std::vector<std::uint32_t>().swap(part_ids[p]);
    }
}

const Triangle& Referee::Impl::triangle(std::uint32_t id, Triangle& scratch) const
{
    auto k = std::lower_bound(kept_ids.begin(), kept_ids.end(), id);
    if (k != kept_ids.end() && *k == id) return kept[std::size_t(k - kept_ids.begin())];
    auto it = std::upper_bound(items.begin(), items.end(), id,
                               [](std::uint32_t v, const RefereeItem& i) { return v < i.first; });
    const RefereeItem& item = *(it - 1);
    Vec3 w[3], c[3];
    vertices(item, id - item.first, w, c);
    scratch = Triangle{};
    setup_triangle(scratch, w, c);
    return scratch;
}

} // namespace clvis
