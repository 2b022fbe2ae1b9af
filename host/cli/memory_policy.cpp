// The heap policy of the commands that hold a whole scene's BVH (issue 37's memory): glibc keeps a
// freed block of up to 32 MB for reuse, raising its mmap threshold to the largest block freed, so
// after the loader's and the BVH build's large temporaries the heap holds tens of MB freed but
// resident beside the tree at the ray path's peak (about 12 bytes a triangle of a 1M sphere). A
// fixed threshold maps every block of 1 MB or more on its own and returns it when freed.
#include "commands.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace clvis::cli {

void return_large_blocks()
{
#if defined(__GLIBC__)
    mallopt(M_MMAP_THRESHOLD, 1 << 20); // also ends the threshold's growth
#endif
}

} // namespace clvis::cli
