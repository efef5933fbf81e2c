/* xoshiro256** with splitmix64 seeding (Blackman and Vigna, "Scrambled linear pseudorandom number
 * generators", 2018): the same seed gives the same sequence on every platform. */
#include <math.h>

#include "core/rng.h"

static uint64_t splitmix64(uint64_t *x) {
    uint64_t z = (*x += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

void fr_rng_seed(fr_rng *rng, uint64_t seed) {
    for (int i = 0; i < 4; i++) rng->s[i] = splitmix64(&seed);
}

uint64_t fr_rng_next(fr_rng *rng) {
    uint64_t *s = rng->s;
    uint64_t result = rotl(s[1] * 5, 7) * 9, t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

double fr_rng_uniform(fr_rng *rng) { return (double)(fr_rng_next(rng) >> 11) * 0x1.0p-53; }

uint64_t fr_rng_below(fr_rng *rng, uint64_t n) {
    /* Rejection keeps it unbiased: draw again in the short top slice. */
    uint64_t limit = UINT64_MAX - UINT64_MAX % n, x;
    do x = fr_rng_next(rng);
    while (x >= limit);
    return x % n;
}

double fr_rng_normal(fr_rng *rng) {
    double u = fr_rng_uniform(rng), v = fr_rng_uniform(rng);
    return sqrt(-2.0 * log1p(-u)) * cos(6.283185307179586 * v);
}
