/* The numbers a sample draws, for each of its dimensions (the image
 * position, the lens, each bounce's light and BSDF choices): independent
 * uniform random numbers, or Owen-scrambled Sobol points (docs/sampling.md).
 * A value depends only on (seed, pixel, sample index, dimension) and the
 * number of sets M, never on how samples are batched or split among devices.
 * Integer-only, so host and kernels agree bit for bit.
 *
 * The Sobol samplers pad: each 1D or 2D dimension is its own (0,2)-sequence,
 * the first two Sobol dimensions, with an index shuffle and an Owen
 * scrambling of its own (Burley, "Practical Hash-based Owen Scrambling",
 * JCGT 2020). Both the shuffle and the scrambling are nested uniform
 * permutations: the first 2^k samples of a sequence are always an aligned
 * block of 2^k Sobol points, a (0,k,2)-net, so every 2D dimension is
 * stratified in every elementary interval at every power of two. */
#ifndef KERNELS_SAMPLER_H
#define KERNELS_SAMPLER_H

#include "rng.h"

#define SAMPLER_INDEPENDENT 0u
/* One scrambled sequence over all the samples of a pixel: sample s is its
 * point s, and its set s mod M holds every M-th point (the sets' means are
 * correlated). */
#define SAMPLER_SOBOL_PIXEL 1u
/* Each set its own, independently scrambled sequence: sample s is point
 * s / M of set s mod M's (the sets are independent randomized QMC
 * replicates, as median of means assumes). */
#define SAMPLER_SOBOL_SETS 2u
#define SAMPLER_COUNT 3u

typedef struct {
    uint64_t key;   /* independent: the sample's; Sobol: its sequence's */
    uint32_t index; /* Sobol: the sample's point in its sequence */
    uint32_t mode;  /* SAMPLER_* */
} SampleStream;

KERNEL_FN uint32_t reverse_bits32(uint32_t x)
{
    x = (x << 16) | (x >> 16);
    x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
    x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
    return ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
}

/* A hashed permutation of 32-bit words in which bit r of the result is bit
 * r of x flipped by a function of the bits below it and the seed (each
 * step only carries upward): on bit-reversed words, one draw of a nested
 * uniform (Owen) scrambling. Vegdahl's constants ("Building a better LK
 * hash", 2021), which improve on Laine and Karras's. */
KERNEL_FN uint32_t scramble_upward(uint32_t x, uint32_t seed)
{
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

/* Owen scrambling of a fraction's bits: bit r from the top flipped by a
 * function of the bits above it. */
KERNEL_FN uint32_t owen_scramble(uint32_t x, uint32_t seed)
{
    return reverse_bits32(scramble_upward(reverse_bits32(x), seed));
}

/* Sobol's second dimension, bit-reversed (bit r is the point's r-th bit
 * after the binary point): its generator matrix is Pascal's triangle mod 2,
 * so bit r is the parity of the index bits j with binomial(j, r) odd, the j
 * whose bits include r's (Lucas): a sum over supersets, five shift-and-xor
 * steps. The first dimension is the van der Corput sequence, the index
 * itself reversed. */
KERNEL_FN uint32_t sobol_second_reversed(uint32_t index)
{
    index ^= (index >> 1) & 0x55555555u;
    index ^= (index >> 2) & 0x33333333u;
    index ^= (index >> 4) & 0x0f0f0f0fu;
    index ^= (index >> 8) & 0x00ff00ffu;
    return index ^ ((index >> 16) & 0x0000ffffu);
}

KERNEL_FN float unit_from_bits(uint32_t x)
{
    return (float)(x >> 8) * (1.0f / 16777216.0f);
}

/* The stream of sample sample_index of pixel `pixel`, whose set is
 * sample_index mod set_count. */
KERNEL_FN SampleStream sample_stream(uint32_t mode, uint32_t seed, uint64_t pixel, uint64_t sample_index,
                                     uint32_t set_count)
{
    SampleStream s;
    s.mode = mode;
    if (mode == SAMPLER_INDEPENDENT) {
        s.key = rng_sample_key(seed, pixel, sample_index);
        s.index = 0u;
        return s;
    }
    uint64_t sequence = 0u, index = sample_index;
    if (mode == SAMPLER_SOBOL_SETS) {
        sequence = 1u + sample_index % set_count;
        index = sample_index / set_count;
    }
    /* Past 2^32 samples a sequence starts anew, scrambled afresh. */
    s.key = rng_sample_key(seed, pixel, (sequence << 32) ^ (index >> 32) ^ 0x5bd1e995u);
    s.index = (uint32_t)index;
    return s;
}

/* The stream of a light subpath: light subpaths land anywhere on the
 * image, so their numbers come from one sequence over the whole image
 * (point sample_index * image_pixels + pixel; with sobol-sets one such
 * sequence a set) rather than one a pixel: all the image's light subpaths
 * are then stratified together, as pbrt-v4's image-wide Sobol sampler
 * stratifies them, and a pixel's splats vary less. Independent numbers
 * stay the sample's own. */
KERNEL_FN SampleStream light_sample_stream(uint32_t mode, uint32_t seed, uint64_t pixel, uint64_t sample_index,
                                           uint32_t set_count, uint64_t image_pixels)
{
    if (mode == SAMPLER_INDEPENDENT)
        return sample_stream(mode, seed, pixel, sample_index, set_count);
    uint64_t sequence = 0u, index = sample_index;
    if (mode == SAMPLER_SOBOL_SETS) {
        sequence = 1u + sample_index % set_count;
        index = sample_index / set_count;
    }
    index = index * image_pixels + pixel;
    SampleStream s;
    s.mode = mode;
    /* The pixel key ~0 keeps these sequences apart from every pixel's. */
    s.key = rng_sample_key(seed, ~(uint64_t)0u, (sequence << 32) ^ (index >> 32) ^ 0x5bd1e995u);
    s.index = (uint32_t)index;
    return s;
}

/* One dimension's hash of the stream's key. */
KERNEL_FN uint64_t dimension_hash(const SampleStream *s, uint32_t dimension)
{
    return rng_mix(s->key ^ ((uint64_t)(dimension + 1u) * 0x9E3779B97F4A7C15ul));
}

/* The point of a Sobol sampler's stream in the dimension hashed to h: its
 * shuffled index's first two Sobol coordinates, each Owen-scrambled
 * (owen_scramble and the reversals of van der Corput's and
 * sobol_second_reversed's bits written out: each pair of reversals that
 * meets cancels). */
KERNEL_FN uint32_t sobol_point(const SampleStream *s, uint64_t h, uint32_t *second)
{
    uint32_t shuffled = reverse_bits32(scramble_upward(reverse_bits32(s->index), (uint32_t)h));
    *second = reverse_bits32(scramble_upward(sobol_second_reversed(shuffled), (uint32_t)rng_mix(h)));
    return reverse_bits32(scramble_upward(shuffled, (uint32_t)(h >> 32)));
}

/* The sample's number in dimension `dimension`, in [0, 1). */
KERNEL_FN float sample_1d(const SampleStream *s, uint32_t dimension)
{
    if (s->mode == SAMPLER_INDEPENDENT)
        return rng_uniform(s->key, dimension);
    uint32_t unused;
    return unit_from_bits(sobol_point(s, dimension_hash(s, dimension), &unused));
}

/* The sample's point in the 2D dimension that starts at `dimension` (the
 * independent sampler's dimensions `dimension` and `dimension` + 1). */
KERNEL_FN void sample_2d(const SampleStream *s, uint32_t dimension, float *u, float *v)
{
    if (s->mode == SAMPLER_INDEPENDENT) {
        *u = rng_uniform(s->key, dimension);
        *v = rng_uniform(s->key, dimension + 1u);
        return;
    }
    uint32_t second;
    *u = unit_from_bits(sobol_point(s, dimension_hash(s, dimension), &second));
    *v = unit_from_bits(second);
}

#endif
