/* Seed mixing shared by the renderers. */
#ifndef PB_CORE_MIX_H
#define PB_CORE_MIX_H

#include <stdint.h>

/* SplitMix64's step and finaliser (Steele, Lea & Flood 2014): well-spread
 * 64-bit values from consecutive inputs (per-thread streams, per-frame
 * seeds). */
static inline uint64_t pb_mix64(uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

#endif
