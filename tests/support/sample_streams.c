#include "sample_streams.h"

#include <math.h>

TestRng test_rng(uint64_t seed)
{
    TestRng rng = {seed * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull};
    return rng;
}

/* splitmix64 */
uint64_t test_rng_next(TestRng *rng)
{
    uint64_t z = (rng->state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

double test_rng_uniform(TestRng *rng)
{
    return (double)((test_rng_next(rng) >> 11) + 1) * 0x1.0p-53;
}

double test_rng_gaussian(TestRng *rng)
{
    double u = test_rng_uniform(rng), v = test_rng_uniform(rng);
    return sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
}

double test_pareto(TestRng *rng, double alpha)
{
    return pow(test_rng_uniform(rng), -1.0 / alpha);
}

double test_spiky(TestRng *rng, double spike, double p)
{
    return test_rng_uniform(rng) < p ? spike : 1.0;
}
