// The one BVH walk of the ray kernels (kernels/shared/bvh_walk.h) compiled by the host, with the
// scalar tests of shared/ray.h as its parameters: on a flat tree and on a two-level tree of
// instances, the nearest hit of every ray is the one a test of every triangle finds, and a walk
// that stops at its first hit (any hit) stops at a real one.
#include "catch.hpp"

#include "ray/bvh_build.hpp"
#include "ray/bvh_instances.hpp"
#include "shared/ray.h"
#include "shared/visibility.h"

#include <clvis/clvis.hpp>
#include <clvis/procedural.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace clvis;
using namespace clvis::detail;

namespace {

/// The walk's context: one ray, its nearest key so far (closest) or its first hit (any).
struct HostWalk {
    clvis_ray_shear shear;
    clvis_box_ray box;
    bool any = false;
    clvis_u64 best = CLVIS_BACKGROUND_KEY;
};

float reach(const HostWalk* c) { return clvis_key_depth(c->best); }

int host_children(HostWalk* c, const clvis_wide_node* nd, const clvis_instance* xi, float keys[CLVIS_BVH_WIDTH])
{
    int bits = 0;
    for (int k = 0; k < bvh_width; ++k) {
        float lo[3], hi[3], e;
        clvis_instance_child_box(nd, k, xi, lo, hi);
        clvis_vec3 l = {lo[0], lo[1], lo[2]}, h = {hi[0], hi[1], hi[2]};
        if (clvis_ray_hits_box(c->box, l, h, 0.0f, reach(c), &e)) {
            bits |= 1 << k;
            keys[k] = e;
        }
    }
    return bits;
}

int host_leaf(HostWalk* c, const clvis_bvh_tri* tris, clvis_u32 first, clvis_u32 count, const clvis_instance* xi)
{
    for (clvis_u32 k = first; k < first + count; ++k) {
        float v[9], t;
        clvis_u32 id = clvis_instance_triangle(tris + k, xi, v);
        clvis_vec3 a = {v[0], v[1], v[2]}, b = {v[3], v[4], v[5]}, d = {v[6], v[7], v[8]};
        if (!clvis_intersect_triangle(c->shear, a, b, d, 0.0f, CLVIS_INFINITY, CLVIS_CULL_NONE, &t)) continue;
        clvis_u64 key = clvis_make_key(t, id);
        c->best = key < c->best ? key : c->best;
        if (c->any) return 1;
    }
    return 0;
}

} // namespace

#define CLVIS_WALK_CTX HostWalk
#define CLVIS_WALK_CHILDREN(c, v, nd, xi, keys) host_children(c, nd, xi, keys)
#define CLVIS_WALK_KEY_SKIP(c, v, key) ((key) > reach(c) * CLVIS_IZE_SCALE)
#define CLVIS_WALK_BOX_SKIP(c, v, nd, k, xi) 0
#define CLVIS_WALK_LEAF(c, v, tris, first, count, xi) host_leaf(c, tris, first, count, xi)
#define CLVIS_RAY_STACK 256
#include "shared/bvh_walk.h"

namespace {

struct Tree {
    std::vector<clvis_wide_node> nodes;
    std::vector<clvis_bvh_tri> tris;
    std::vector<clvis_instance> instances; ///< empty: a flat tree
};

/// The nearest key along o + t d (t >= 0) by the walk, or its first hit with `any`.
clvis_u64 walk(const Tree& tree, clvis_vec3 o, clvis_vec3 d, bool any)
{
    HostWalk c;
    c.shear = clvis_make_shear(o, d);
    c.box = clvis_make_box_ray(o, d);
    c.any = any;
    clvis_walk w;
    clvis_walk_stack st;
    bool two = !tree.instances.empty();
    clvis_walk_start(&w, clvis_u32(tree.nodes.size()), two);
    while (w.node != CLVIS_WALK_DONE)
        if (two) clvis_walk_step(&c, 0, 1, tree.nodes.data(), tree.tris.data(), tree.instances.data(), &w, &st);
        else clvis_walk_step(&c, 0, 0, tree.nodes.data(), tree.tris.data(), nullptr, &w, &st);
    return c.best;
}

/// Every triangle of the scene's expansion, by the same test: the nearest key and all hit ids.
clvis_u64 brute(const Scene& scene, clvis_vec3 o, clvis_vec3 d, std::vector<clvis_u32>* hits)
{
    clvis_ray_shear s = clvis_make_shear(o, d);
    clvis_u64 best = CLVIS_BACKGROUND_KEY;
    for (clvis_u32 id = 0; id < scene.triangle_count(); ++id) {
        float v[9], t;
        scene.triangle(id, v);
        clvis_vec3 a = {v[0], v[1], v[2]}, b = {v[3], v[4], v[5]}, c = {v[6], v[7], v[8]};
        if (!clvis_intersect_triangle(s, a, b, c, 0.0f, CLVIS_INFINITY, CLVIS_CULL_NONE, &t)) continue;
        clvis_u64 key = clvis_make_key(t, id);
        best = key < best ? key : best;
        hits->push_back(id);
    }
    return best;
}

/// Rays from around the scene's box towards points inside it.
void check_rays(const Tree& tree, const Scene& scene, int count, std::uint32_t seed)
{
    Bounds b = scene.bounds();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.25, 1.25);
    auto at = [&](double fx, double fy, double fz) {
        return clvis_vec3{float(b.lo.x + fx * (b.hi.x - b.lo.x)), float(b.lo.y + fy * (b.hi.y - b.lo.y)),
                          float(b.lo.z + fz * (b.hi.z - b.lo.z))};
    };
    int hit_rays = 0;
    for (int i = 0; i < count; ++i) {
        clvis_vec3 o = at(u(rng), u(rng), u(rng)), p = at(u(rng), u(rng), u(rng));
        clvis_vec3 d = {p.x - o.x, p.y - o.y, p.z - o.z};
        std::vector<clvis_u32> hits;
        clvis_u64 expected = brute(scene, o, d, &hits);
        REQUIRE(walk(tree, o, d, false) == expected);
        clvis_u64 first = walk(tree, o, d, true);
        if (hits.empty()) {
            REQUIRE(first == CLVIS_BACKGROUND_KEY);
            continue;
        }
        ++hit_rays;
        REQUIRE(std::find(hits.begin(), hits.end(), clvis_u32(first & 0xFFFFFFFFu)) != hits.end());
    }
    CHECK(hit_rays > count / 10);
}

} // namespace

TEST_CASE("the shared BVH walk finds every ray's nearest hit in a flat tree", "[bvh]")
{
    MeshData soup = make_soup(3000, 5);
    Scene scene;
    scene.add_mesh(soup);
    BvhBuildOptions options;
    BvhWide wide;
    Bvh bvh = build_bvh(soup.positions.data(), soup.indices.data(), soup.indices.size() / 3, options, &wide);
    REQUIRE((bvh_width - 1) * wide.depth + 1 <= CLVIS_RAY_STACK);
    check_rays({wide.nodes, bvh.tris, {}}, scene, 400, 11);
}

TEST_CASE("the shared BVH walk enters instances and finds the expansion's nearest hit", "[bvh][instances]")
{
    Scene scene;
    scene.add_mesh(make_soup(200, 3));
    std::size_t proto = scene.add_prototype(make_uv_sphere(400));
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-3, 3), s(0.3, 1.2), a(0, 6.28);
    for (int i = 0; i < 40; ++i) {
        double c = std::cos(a(rng)), n = std::sin(a(rng)), k = s(rng);
        Mat4 m;
        m.m = {k * c, 0, k * n, u(rng), 0, k, 0, u(rng), -k * n, 0, k * c, u(rng), 0, 0, 0, 1};
        scene.add_instance(proto, m);
        if (i == 20) scene.add_mesh(make_soup(100, 8));
    }
    InstanceBvh two;
    two.update(scene, BvhBuildOptions{});
    REQUIRE(two.stack_entries() <= CLVIS_RAY_STACK);
    check_rays({two.nodes(), two.tris(), two.instances()}, scene, 300, 12);
}
