/* Seeds of the synthetic data's independent streams (subject k of a data set, photo i of a
 * subject, the albedo of a subject, ...): two rounds of splitmix64's finalizer over the
 * parent seed and the index, so neighbouring indices give unrelated streams. */
#include "synth/synth.h"

uint64_t fr_seed_mix(uint64_t seed, uint64_t index) {
    uint64_t z = seed ^ (index * 0xd1b54a32d192ed03ull) ^ 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    z += index + 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
