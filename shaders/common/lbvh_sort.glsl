// The GPU radix sort's kernels (src/render/photon/lbvh_sort.c; the state and the
// constants are in shared/pb_lbvh.h). Each shaders/lbvh_sort_*.comp includes
// this file and calls one function; lbvh_sort_downsweep_sg defines
// PB_SORT_SUBGROUPS and ranks with subgroup operations, the others use only
// workgroup barriers and shared-memory atomics (the portable path: devices
// without subgroup operations, and the tests of both paths on one device).
//
// Costs that shaped the kernels, measured on lavapipe (llvmpipe runs a
// subgroup of 8 lanes as one SIMD vector and every buffer or shared access,
// ballot and shuffle as a loop over the lanes; bench/README.md): a
// workgroup barrier costs about as much as two memory accesses per
// invocation, a 4-component load about 0.4 of four 1-component ones, nine
// ballots about twice as much as seven shuffles, while a subgroup barrier is
// free (one vector is one subgroup).
//
// A tile is PB_SORT_TILE consecutive keys, one workgroup's. Stability: the
// downsweep writes every digit's keys of a tile in their order in the tile,
// and the tiles' runs in tile order, so each pass is stable and the passes
// together sort by the whole key (LSD), equal keys in their input order.
#ifndef PB_LBVH_SORT_GLSL
#define PB_LBVH_SORT_GLSL

layout(std430, set = 0, binding = PB_SORT_BIND_STATE) buffer SortState { pb_gpu_sort_state st; };
layout(std430, set = 0, binding = PB_SORT_BIND_KEYS) buffer SortKeys { uint keys[]; };   // 2 x capacity (ping-pong)
layout(std430, set = 0, binding = PB_SORT_BIND_VALS) buffer SortVals { uint vals[]; };   // 2 x capacity
layout(std430, set = 0, binding = PB_SORT_BIND_HIST) buffer SortHist { uint hist[]; };   // radix x tiles, digit-major
layout(std430, set = 0, binding = PB_SORT_BIND_COUNT_SRC) readonly buffer SortCount { uint count_src[]; };
layout(std430, set = 0, binding = PB_SORT_BIND_KEYS4) readonly buffer SortKeys4 { uvec4 keys4[]; }; // binding 1 again
layout(std430, set = 0, binding = PB_SORT_BIND_VALS4) readonly buffer SortVals4 { uvec4 vals4[]; }; // binding 2 again
layout(push_constant) uniform SortPush { pb_gpu_sort_push pc; };

const uint PB_SORT_WG = PB_GPU_WORKGROUP;

// Workgroup index in a grid folded into x and y (pb_gpu_dispatch_indirect).
uint pb_sort_group() { return gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x; }
// This pass's digits: 1 << pc.bits of them (at most PB_SORT_RADIX on the
// workgroup paths, PB_SORT_MAX_RADIX on the serial one; lbvh_sort.c).
uint pb_sort_radix() { return 1u << pc.bits; }
uint pb_sort_digit(uint key) { return (key >> pc.shift) & (pb_sort_radix() - 1u); }

#ifdef PB_SORT_SUBGROUPS
// The host takes this path only where gl_SubgroupSize is 8..64 and divides
// the workgroup (lbvh_sort.c), so there are at most 8 full subgroups, and a
// lane mask fits in .xy of a ballot.
const uint PB_SORT_MAX_SUBGROUPS = PB_GPU_WORKGROUP / 8u;
const uint PB_SORT_NO_DIGIT = PB_SORT_RADIX; // invalid lanes: matches no digit

// The lanes of the subgroup whose digit equals d (d == PB_SORT_NO_DIGIT on
// lanes without a key; warp-level multisplit, Ashkiani et al. 2016,
// Adinets & Merrill 2022 "Onesweep" 3.2). Subgroups of 8 compare with the
// seven other lanes (7 shuffles), larger ones take one ballot per digit bit
// (8 ballots, fewer than S - 1 shuffles).
uvec2 pb_sort_peers(uint d) {
  uint S = gl_SubgroupSize;
  if (S <= 8u) {
    uint m = 0u;
    for (uint k = 0u; k < S; ++k) m |= subgroupShuffle(d, k) == d ? (1u << k) : 0u;
    return uvec2(d == PB_SORT_NO_DIGIT ? 0u : m, 0u);
  }
  uvec4 m = subgroupBallot(d != PB_SORT_NO_DIGIT);
  for (uint b = 0u; b < PB_SORT_RADIX_BITS; ++b) {
    bool bit = ((d >> b) & 1u) != 0u;
    uvec4 v = subgroupBallot(bit);
    m &= bit ? v : ~v;
  }
  return m.xy;
}
uint pb_sort_popc(uvec2 m) { return bitCount(m.x) + bitCount(m.y); }
// Set bits of m on lanes below `lane`.
uint pb_sort_below(uvec2 m, uint lane) {
  return lane < 32u ? bitCount(m.x & ((1u << lane) - 1u)) : bitCount(m.x) + bitCount(m.y & ((1u << (lane - 32u)) - 1u));
}
// The highest lane of m.
uint pb_sort_last(uvec2 m) { return m.y != 0u ? 32u + uint(findMSB(m.y)) : uint(findMSB(m.x)); }
#endif

// ---- setup (one workgroup): key count, tile grid, spine grid, totals ----
void pb_sort_setup() {
  uint l = gl_LocalInvocationID.x;
  for (uint i = l; i < PB_SORT_MAX_PASSES * PB_SORT_MAX_RADIX; i += PB_SORT_WG) st.totals[i] = 0u;
  if (l != 0u) return;
  uint n = min(count_src[pc.count_word], pc.capacity);
  uint tiles = (n + pc.tile - 1u) / pc.tile;
  uint x = min(tiles, pc.max_groups_x);
  uint groups = (tiles + PB_SORT_WG - 1u) / PB_SORT_WG;
  st.count = n;
  st.tiles = tiles;
  st.tile_args = uint[4](x, x == 0u ? 1u : (tiles + x - 1u) / x, 1u, 0u);
  st.serial_args = uint[4](groups, 1u, 1u, 0u); // tiles / 64 < 2^32 / 2^16 <= the x limit's minimum
  // At most PB_SORT_RADIX digits a workgroup: each costs its invocations
  // ~PB_SORT_WG + 2 loop iterations, and llvmpipe cuts a SIMD vector's
  // loops short after 65535 iterations in all (1024 digits of one tile
  // left 10-bit sorts of <= 4096 keys unsorted).
  uint dpw = 1u, radix = pb_sort_radix(); // the widest pass's (the host's pc.bits for the setup)
  while (dpw < min(radix, PB_SORT_RADIX) && dpw * tiles < PB_SORT_SPINE_MIN) dpw *= 2u;
  st.spine_digits = dpw;
  st.spine_args = uint[4](radix / dpw, 1u, 1u, 0u); // narrower passes: the groups past their digits return
}

// ---- upsweep: the digit counts of one tile -> hist[digit * tiles + tile],
// and the pass's digit totals (global atomics, one per digit and tile).
// Shared atomics on one histogram, four keys per load (the tile's keys
// start at a multiple of 4: the host pads the capacity to one). ----
shared uint s_up[PB_SORT_RADIX];

void pb_sort_upsweep() {
  uint tile = pb_sort_group();
  if (tile >= st.tiles) return; // uniform in the workgroup
  uint l = gl_LocalInvocationID.x, n = st.count, base = tile * PB_SORT_TILE;
  for (uint d = l; d < PB_SORT_RADIX; d += PB_SORT_WG) s_up[d] = 0u;
  barrier();
  for (uint r = 0u; r < PB_SORT_KPT / 4u; ++r) {
    uint i = base + 4u * (r * PB_SORT_WG + l);
    if (i >= n) break;
    uvec4 k = keys4[(pc.src + i) / 4u];
    atomicAdd(s_up[pb_sort_digit(k.x)], 1u);
    if (i + 1u < n) atomicAdd(s_up[pb_sort_digit(k.y)], 1u);
    if (i + 2u < n) atomicAdd(s_up[pb_sort_digit(k.z)], 1u);
    if (i + 3u < n) atomicAdd(s_up[pb_sort_digit(k.w)], 1u);
  }
  barrier();
  for (uint d = l; d < pb_sort_radix(); d += PB_SORT_WG) {
    uint c = s_up[d];
    hist[d * st.tiles + tile] = c;
    if (c != 0u) atomicAdd(st.totals[pc.pass * PB_SORT_MAX_RADIX + d], c);
  }
}

// ---- spine: hist[d * tiles + t] <- first output position of digit d's keys
// of tile t (the keys of lower digits, plus digit d's keys in tiles < t).
// Workgroup w scans digits w * spine_digits ... in order. ----
shared uint s_spine[PB_SORT_WG];
shared uint s_spine_base;

void pb_sort_spine() {
  uint dpw = st.spine_digits, d0 = pb_sort_group() * dpw;
  if (d0 >= pb_sort_radix()) return;
  uint l = gl_LocalInvocationID.x, tiles = st.tiles;
  uint row = pc.pass * PB_SORT_MAX_RADIX;
  uint below = 0u;
  for (uint k = l; k < d0; k += PB_SORT_WG) below += st.totals[row + k];
  s_spine[l] = below;
  barrier();
  if (l == 0u) {
    uint b = 0u;
    for (uint k = 0u; k < PB_SORT_WG; ++k) b += s_spine[k];
    s_spine_base = b;
  }
  barrier();
  uint chunk = (tiles + PB_SORT_WG - 1u) / PB_SORT_WG;
  uint t0 = min(l * chunk, tiles), t1 = min(t0 + chunk, tiles);
  for (uint d = d0; d < d0 + dpw; ++d) {
    uint sum = 0u;
    for (uint t = t0; t < t1; ++t) sum += hist[d * tiles + t];
    s_spine[l] = sum;
    barrier();
    if (l == 0u) {
      uint run = s_spine_base;
      for (uint k = 0u; k < PB_SORT_WG; ++k) {
        uint c = s_spine[k];
        s_spine[k] = run;
        run += c;
      }
      s_spine_base = run;
    }
    barrier();
    uint run = s_spine[l];
    for (uint t = t0; t < t1; ++t) {
      uint c = hist[d * tiles + t];
      hist[d * tiles + t] = run;
      run += c;
    }
    barrier(); // s_spine is reused by the next digit
  }
}

// ---- downsweep: stable rank within the tile, scatter to hist's position ----
#ifdef PB_SORT_SUBGROUPS
// Per-subgroup digit counts, then each subgroup's first output position per
// digit. No workgroup barrier between the rounds: each subgroup ranks a
// contiguous chunk on its own.
shared uint s_down[PB_SORT_MAX_SUBGROUPS * PB_SORT_RADIX];

void pb_sort_downsweep() {
  uint tile = pb_sort_group();
  if (tile >= st.tiles) return; // uniform in the workgroup
  uint l = gl_LocalInvocationID.x, n = st.count, base = tile * PB_SORT_TILE;
  uint sg = gl_SubgroupID, lane = gl_SubgroupInvocationID, S = gl_SubgroupSize, NS = gl_NumSubgroups;
  for (uint i = l; i < NS * PB_SORT_RADIX; i += PB_SORT_WG) s_down[i] = 0u;
  barrier();
  // Each subgroup ranks a contiguous chunk, S keys per round: the rank of a
  // key is the number of keys with its digit earlier in the chunk (earlier
  // rounds: the running count; this round: peers on lower lanes).
  uint chunk = base + sg * S * PB_SORT_KPT;
  uint kreg[PB_SORT_KPT], oreg[PB_SORT_KPT]; // key; rank << 8 | digit
  for (uint r = 0u; r < PB_SORT_KPT; ++r) {
    uint i = chunk + r * S + lane;
    bool valid = i < n;
    uint key = valid ? keys[pc.src + i] : 0u;
    uint d = valid ? pb_sort_digit(key) : PB_SORT_NO_DIGIT;
    uvec2 peers = pb_sort_peers(d);
    uint slot = sg * PB_SORT_RADIX + (d & (PB_SORT_RADIX - 1u));
    uint prior = valid ? s_down[slot] : 0u;
    subgroupBarrier();
    if (valid && pb_sort_last(peers) == lane) s_down[slot] = prior + pb_sort_popc(peers);
    subgroupBarrier();
    kreg[r] = key;
    oreg[r] = ((prior + pb_sort_below(peers, lane)) << 8) | (d & (PB_SORT_RADIX - 1u));
  }
  barrier();
  for (uint d = l; d < pb_sort_radix(); d += PB_SORT_WG) {
    uint run = hist[d * st.tiles + tile];
    for (uint s = 0u; s < NS; ++s) {
      uint c = s_down[s * PB_SORT_RADIX + d];
      s_down[s * PB_SORT_RADIX + d] = run;
      run += c;
    }
  }
  barrier();
  for (uint r = 0u; r < PB_SORT_KPT; ++r) {
    uint i = chunk + r * S + lane;
    if (i >= n) continue;
    uint dst = s_down[sg * PB_SORT_RADIX + (oreg[r] & 0xffu)] + (oreg[r] >> 8);
    keys[pc.dst + dst] = kreg[r];
    vals[pc.dst + dst] = vals[pc.src + i];
  }
}
#else
// Rounds of one key per invocation: a bit per invocation in its digit's mask
// (two alternating mask sets, so that a round's clearing never meets the
// next round's setting), the rank from the bits below, a running count per
// digit that starts at hist's position.
const uint PB_SORT_WORDS = PB_GPU_WORKGROUP / 32u;
shared uint s_mask[2u * PB_SORT_RADIX * PB_SORT_WORDS];
shared uint s_run[PB_SORT_RADIX];

void pb_sort_downsweep() {
  uint tile = pb_sort_group();
  if (tile >= st.tiles) return; // uniform in the workgroup
  uint l = gl_LocalInvocationID.x, n = st.count, base = tile * PB_SORT_TILE;
  for (uint d = l; d < pb_sort_radix(); d += PB_SORT_WG) s_run[d] = hist[d * st.tiles + tile];
  for (uint i = l; i < 2u * PB_SORT_RADIX * PB_SORT_WORDS; i += PB_SORT_WG) s_mask[i] = 0u;
  barrier();
  uint word = l / 32u, bit = l % 32u;
  for (uint r = 0u; r < PB_SORT_KPT; ++r) {
    uint i = base + r * PB_SORT_WG + l;
    bool valid = i < n;
    uint key = valid ? keys[pc.src + i] : 0u;
    uint d = pb_sort_digit(key);
    uint m0 = ((r & 1u) * PB_SORT_RADIX + d) * PB_SORT_WORDS;
    if (valid) atomicOr(s_mask[m0 + word], 1u << bit);
    barrier();
    uint dst = 0u, total = 0u, below = 0u;
    if (valid) {
      for (uint w = 0u; w < PB_SORT_WORDS; ++w) {
        uint m = s_mask[m0 + w];
        total += bitCount(m);
        if (w < word) below += bitCount(m);
        else if (w == word) below += bitCount(m & ((1u << bit) - 1u));
      }
      dst = s_run[d] + below;
    }
    barrier();
    if (valid && below + 1u == total) { // the digit's last key of the round
      s_run[d] += total;
      for (uint w = 0u; w < PB_SORT_WORDS; ++w) s_mask[m0 + w] = 0u;
    }
    if (valid) {
      keys[pc.dst + dst] = key;
      vals[pc.dst + dst] = vals[pc.src + i];
    }
  }
}
#endif

// ---- serial variant (CPU devices): one invocation counts, and then ranks,
// a whole tile in order, with its digit counters in private memory, which a
// CPU implementation keeps in registers and the stack (llvmpipe: a gather
// or scatter of one vector, no loop over the lanes) while the wide kernels
// above pay a lane loop for every shared access. The tiles, hist and the
// spine are the same. ----
uint pb_sort_serial_tile() { return gl_GlobalInvocationID.x; }

void pb_sort_upsweep_serial() {
  uint tile = pb_sort_serial_tile();
  if (tile >= st.tiles) return;
  uint n = st.count, base = tile * PB_SORT_SERIAL_TILE, end = min(base + PB_SORT_SERIAL_TILE, n);
  uint R = pb_sort_radix(), h[PB_SORT_MAX_RADIX];
  for (uint d = 0u; d < R; ++d) h[d] = 0u;
  for (uint i = base; i < end; i += 4u) {
    uvec4 k = keys4[(pc.src + i) / 4u];
    h[pb_sort_digit(k.x)]++;
    if (i + 1u < end) h[pb_sort_digit(k.y)]++;
    if (i + 2u < end) h[pb_sort_digit(k.z)]++;
    if (i + 3u < end) h[pb_sort_digit(k.w)]++;
  }
  for (uint d = 0u; d < R; ++d) {
    hist[d * st.tiles + tile] = h[d];
    if (h[d] != 0u) atomicAdd(st.totals[pc.pass * PB_SORT_MAX_RADIX + d], h[d]);
  }
}

void pb_sort_downsweep_serial() {
  uint tile = pb_sort_serial_tile();
  if (tile >= st.tiles) return;
  uint n = st.count, base = tile * PB_SORT_SERIAL_TILE, end = min(base + PB_SORT_SERIAL_TILE, n);
  uint R = pb_sort_radix(), o[PB_SORT_MAX_RADIX]; // the next output position of each digit
  for (uint d = 0u; d < R; ++d) o[d] = hist[d * st.tiles + tile];
  uint i = base;
  for (; i + 4u <= end; i += 4u) {
    uvec4 k = keys4[(pc.src + i) / 4u], v = vals4[(pc.src + i) / 4u];
    uint d = pb_sort_digit(k.x), dst = o[d]++;
    keys[pc.dst + dst] = k.x;
    vals[pc.dst + dst] = v.x;
    d = pb_sort_digit(k.y), dst = o[d]++;
    keys[pc.dst + dst] = k.y;
    vals[pc.dst + dst] = v.y;
    d = pb_sort_digit(k.z), dst = o[d]++;
    keys[pc.dst + dst] = k.z;
    vals[pc.dst + dst] = v.z;
    d = pb_sort_digit(k.w), dst = o[d]++;
    keys[pc.dst + dst] = k.w;
    vals[pc.dst + dst] = v.w;
  }
  for (; i < end; ++i) {
    uint key = keys[pc.src + i], d = pb_sort_digit(key), dst = o[d]++;
    keys[pc.dst + dst] = key;
    vals[pc.dst + dst] = vals[pc.src + i];
  }
}

#endif
