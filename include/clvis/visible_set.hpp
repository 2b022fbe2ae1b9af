// The visible set: which triangles cover at least one sample of one view or of many, kept on the
// device as a per-triangle bit mask (kernels/visible.cl) and compacted there into a sorted list
// of ids. Marking reads only a visibility buffer, so both paths give the same set from the same
// buffer.
#pragma once

#include <clvis/device.hpp>
#include <clvis/visibility.hpp>


#include <cstdint>
#include <memory>
#include <vector>

namespace clvis {

class VisibleSet {
public:
    VisibleSet() = default;
    /// An empty set over `triangle_count` triangles on `device`.
    VisibleSet(const Device& device, std::uint32_t triangle_count);

    std::uint32_t triangle_count() const { return triangle_count_; }
    /// Adds every triangle id found in `vis` (views accumulate until clear()).
    void mark(const VisibilityBuffer& vis);
    void clear();

    /// The mask on the device: (triangle_count + 31) / 32 words, bit (id % 32) of word id / 32.
    cl_mem mask() const;
    /// Compacts the set on the device into ascending ids; returns how many. ids() then holds them.
    std::uint32_t compact();
    /// The compacted ids on the device (at least compact()'s count of uint32; valid after compact()).
    cl_mem ids() const;

    /// One byte per triangle, 1 where visible (reused storage).
    void read_mask(std::vector<std::uint8_t>& out) const;
    /// The visible ids in ascending order, compacted on the device (reused storage).
    void read_ids(std::vector<std::uint32_t>& out);
    std::vector<std::uint32_t> read_ids();

    struct State;

private:
    std::shared_ptr<State> state_;
    std::uint32_t triangle_count_ = 0;
};

} // namespace clvis
