// An allocator for the host's large, short-lived arrays (the BVH build's primitives, nodes and
// leaf triangles): from 16 MiB up, memory mapped on its own, aligned to 2 MiB and advised as
// transparent huge pages (madvise(MADV_HUGEPAGE), which Linux honours where THP is "always" or
// "madvise"), so that its first touch faults once per 2 MiB instead of once per 4 KiB. A fresh
// 1M-triangle soup's build touches about 250 MB: its page faults were a fifth of the build
// (360 -> 281 ms). Below 16 MiB the mapping and the zeroing of whole 2 MiB pages cost more than
// the faults saved (from 2 MiB, a 64k-triangle build was 5-15 % slower), and elsewhere than
// Linux it is std::allocator throughout. Same contents either way.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace clvis::detail {

/// Maps `bytes` (a multiple of large_page_bytes) aligned to large_page_bytes, advised as huge
/// pages; nullptr where the mapping fails.
void* map_large_pages(std::size_t bytes) noexcept;
/// Unmaps what map_large_pages returned for the same `bytes`.
void unmap_large_pages(void* p, std::size_t bytes) noexcept;

constexpr std::size_t large_page_bytes = std::size_t(2) << 20;
/// Arrays from this size on are mapped in large pages (see the top of this file).
constexpr std::size_t large_threshold = std::size_t(16) << 20;

template <class T> struct LargePageAllocator {
    using value_type = T;

    LargePageAllocator() = default;
    template <class U> LargePageAllocator(const LargePageAllocator<U>&) noexcept {}

    T* allocate(std::size_t n)
    {
        if (n > std::size_t(-1) / sizeof(T)) throw std::bad_alloc();
        std::size_t bytes = n * sizeof(T);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        if (bytes >= large_threshold) {
            if (bytes > std::size_t(-1) - 2 * large_page_bytes) throw std::bad_alloc();
            void* p = map_large_pages(rounded(bytes));
            if (!p) throw std::bad_alloc();
            return static_cast<T*>(p);
        }
#endif
        return std::allocator<T>().allocate(n);
    }

    void deallocate(T* p, std::size_t n) noexcept
    {
        std::size_t bytes = n * sizeof(T);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        if (bytes >= large_threshold) {
            unmap_large_pages(p, rounded(bytes));
            return;
        }
#endif
        std::allocator<T>().deallocate(p, n);
    }

    template <class U> bool operator==(const LargePageAllocator<U>&) const noexcept { return true; }
    template <class U> bool operator!=(const LargePageAllocator<U>&) const noexcept { return false; }

private:
    static std::size_t rounded(std::size_t bytes) { return (bytes + large_page_bytes - 1) / large_page_bytes * large_page_bytes; }
};

/// A std::vector in large pages (LargePageAllocator).
template <class T> using LargeVector = std::vector<T, LargePageAllocator<T>>;

} // namespace clvis::detail
