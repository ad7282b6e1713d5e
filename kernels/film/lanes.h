/* Lanes: lets one piece of shared code (C11 and OpenCL C) work on one value
 * or on EST_VECTOR_WIDTH values at once.
 *
 * With EST_VECTOR_WIDTH 1 (the default, and always on the host) the lane
 * types are the scalar types; in an OpenCL kernel built with
 * -DEST_VECTOR_WIDTH=N (2, 4, 8 or 16) they are OpenCL vectors, one lane per
 * pixel. Every operation below acts on each lane alone and rounds exactly as
 * the scalar operation does, so a lane of the vector code and the scalar code
 * give the same bits.
 *
 *   est_float, est_int, est_uint, est_long, est_ulong  lane types
 *   est_mask   result of comparing est_float, est_int or est_uint lanes
 *   est_lmask  result of comparing est_long or est_ulong lanes
 *   EST_SELECT(mask, a, b)  per lane: mask ? a : b (a, b of one lane type; a
 *              mask from a comparison, or masks combined with & | and !;
 *              never ~ or arithmetic on masks: a true scalar mask is 1, a
 *              true vector mask -1)
 *   EST_FLOATS(x), EST_INTS(x), EST_ULONGS(x)  a scalar in every lane
 *   conversions and bit casts: see the macro names
 * A uniform condition (the same in every lane: a plain int) uses ordinary
 * `if` and `?:`. */
#ifndef KERNELS_LANES_H
#define KERNELS_LANES_H

#include "../common/compat.h"

#ifndef EST_VECTOR_WIDTH
#define EST_VECTOR_WIDTH 1
#endif

#define EST_PASTE_(a, b) a##b
#define EST_PASTE(a, b) EST_PASTE_(a, b)

#if EST_VECTOR_WIDTH == 1

typedef float est_float;
typedef int32_t est_int;
typedef uint32_t est_uint;
typedef int64_t est_long;
typedef uint64_t est_ulong;
typedef int32_t est_mask;
typedef int32_t est_lmask;

#define EST_SELECT(mask, a, b) ((mask) ? (a) : (b))
#define EST_FLOATS(x) ((float)(x))
#define EST_INTS(x) ((int32_t)(x))
#define EST_ULONGS(x) ((uint64_t)(x))
#define EST_FLOAT_BITS(x) float_bits(x)
#define EST_FLOAT_FROM_BITS(x) float_from_bits(x)
#define EST_INT_FROM_UINT(x) ((int32_t)(x))
#define EST_UINT_FROM_INT(x) ((uint32_t)(x))
#define EST_LONG_FROM_ULONG(x) ((int64_t)(x))
#define EST_FLOAT_FROM_INT(x) ((float)(x))
/* Rounds toward zero, as a C cast. */
#define EST_INT_FROM_FLOAT(x) ((int32_t)(x))
/* Correctly rounded (to nearest, ties to even) in C and in OpenCL. */
#define EST_FLOAT_FROM_ULONG(x) ((float)(x))
#define EST_UINT_FROM_ULONG(x) ((uint32_t)(x))
#define EST_ULONG_FROM_INT(x) ((uint64_t)(x))

#else /* OpenCL vectors */

#ifndef __OPENCL_C_VERSION__
#error "EST_VECTOR_WIDTH > 1 needs OpenCL C"
#endif
#if EST_VECTOR_WIDTH != 2 && EST_VECTOR_WIDTH != 4 && EST_VECTOR_WIDTH != 8 && EST_VECTOR_WIDTH != 16
#error "EST_VECTOR_WIDTH must be 1, 2, 4, 8 or 16"
#endif

typedef EST_PASTE(float, EST_VECTOR_WIDTH) est_float;
typedef EST_PASTE(int, EST_VECTOR_WIDTH) est_int;
typedef EST_PASTE(uint, EST_VECTOR_WIDTH) est_uint;
typedef EST_PASTE(long, EST_VECTOR_WIDTH) est_long;
typedef EST_PASTE(ulong, EST_VECTOR_WIDTH) est_ulong;
typedef EST_PASTE(int, EST_VECTOR_WIDTH) est_mask;
typedef EST_PASTE(long, EST_VECTOR_WIDTH) est_lmask;

/* OpenCL's ?: with a vector condition is select(b, a, mask); written as ?:
 * the compiler sees an instruction, not a library call, from the start. */
#define EST_SELECT(mask, a, b) ((mask) ? (a) : (b))
#define EST_FLOATS(x) ((est_float)(x))
#define EST_INTS(x) ((est_int)(x))
#define EST_ULONGS(x) ((est_ulong)(x))
#define EST_FLOAT_BITS(x) EST_PASTE(as_uint, EST_VECTOR_WIDTH)(x)
#define EST_FLOAT_FROM_BITS(x) EST_PASTE(as_float, EST_VECTOR_WIDTH)(x)
#define EST_INT_FROM_UINT(x) EST_PASTE(as_int, EST_VECTOR_WIDTH)(x)
#define EST_UINT_FROM_INT(x) EST_PASTE(as_uint, EST_VECTOR_WIDTH)(x)
#define EST_LONG_FROM_ULONG(x) EST_PASTE(as_long, EST_VECTOR_WIDTH)(x)
#define EST_FLOAT_FROM_INT(x) EST_PASTE(convert_float, EST_VECTOR_WIDTH)(x)
#define EST_INT_FROM_FLOAT(x) EST_PASTE(convert_int, EST_VECTOR_WIDTH)(x)
#define EST_FLOAT_FROM_ULONG(x) EST_PASTE(convert_float, EST_VECTOR_WIDTH)(x)
/* Integer conversions between lane widths (values in range) */
#define EST_UINT_FROM_ULONG(x) EST_PASTE(convert_uint, EST_VECTOR_WIDTH)(x)
#define EST_ULONG_FROM_INT(x) EST_PASTE(convert_ulong, EST_VECTOR_WIDTH)(x)

#endif

/* The per-pixel functions: always inlined in kernels, so that with M a
 * compile-time constant every loop unrolls and every array index is a
 * constant (the arrays then live in registers). */
#ifdef __OPENCL_C_VERSION__
#define EST_INLINE static inline __attribute__((always_inline))
#else
#define EST_INLINE static inline
#endif

/* Full unrolling where the trip count is a compile-time constant: in
 * kernels for M (EST_SETS) up to EST_UNROLL_MAX_SETS. Past that the values
 * no longer fit in registers anyway and unrolled code takes minutes to
 * compile. Nothing on the host. */
#ifndef EST_UNROLL_MAX_SETS
#define EST_UNROLL_MAX_SETS 32
#endif
#if defined(__OPENCL_C_VERSION__) && defined(EST_SETS) && EST_SETS <= EST_UNROLL_MAX_SETS
#define EST_UNROLL _Pragma("clang loop unroll(full)")
#else
#define EST_UNROLL
#endif

#endif /* KERNELS_LANES_H */
