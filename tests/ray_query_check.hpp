// What the ray-query tests share: answers of all three queries for a batch of rays, and the check
// that the BVH walk answers as the brute force does, bit for bit (and, optionally, acceptably to
// the double-precision oracle of ray_oracle.hpp).
#pragma once

#include "catch.hpp"
#include "ray_oracle.hpp"

#include <clvis/clvis.hpp>
#include <clvis/ray_query.hpp>

#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace clvis::test {

inline std::uint32_t bits(float f)
{
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    return u;
}

inline bool same_hit(const HitRecord& a, const HitRecord& b)
{
    return bits(a.t) == bits(b.t) && a.id == b.id && bits(a.u) == bits(b.u) && bits(a.v) == bits(b.v);
}

/// The oracle's verdict on triangle `id` for a failure message.
inline std::string describe(const RayRecord& r, const Scene& scene, std::uint32_t id)
{
    if (id >= scene.triangle_count()) return "no triangle";
    float v[9];
    scene.triangle(id, v);
    Judged j = judge_triangle(r, v);
    std::ostringstream s;
    s << "the oracle judges it " << (j.verdict == Verdict::In ? "in" : j.verdict == Verdict::Out ? "out" : "ambiguous")
      << " at t = " << j.t << " +- " << j.t_tol;
    return s.str();
}

struct Answers {
    std::vector<HitRecord> hits;
    std::vector<std::uint8_t> flags;
    std::vector<std::uint32_t> counts;
    RayQueryStats stats;
};

inline Answers answer(RayQuery& q, const std::vector<RayRecord>& rays)
{
    Answers a;
    a.hits.resize(rays.size());
    a.flags.resize(rays.size());
    a.counts.resize(rays.size());
    a.stats = q.closest({rays.data(), rays.size()}, a.hits.data());
    REQUIRE(q.occluded({rays.data(), rays.size()}, a.flags.data()).invalid == a.stats.invalid);
    REQUIRE(q.count({rays.data(), rays.size()}, a.counts.data()).invalid == a.stats.invalid);
    return a;
}

/// Everything the BVH walk answers equals the brute force's answer, bit for bit, occlusion is
/// whether a closest hit exists, invalid rays are misses, and closest hits and counts satisfy
/// the double-precision oracle. `options`: the renderer's (its BVH's leaf size, say).
inline void check_scene(const Scene& scene, const std::vector<RayRecord>& rays, bool oracle,
                        const RenderOptions& options = {})
{
    Renderer renderer(Device::open(), scene, options);
    RayQuery bvh(renderer), brute(renderer, RayQueryOptions{std::size_t(1) << 20, true});
    Answers a = answer(bvh, rays), b = answer(brute, rays);
    std::size_t invalid = 0, hits = 0, bad_closest = 0, bad_count = 0;
    std::ostringstream failures;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        INFO("ray " << i << " (" << rays[i].ox << ", " << rays[i].oy << ", " << rays[i].oz << ") + t ("
                    << rays[i].dx << ", " << rays[i].dy << ", " << rays[i].dz << "), t in [" << rays[i].tmin
                    << ", " << rays[i].tmax << "]");
        REQUIRE(same_hit(a.hits[i], b.hits[i]));
        REQUIRE(a.flags[i] == b.flags[i]);
        REQUIRE(a.counts[i] == b.counts[i]);
        REQUIRE(int(a.flags[i]) == int(a.hits[i].id != background_id));
        bool valid = ray_is_valid(rays[i]);
        invalid += !valid;
        hits += a.hits[i].id != background_id;
        if (!valid) {
            REQUIRE(a.hits[i].id == background_id);
            REQUIRE(a.hits[i].t == std::numeric_limits<float>::infinity());
            REQUIRE(a.hits[i].u == 0.0f);
            REQUIRE(a.counts[i] == 0);
        } else if (oracle) {
            RayVerdict rv = judge_ray(rays[i], scene);
            bool ok = closest_acceptable(rays[i], scene, rv, a.hits[i]);
            if (!ok && bad_closest < 5)
                failures << "ray " << i << ": hit " << a.hits[i].id << " at " << a.hits[i].t << ", oracle: " << rv.in
                         << " in, nearest at " << rv.nearest_in << ", " << rv.ambiguous << " ambiguous, "
                         << describe(rays[i], scene, a.hits[i].id) << "\n";
            bad_closest += !ok;
            bad_count += a.counts[i] < rv.in || a.counts[i] > rv.in + rv.ambiguous;
        }
    }
    CHECK(a.stats.invalid == invalid);
    CHECK(hits > rays.size() / 20);
    INFO(failures.str());
    CHECK(bad_closest == 0);
    CHECK(bad_count == 0);
}

} // namespace clvis::test
