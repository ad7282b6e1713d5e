/* Counter-based random numbers: a value depends only on (seed, pixel, sample
 * index, dimension), never on how samples are batched into passes or split
 * among devices. Integer-only, so host and kernels agree. */
#ifndef KERNELS_RNG_H
#define KERNELS_RNG_H

#include "../common/compat.h"

/* splitmix64's finalizer: a bijective 64-bit mix. */
KERNEL_FN uint64_t rng_mix(uint64_t x)
{
    x ^= x >> 30;
    x *= 0xBF58476D1CE4E5B9ul;
    x ^= x >> 27;
    x *= 0x94D049BB133111EBul;
    x ^= x >> 31;
    return x;
}

/* The key of one sample of one pixel. */
KERNEL_FN uint64_t rng_sample_key(uint32_t seed, uint64_t pixel, uint64_t sample_index)
{
    uint64_t k = rng_mix((uint64_t)seed * 0x9E3779B97F4A7C15ul + 0x632BE59BD9B4E019ul);
    k = rng_mix(k ^ (pixel * 0xD1B54A32D192ED03ul + 0x8CB92BA72F3D8DD7ul));
    return rng_mix(k ^ (sample_index * 0xAEF17502108EF2D9ul + 0x2545F4914F6CDD1Dul));
}

/* Uniform in [0, 1) with 24 random bits, for dimension `dimension`. */
KERNEL_FN float rng_uniform(uint64_t key, uint32_t dimension)
{
    uint64_t x = rng_mix(key ^ ((uint64_t)(dimension + 1) * 0x9E3779B97F4A7C15ul));
    return (float)(uint32_t)(x >> 40) * (1.0f / 16777216.0f);
}

#endif
