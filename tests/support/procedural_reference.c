#include "procedural_reference.h"

#include <math.h>

/* pbrt-v4's gradients, indexed by the low 4 bits of the hash: the 12 cube
 * edge directions, (1, 1, 0), (-1, 1, 0), (0, 1, -1), (0, -1, -1) twice. */
static const int gradients[16][3] = {
    {1, 1, 0}, {-1, 1, 0}, {1, -1, 0}, {-1, -1, 0}, {1, 0, 1}, {-1, 0, 1}, {1, 0, -1}, {-1, 0, -1},
    {0, 1, 1}, {0, -1, 1}, {0, 1, -1}, {0, -1, -1}, {1, 1, 0}, {-1, 1, 0}, {0, 1, -1}, {0, -1, -1},
};

static int hash3(const uint8_t p[256], long long x, long long y, long long z)
{
    int a = p[(int)(((x % 256) + 256) % 256)];
    int b = p[(int)(((a + y) % 256 + 256) % 256)];
    return p[(int)(((b + z) % 256 + 256) % 256)] & 15;
}

static long double fade(long double t)
{
    return t * t * t * (t * (t * 6 - 15) + 10);
}

long double ref_noise(const uint8_t permutation[256], long double x, long double y, long double z)
{
    long double cell[3] = {floorl(x), floorl(y), floorl(z)};
    long double d[3] = {x - cell[0], y - cell[1], z - cell[2]};
    long double sum = 0;
    for (int corner = 0; corner < 8; ++corner) {
        int o[3] = {corner & 1, (corner >> 1) & 1, (corner >> 2) & 1};
        const int *g = gradients[hash3(permutation, (long long)cell[0] + o[0], (long long)cell[1] + o[1],
                                       (long long)cell[2] + o[2])];
        long double weight = 1, dot = 0;
        for (int k = 0; k < 3; ++k) {
            long double f = fade(d[k]);
            weight *= o[k] ? f : 1 - f;
            dot += g[k] * (d[k] - o[k]);
        }
        sum += weight * dot;
    }
    return sum;
}

static long double noise_scaled(const uint8_t permutation[256], const long double p[3], long double lambda)
{
    return ref_noise(permutation, lambda * p[0], lambda * p[1], lambda * p[2]);
}

/* log2 exact at powers of two and linear between them. */
static long double log2_piecewise(long double x)
{
    int e;
    long double m = frexpl(x, &e); /* x = m 2^e, m in [0.5, 1) */
    return (e - 1) + (2 * m - 1);
}

static long double octave_count(long double len2, int octaves)
{
    if (!(len2 > 0))
        return octaves;
    long double n = -1 - log2_piecewise(len2) / 2;
    return n < 0 ? 0 : (n > octaves ? octaves : n);
}

static long double smooth_step(long double x, long double a, long double b)
{
    long double t = (x - a) / (b - a);
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    return t * t * (3 - 2 * t);
}

static const long double frequency = 1.99f; /* pbrt-v4's lacunarity, a float */

long double ref_fbm(const uint8_t permutation[256], const long double p[3], long double len2, long double omega,
                    int octaves)
{
    long double n = octave_count(len2, octaves), whole = floorl(n), sum = 0;
    for (int i = 0; i < (int)whole; ++i)
        sum += powl(omega, i) * noise_scaled(permutation, p, powl(frequency, i));
    return sum + powl(omega, whole) * smooth_step(n - whole, 0.3L, 0.7L) *
                     noise_scaled(permutation, p, powl(frequency, whole));
}

long double ref_turbulence(const uint8_t permutation[256], const long double p[3], long double len2, long double omega,
                           int octaves)
{
    long double n = octave_count(len2, octaves), whole = floorl(n), sum = 0;
    for (int i = 0; i < (int)whole; ++i)
        sum += powl(omega, i) * fabsl(noise_scaled(permutation, p, powl(frequency, i)));
    /* The fractional octave between its average 0.2 and its value; then
     * every octave from the fractional one on at the average (pbrt-v4). */
    long double w = smooth_step(n - whole, 0.3L, 0.7L);
    sum += powl(omega, whole) * ((1 - w) * 0.2L + w * fabsl(noise_scaled(permutation, p, powl(frequency, whole))));
    for (int i = (int)whole; i < octaves; ++i)
        sum += powl(omega, i) * 0.2L;
    return sum;
}

long double ref_windy(const uint8_t permutation[256], const long double p[3], long double len2)
{
    long double tenth[3] = {p[0] / 10, p[1] / 10, p[2] / 10};
    return fabsl(ref_fbm(permutation, tenth, len2 / 100, 0.5L, 3)) * ref_fbm(permutation, p, len2, 0.5L, 6);
}

void ref_marble(const uint8_t permutation[256], const long double p[3], long double len2, long double omega,
                int octaves, long double scale, long double variation, long double rgb[3])
{
    static const long double knots[9][3] = {{.58L, .58L, .6L}, {.58L, .58L, .6L}, {.58L, .58L, .6L},
                                            {.5L, .5L, .5L},   {.6L, .59L, .58L}, {.58L, .58L, .6L},
                                            {.58L, .58L, .6L}, {.2L, .2L, .33L},  {.58L, .58L, .6L}};
    long double q[3] = {scale * p[0], scale * p[1], scale * p[2]};
    long double marble = q[1] + variation * ref_fbm(permutation, q, scale * scale * len2, omega, octaves);
    long double t = (0.5L + 0.5L * sinl(marble)) * 6;
    int first = (int)floorl(t);
    first = first > 5 ? 5 : first;
    long double u = t - first, v = 1 - u;
    long double bernstein[4] = {v * v * v, 3 * u * v * v, 3 * u * u * v, u * u * u};
    for (int c = 0; c < 3; ++c) {
        rgb[c] = 0;
        for (int k = 0; k < 4; ++k)
            rgb[c] += 1.5L * bernstein[k] * knots[first + k][c];
    }
}

int ref_inside_dot(const uint8_t permutation[256], long double s, long double t, long double *margin)
{
    long double cs = floorl(s + 0.5L), ct = floorl(t + 0.5L);
    *margin = 0;
    if (!(ref_noise(permutation, cs + 0.5L, ct + 0.5L, 0.5L) > 0))
        return 0;
    /* pbrt-v4's constants are floats: the radius 0.35f, the shift 0.5f - 0.35f */
    long double radius = 0.35f, shift = 0.5f - 0.35f;
    long double centre_s = cs + shift * ref_noise(permutation, cs + 1.5L, ct + 2.8f, 0.5L);
    long double centre_t = ct + shift * ref_noise(permutation, cs + 4.5L, ct + 9.8f, 0.5L);
    long double d2 = (s - centre_s) * (s - centre_s) + (t - centre_t) * (t - centre_t);
    *margin = fabsl(d2 - radius * radius);
    return d2 < radius * radius;
}
