// The process's thread pool (host/runtime/thread_pool.cpp) under the BVH build: many builds at
// once from several threads give the serial build's bits, tasks nest without tying up the pool,
// and a task's exception reaches the caller as a clvis::Error.
#include "catch.hpp"

#include "ray/bvh_build.hpp"
#include "runtime/thread_pool.hpp"

#include <clvis/error.hpp>
#include <clvis/procedural.hpp>

#include <atomic>
#include <cstring>
#include <functional>
#include <new>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace clvis;
using namespace clvis::detail;

namespace {

Bvh build(const MeshData& m, unsigned threads)
{
    BvhBuildOptions o;
    o.threads = threads;
    return build_bvh(m.positions.data(), m.indices.data(), m.triangle_count(), o);
}

bool same_bits(const Bvh& a, const Bvh& b)
{
    return a.nodes.size() == b.nodes.size() && a.tris.size() == b.tris.size() &&
           std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(clvis_bvh_node)) == 0 &&
           std::memcmp(a.tris.data(), b.tris.data(), a.tris.size() * sizeof(clvis_bvh_tri)) == 0;
}

} // namespace

TEST_CASE("many builds at once on several threads give the serial build's bits", "[bvh]")
{
    // Past the sizes that split the top of the tree into tasks and bin in parts.
    MeshData soup = make_soup(150000, 5), sphere = make_uv_sphere(40000);
    Bvh soup_serial = build(soup, 1), sphere_serial = build(sphere, 1);
    constexpr int callers = 6;
    std::vector<Bvh> results(callers);
    std::vector<std::thread> threads;
    for (int c = 0; c < callers; ++c)
        threads.emplace_back([&, c] { results[c] = build(c % 2 ? sphere : soup, unsigned(2 + c)); });
    for (std::thread& t : threads) t.join();
    for (int c = 0; c < callers; ++c) {
        INFO("caller " << c);
        CHECK(same_bits(results[c], c % 2 ? sphere_serial : soup_serial));
    }
}

TEST_CASE("tasks that wait on tasks of their own all finish", "[bvh]")
{
    std::atomic<int> leaves{0};
    std::function<void(int)> tree = [&](int depth) {
        if (depth == 0) {
            ++leaves;
            return;
        }
        TaskGroup group;
        group.run([&, depth] { tree(depth - 1); });
        tree(depth - 1);
        group.wait();
    };
    tree(10);
    CHECK(leaves.load() == 1024);
}

TEST_CASE("a pool task's exception reaches the caller as a clvis::Error", "[bvh]")
{
    SECTION("an Error keeps its kind and message")
    {
        TaskGroup group;
        group.run([] { throw Error(Error::Kind::InvalidArgument, "task 3: bad input"); });
        try {
            group.wait();
            FAIL("wait() returned");
        } catch (const Error& e) {
            CHECK(e.kind() == Error::Kind::InvalidArgument);
            CHECK(std::string(e.what()) == "task 3: bad input");
        }
    }
    SECTION("another exception becomes an Error naming it; the other tasks still run")
    {
        std::atomic<int> ran{0};
        TaskGroup group;
        for (int t = 0; t < 8; ++t)
            group.run([&ran, t] {
                ++ran;
                if (t == 2) throw std::runtime_error("slice 2 failed");
            });
        try {
            group.wait();
            FAIL("wait() returned");
        } catch (const Error& e) {
            CHECK(std::string(e.what()).find("slice 2 failed") != std::string::npos);
        }
        CHECK(ran.load() == 8);
    }
    SECTION("parallel_slices hands a slice's bad_alloc back as a Limit error")
    {
        for (unsigned failing : {0u, 3u}) { // the caller's own slice and a pool task's
            INFO("slice " << failing);
            try {
                parallel_slices(1000, 4, [failing](unsigned part, std::size_t, std::size_t) {
                    if (part == failing) throw std::bad_alloc();
                });
                FAIL("parallel_slices returned");
            } catch (const Error& e) {
                CHECK(e.kind() == Error::Kind::Limit);
            }
        }
    }
    SECTION("a group waited for twice has nothing left to throw")
    {
        TaskGroup group;
        group.run([] { throw std::logic_error("once"); });
        CHECK_THROWS_AS(group.wait(), Error);
        CHECK_NOTHROW(group.wait());
    }
}

TEST_CASE("parallel_slices covers [0, n) once in contiguous slices", "[bvh]")
{
    for (unsigned parts : {1u, 2u, 3u, 7u, 64u}) {
        std::vector<std::atomic<int>> hits(1000);
        for (auto& h : hits) h.store(0);
        std::vector<int> seen_part(parts, 0);
        parallel_slices(hits.size(), parts, [&](unsigned part, std::size_t b, std::size_t e) {
            seen_part[part] = int(e - b);
            for (std::size_t i = b; i < e; ++i) ++hits[i];
        });
        INFO(parts << " parts");
        for (const auto& h : hits) REQUIRE(h.load() == 1);
        for (int s : seen_part) CHECK(s >= int(1000 / parts));
    }
}
