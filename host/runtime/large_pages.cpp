// The mappings behind LargePageAllocator (large_pages.hpp).
#include "runtime/large_pages.hpp"

#include <cstdint>

namespace clvis::detail {

#if defined(__linux__) && defined(MADV_HUGEPAGE)

void* map_large_pages(std::size_t bytes) noexcept
{
    // Over-map by one large page, then unmap the ends outside the aligned span.
    if (bytes > std::size_t(-1) - large_page_bytes) return nullptr;
    std::size_t span = bytes + large_page_bytes;
    void* raw = mmap(nullptr, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) return nullptr;
    auto start = reinterpret_cast<std::uintptr_t>(raw);
    std::uintptr_t aligned = (start + large_page_bytes - 1) / large_page_bytes * large_page_bytes;
    std::size_t head = aligned - start, tail = span - head - bytes;
    if (head) munmap(raw, head);
    if (tail) munmap(reinterpret_cast<void*>(aligned + bytes), tail);
    madvise(reinterpret_cast<void*>(aligned), bytes, MADV_HUGEPAGE); // advice only: 4 KiB pages if refused
    return reinterpret_cast<void*>(aligned);
}

void unmap_large_pages(void* p, std::size_t bytes) noexcept
{
    if (p) munmap(p, bytes);
}

#else

void* map_large_pages(std::size_t) noexcept { return nullptr; }
void unmap_large_pages(void*, std::size_t) noexcept {}

#endif

} // namespace clvis::detail
