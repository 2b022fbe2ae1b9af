// The visible set on the device (kernels/visible.cl): marking from visibility buffers, the
// compaction into sorted ids, and the reads back.
#include "frame/frame.hpp"
#include "runtime/cl_runtime.hpp"

#include <clvis/visible_set.hpp>

#include <algorithm>

namespace clvis {

using detail::round_up;
using detail::throw_cl_error;

namespace {

/// Work-items of visible_scan's single work-group, at most.
constexpr std::size_t scan_group = 256;
/// Work-items per group of the one-dimensional kernels.
constexpr std::size_t linear_group = 64;

} // namespace

struct VisibleSet::State {
    Device device;
    cl::CommandQueue queue;
    cl::Kernel clear, mark, scan, fill;
    cl::Buffer mask, offsets, ids;
    std::uint32_t words = 0;
    std::size_t scan_items = 1;

    void run(cl::Kernel& k, std::size_t n, std::size_t group)
    {
        queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(round_up(std::max<std::size_t>(n, 1), group)),
                                   cl::NDRange(group));
    }
};

VisibleSet::VisibleSet(const Device& device, std::uint32_t triangle_count) : triangle_count_(triangle_count)
{
    if (!device) throw Error(Error::Kind::InvalidArgument, "VisibleSet: empty Device");
    auto s = std::make_shared<State>();
    s->device = device;
    auto& d = detail::DeviceAccess::of(device, "VisibleSet");
    s->words = (triangle_count + 31) / 32;
    std::size_t word_bytes = std::max<std::size_t>(s->words, 1) * 4;
    d.check_allocation(std::uint64_t(triangle_count) * 4 + 4, "a visible set's id list");
    try {
        s->queue = d.make_queue();
        cl::Program program = d.program("visible");
        s->clear = cl::Kernel(program, "visible_clear");
        s->mark = cl::Kernel(program, "visible_mark");
        s->scan = cl::Kernel(program, "visible_scan");
        s->fill = cl::Kernel(program, "visible_fill");
        std::size_t granted = s->scan.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(d.device);
        while (s->scan_items * 2 <= std::min(granted, scan_group)) s->scan_items *= 2;
        s->mask = cl::Buffer(d.context, CL_MEM_READ_WRITE, word_bytes);
        s->offsets = cl::Buffer(d.context, CL_MEM_READ_WRITE, word_bytes + 4);
        s->ids = cl::Buffer(d.context, CL_MEM_READ_WRITE, std::max<std::size_t>(triangle_count, 1) * 4);
    } catch (const cl::Error& e) {
        throw_cl_error(e, "making a visible set on " + d.info.name);
    }
    state_ = std::move(s);
    clear();
}

void VisibleSet::clear()
{
    if (!state_) throw Error(Error::Kind::InvalidArgument, "use of an empty VisibleSet");
    State& s = *state_;
    try {
        s.clear.setArg(0, s.mask);
        s.clear.setArg(1, cl_uint(s.words));
        s.run(s.clear, s.words, linear_group);
        s.queue.finish();
    } catch (const cl::Error& e) {
        throw_cl_error(e, "clearing a visible set");
    }
}

void VisibleSet::mark(const VisibilityBuffer& vis)
{
    if (!state_) throw Error(Error::Kind::InvalidArgument, "use of an empty VisibleSet");
    if (vis.empty()) throw Error(Error::Kind::InvalidArgument, "VisibleSet::mark: empty visibility buffer");
    State& s = *state_;
    if (vis.device().context() != s.device.context())
        throw Error(Error::Kind::InvalidArgument, "VisibleSet::mark: the buffer belongs to another OpenCL context");
    std::size_t count = vis.key_count(); // every sample of every pixel
    try {
        s.mark.setArg(0, cl::Buffer(vis.keys(), true));
        s.mark.setArg(1, cl_uint(count));
        s.mark.setArg(2, cl_uint(triangle_count_));
        s.mark.setArg(3, s.mask);
        s.run(s.mark, count, linear_group);
        s.queue.finish();
    } catch (const cl::Error& e) {
        throw_cl_error(e, "marking a visible set");
    }
}

cl_mem VisibleSet::mask() const
{
    if (!state_) throw Error(Error::Kind::InvalidArgument, "use of an empty VisibleSet");
    return state_->mask();
}

cl_mem VisibleSet::ids() const
{
    if (!state_) throw Error(Error::Kind::InvalidArgument, "use of an empty VisibleSet");
    return state_->ids();
}

std::uint32_t VisibleSet::compact()
{
    if (!state_) throw Error(Error::Kind::InvalidArgument, "use of an empty VisibleSet");
    State& s = *state_;
    cl_uint total = 0;
    try {
        s.scan.setArg(0, s.mask);
        s.scan.setArg(1, cl_uint(s.words));
        s.scan.setArg(2, s.offsets);
        s.scan.setArg(3, cl::Local(s.scan_items * sizeof(cl_uint)));
        s.queue.enqueueNDRangeKernel(s.scan, cl::NullRange, cl::NDRange(s.scan_items), cl::NDRange(s.scan_items));
        s.fill.setArg(0, s.mask);
        s.fill.setArg(1, cl_uint(s.words));
        s.fill.setArg(2, s.offsets);
        s.fill.setArg(3, s.ids);
        s.run(s.fill, s.words, linear_group);
        s.queue.enqueueReadBuffer(s.offsets, CL_TRUE, std::size_t(s.words) * 4, 4, &total);
    } catch (const cl::Error& e) {
        throw_cl_error(e, "compacting a visible set");
    }
    return total;
}

void VisibleSet::read_mask(std::vector<std::uint8_t>& out) const
{
    if (!state_) throw Error(Error::Kind::InvalidArgument, "use of an empty VisibleSet");
    State& s = *state_;
    std::vector<std::uint32_t> words(s.words);
    try {
        if (s.words) s.queue.enqueueReadBuffer(s.mask, CL_TRUE, 0, words.size() * 4, words.data());
    } catch (const cl::Error& e) {
        throw_cl_error(e, "reading a visible set's mask");
    }
    out.resize(triangle_count_);
    for (std::uint32_t i = 0; i < triangle_count_; ++i) out[i] = std::uint8_t((words[i >> 5] >> (i & 31)) & 1u);
}

void VisibleSet::read_ids(std::vector<std::uint32_t>& out)
{
    std::uint32_t n = compact();
    out.resize(n);
    try {
        if (n) state_->queue.enqueueReadBuffer(state_->ids, CL_TRUE, 0, std::size_t(n) * 4, out.data());
    } catch (const cl::Error& e) {
        throw_cl_error(e, "reading a visible set's ids");
    }
}

std::vector<std::uint32_t> VisibleSet::read_ids()
{
    std::vector<std::uint32_t> out;
    read_ids(out);
    return out;
}

} // namespace clvis
