/* An independent long-double evaluation of pbrt-v4's Perlin noise and its
 * procedural textures (dots, fbm, wrinkled, windy, marble), for tests of
 * kernels/tracing/texture.h.
 *
 * Written from the definitions (Perlin's "Improving Noise", SIGGRAPH 2002,
 * with pbrt-v4's choice of gradients; pbrt-v4's FBm, Turbulence and
 * textures), not from the shared code: gradients from a table of vectors,
 * the trilinear blend as a weighted sum over the cell's 8 corners, the
 * marble spline by Bernstein polynomials, long double throughout. The
 * permutation table is data, passed in (the test checks it against the
 * published one). log2 of the octave count is the one the renderer
 * defines: exact at powers of two and linear between. */
#ifndef TESTS_SUPPORT_PROCEDURAL_REFERENCE_H
#define TESTS_SUPPORT_PROCEDURAL_REFERENCE_H

#include <stdint.h>

long double ref_noise(const uint8_t permutation[256], long double x, long double y, long double z);

/* p in texture space; len2 the footprint's squared length there (0: none). */
long double ref_fbm(const uint8_t permutation[256], const long double p[3], long double len2, long double omega,
                    int octaves);
long double ref_turbulence(const uint8_t permutation[256], const long double p[3], long double len2, long double omega,
                           int octaves);
long double ref_windy(const uint8_t permutation[256], const long double p[3], long double len2);
void ref_marble(const uint8_t permutation[256], const long double p[3], long double len2, long double omega,
                int octaves, long double scale, long double variation, long double rgb[3]);

/* Whether (s, t) lies in a polka dot; *margin is |distance^2 - radius^2|
 * (0 when the cell has no dot), how far the point is from deciding the
 * other way. */
int ref_inside_dot(const uint8_t permutation[256], long double s, long double t, long double *margin);

#endif
