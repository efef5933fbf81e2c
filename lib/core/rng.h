/* A seeded pseudo-random generator with explicit state (no global state, no rand()):
 * xoshiro256** (Blackman and Vigna 2018) seeded through splitmix64. Internal. */
#ifndef FR_CORE_RNG_H
#define FR_CORE_RNG_H

#include <stdint.h>

typedef struct fr_rng {
    uint64_t s[4];
} fr_rng;

void fr_rng_seed(fr_rng *rng, uint64_t seed);
uint64_t fr_rng_next(fr_rng *rng);
/* Uniform in [0, 1) with 53 random bits. */
double fr_rng_uniform(fr_rng *rng);
/* Uniform integer in [0, n) (n >= 1). */
uint64_t fr_rng_below(fr_rng *rng, uint64_t n);
/* Standard normal (Box-Muller; one of the pair is discarded, so the sequence is simple to replay). */
double fr_rng_normal(fr_rng *rng);

#endif
