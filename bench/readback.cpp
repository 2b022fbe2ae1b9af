// Times the read-back of a visibility buffer to the host against a plain clEnqueueReadBuffer of
// its keys: the allocating read() as it was (read the keys, then split into new vectors), and
// the reads into storage the caller reuses. Usage: clvis_readback [WIDTH HEIGHT [REPEAT]].
#include <clvis/clvis.hpp>

#include <CL/cl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <vector>

using namespace clvis;

namespace {

/// The median of `repeat` timed runs of `fn`, in ms, after one untimed run.
double median_ms(int repeat, const std::function<void()>& fn)
{
    fn();
    std::vector<double> ms;
    for (int i = 0; i < repeat; ++i) {
        auto t0 = std::chrono::steady_clock::now();
        fn();
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    return ms[ms.size() / 2];
}

} // namespace

int main(int argc, char** argv)
{
    int w = argc > 2 ? std::atoi(argv[1]) : 1024, h = argc > 2 ? std::atoi(argv[2]) : 1024;
    int repeat = argc > 3 ? std::atoi(argv[3]) : 21;
    try {
        Device device = Device::open();
        Scene scene;
        scene.add_mesh(make_uv_sphere(4000));
        Renderer renderer(device, scene);
        VisibilityBuffer v = renderer.render(Camera::framing(scene.bounds()), w, h, Path::Raster);
        std::size_t n = std::size_t(w) * h;
        cl_command_queue queue = device.queue();
        std::vector<std::uint64_t> keys(n);
        double plain = median_ms(repeat, [&] {
            clEnqueueReadBuffer(queue, v.keys(), CL_TRUE, 0, n * 8, keys.data(), 0, nullptr, nullptr);
        });
        double before = median_ms(repeat, [&] {
            std::vector<std::uint64_t> fresh(n);
            clEnqueueReadBuffer(queue, v.keys(), CL_TRUE, 0, n * 8, fresh.data(), 0, nullptr, nullptr);
            HostVisibility split = split_keys(fresh.data(), w, h);
        });
        std::vector<std::uint32_t> bar_ids(n);
        std::vector<float> bar_depth(n);
        double bar = median_ms(repeat, [&] {
            clEnqueueReadBuffer(queue, v.keys(), CL_TRUE, 0, n * 8, keys.data(), 0, nullptr, nullptr);
            for (std::size_t i = 0; i < n; ++i) {
                bar_ids[i] = std::uint32_t(keys[i]);
                std::uint32_t bits = std::uint32_t(keys[i] >> 32);
                std::memcpy(&bar_depth[i], &bits, 4);
            }
        });
        double fresh_read = median_ms(repeat, [&] { HostVisibility r = v.read(); });
        HostVisibility reused;
        double reused_read = median_ms(repeat, [&] { v.read(reused); });
        std::vector<std::uint32_t> ids;
        double ids_read = median_ms(repeat, [&] { v.read_ids(ids); });
        std::printf("%s, %dx%d, median of %d (ms):\n", device.info().name.c_str(), w, h, repeat);
        std::printf("  clEnqueueReadBuffer of the keys      %8.3f  (1.00x)\n", plain);
        std::printf("  the bar: that read + split, reused  %8.3f  (%.2fx)\n", bar, bar / plain);
        std::printf("  read as before (new vectors, split)  %8.3f  (%.2fx)\n", before, before / plain);
        std::printf("  read() (new vectors)                 %8.3f  (%.2fx)\n", fresh_read, fresh_read / plain);
        std::printf("  read(HostVisibility&) reused         %8.3f  (%.2fx)\n", reused_read, reused_read / plain);
        std::printf("  read_ids(vector&) reused             %8.3f  (%.2fx)\n", ids_read, ids_read / plain);
    } catch (const Error& e) {
        std::fprintf(stderr, "clvis_readback: %s\n", e.what());
        return 1;
    }
    return 0;
}
