/* Host/device compatibility: lets one header be valid C11 and OpenCL C 1.2.
 *
 * Shared code uses the stdint names, KERNEL_FN for its functions, and the
 * helpers below for bit casts and bit counts, which differ between the two
 * languages. Floating-point contraction is off on both sides (the host is
 * built with -ffp-contract=off) so that a*b+c rounds twice everywhere and
 * host and kernel agree bit for bit. */
#ifndef KERNELS_COMPAT_H
#define KERNELS_COMPAT_H

#ifdef __OPENCL_C_VERSION__

#pragma OPENCL FP_CONTRACT OFF

typedef ulong uint64_t;
typedef long int64_t;
typedef uint uint32_t;
typedef int int32_t;
typedef uchar uint8_t;

#define KERNEL_FN static inline
#define GLOBAL __global
/* Rare paths kept out of line, so they do not bloat the hot loop (PoCL
 * inlines every function anyway: loops over all sums of a pixel are also
 * kept rolled, KERNEL_NO_UNROLL, or they would grow the path tracer's loop
 * by their M * 3 copies and slow it by 15%). */
#define KERNEL_COLD_FN static __attribute__((noinline))
#define KERNEL_NO_UNROLL _Pragma("unroll 1")

#define float_bits(x) as_uint(x)
#define float_from_bits(x) as_float(x)
#define abs_float(x) fabs(x)
/* OpenCL defines clz(0) as the bit width; callers never pass 0 anyway. */
#define leading_zeros64(x) ((int)clz(x))
/* OpenCL 1.2 has no ctz: the bits below the lowest one, counted. x != 0. */
#define trailing_zeros64(x) ((int)popcount(((x) & (0 - (x))) - 1))
#define count_bits32(x) ((int)popcount((uint)(x)))

#else /* host C11 */

#include <stdint.h>
#include <string.h>
#include <math.h>

#define KERNEL_FN static inline
#define GLOBAL
#define KERNEL_COLD_FN static __attribute__((noinline))
#define KERNEL_NO_UNROLL

KERNEL_FN uint32_t float_bits(float x)
{
    uint32_t bits;
    memcpy(&bits, &x, sizeof bits);
    return bits;
}

KERNEL_FN float float_from_bits(uint32_t bits)
{
    float x;
    memcpy(&x, &bits, sizeof x);
    return x;
}

#define abs_float(x) fabsf(x)
/* __builtin_clzll(0) and __builtin_ctzll(0) are undefined; callers never
 * pass 0. */
#define leading_zeros64(x) __builtin_clzll(x)
#define trailing_zeros64(x) __builtin_ctzll(x)
#define count_bits32(x) __builtin_popcount(x)

#endif

#endif /* KERNELS_COMPAT_H */
