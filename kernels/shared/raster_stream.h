/* Whole cache lines of keys written by the raster path's clear (kernels/visibility_clear.cl): with
   CLVIS_STREAM (PoCL's CPU device, Device::Impl::cpu_hints) and the host's `stream` as
   non-temporal stores, which write a 64-byte line without first reading it into the cache (a
   clear through the cache reads every line it writes, then evicts it dirty); elsewhere as plain
   vector stores. Either way the same keys. */
#ifndef CLVIS_SHARED_RASTER_STREAM_H
#define CLVIS_SHARED_RASTER_STREAM_H

/* Keys per work-item of visibility_clear_lines: 32 lines of 8 keys. */
#define CLVIS_CLEAR_RUN 256

#ifdef __OPENCL_C_VERSION__
/* Whether p starts a 64-byte line: the vector stores below need it (OpenCL buffers start at
   CL_DEVICE_MEM_BASE_ADDR_ALIGN, at least 128 bytes on PoCL; a wrapped sub-buffer may not). */
static inline int clvis_stream_aligned(__global const ulong* p) { return ((ulong)p & 63ul) == 0ul; }

/* Writes the 8 keys of the line at p (clvis_stream_aligned), streamed when `stream`. */
static inline void clvis_stream_line(__global ulong* p, ulong8 keys, int stream)
{
#ifdef CLVIS_STREAM
    if (stream) {
        __builtin_nontemporal_store(keys, (__global ulong8*)p);
        return;
    }
#endif
    vstore8(keys, 0, p);
}

/* After a work-item's last streamed line: non-temporal stores are weakly ordered on x86, and an
   sfence orders them before the stores that end the kernel (where the device reports it done).
   Other CPUs order them with the barriers their runtime already takes. */
static inline void clvis_stream_fence(void)
{
#if defined(CLVIS_STREAM) && (defined(__x86_64__) || defined(__i386__))
    __builtin_ia32_sfence();
#endif
}
#endif

#endif
