/* Scalar types and bit casts that OpenCL C and C++17 both accept, so the shared headers compile
   unchanged on the device and on the host (host tests check the code the kernels run). */
#ifndef CLVIS_SHARED_TYPES_H
#define CLVIS_SHARED_TYPES_H

#ifdef __OPENCL_C_VERSION__
#pragma OPENCL FP_CONTRACT OFF
typedef uint clvis_u32;
typedef int clvis_i32;
typedef ulong clvis_u64;
typedef long clvis_i64;
static inline clvis_u32 clvis_float_bits(float f) { return as_uint(f); }
static inline float clvis_bits_float(clvis_u32 u) { return as_float(u); }
/* A hint that the cache line holding address p is read soon: the CPU's prefetch where the host
   builds with CLVIS_PREFETCH (Device::Impl::cpu_hints, PoCL's clang), nothing elsewhere. */
#ifdef CLVIS_PREFETCH
#define CLVIS_PREFETCH_LINE(p) __builtin_prefetch((const void*)(ulong)(p))
#else
#define CLVIS_PREFETCH_LINE(p) ((void)0)
#endif
#else
#include <cstdint>
#include <cstring>
typedef std::uint32_t clvis_u32;
typedef std::int32_t clvis_i32;
typedef std::uint64_t clvis_u64;
typedef std::int64_t clvis_i64;
static inline clvis_u32 clvis_float_bits(float f) { clvis_u32 u; std::memcpy(&u, &f, 4); return u; }
static inline float clvis_bits_float(clvis_u32 u) { float f; std::memcpy(&f, &u, 4); return f; }
#endif

/* For hot helpers of the shared headers that take or return structs by value: PoCL keeps such
   a helper out of line and copies the structs through private memory per call, then reads them
   back with loads that straddle the copy's stores (docs/architecture.md, "Decisions", 5). */
#if defined(__OPENCL_C_VERSION__) || defined(__GNUC__)
#define CLVIS_ALWAYS_INLINE __attribute__((always_inline))
#define CLVIS_NOINLINE __attribute__((noinline))
#else
#define CLVIS_ALWAYS_INLINE
#define CLVIS_NOINLINE
#endif

/* Own vector structs: OpenCL's float3 is 16 bytes and C++ has none. */
typedef struct { float x, y; } clvis_vec2;
typedef struct { float x, y, z; } clvis_vec3;

#endif
