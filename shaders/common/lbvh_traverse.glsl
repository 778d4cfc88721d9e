// The photon LBVH's traversal for a point query (seed 000 6.3): the leaves
// whose boxes contain x, one per call, in left-to-right (Morton) order, so
// that the photons are visited, and their contributions summed, in the
// order of the sorted map. Each node holds both children's boxes: a node is
// fetched once, both boxes tested, the right child deferred on a short
// stack (one entry per level; a leaf is deferred as the address of its
// entry, node << 1 | 1). Include after declaring `lnodes4` (the nodes),
// `photons4` (the sorted photons) and `info` (pb_gpu_lbvh_info); start with
// pb_lbvh_begin(). Nodes and photons are read as uvec4 (a child entry is 2,
// a photon 3): llvmpipe turns each buffer load whose address differs between
// lanes into a loop over the lanes, one per load instruction, so a struct
// read member by member (16 loads for a photon) costs several times 6.
#ifndef PB_LBVH_TRAVERSE_GLSL
#define PB_LBVH_TRAVERSE_GLSL
#include "common/photon_pack.glsl"

uint pb_lt_stack[PB_LBVH_STACK];
uint pb_lt_sp;
uint pb_lt_node; // next node to open, or PB_LBVH_NONE: pop

void pb_lbvh_begin() {
  pb_lt_sp = 0u;
  pb_lt_node = info.root;
}

// Child `side` of `node`: its box (lo_ref.xyz, hi_count.xyz as float bits),
// reference (lo_ref.w) and photon count (hi_count.w).
struct pb_lbvh_entry {
  uvec4 lo_ref, hi_count;
};
pb_lbvh_entry pb_lbvh_child(uint node, uint side) {
  uint at = node * 4u + side * 2u;
  return pb_lbvh_entry(lnodes4[at], lnodes4[at + 1u]);
}
bool pb_lbvh_inside(vec3 x, pb_lbvh_entry c) {
  return all(greaterThanEqual(x, uintBitsToFloat(c.lo_ref.xyz))) && all(lessThanEqual(x, uintBitsToFloat(c.hi_count.xyz)));
}

// Sorted photon i: the 48-byte record (shared/pb_photon.h,
// pb_gpu_photon_packed), decoded by common/photon_pack.glsl.
pb_gpu_photon pb_lbvh_photon(uint i) {
  uint at = PB_PHOTON_PACKED_WORDS4 * i;
  return pb_photon_unpack(photons4[at], photons4[at + 1u], photons4[at + 2u]);
}

// The next leaf containing x: its first sorted photon and photon count;
// false when there is none left.
bool pb_lbvh_next_leaf(vec3 x, out uint first, out uint count) {
  for (;;) {
    if (pb_lt_node == PB_LBVH_NONE) {
      if (pb_lt_sp == 0u) return false;
      uint it = pb_lt_stack[--pb_lt_sp];
      if ((it & PB_LBVH_LEAF) != 0u) {
        pb_lbvh_entry c = pb_lbvh_child((it & ~PB_LBVH_LEAF) >> 1, it & 1u);
        first = c.lo_ref.w & ~PB_LBVH_LEAF;
        count = c.hi_count.w;
        return true;
      }
      pb_lt_node = it;
    }
    uint node = pb_lt_node;
    pb_lt_node = PB_LBVH_NONE;
    pb_lbvh_entry c0 = pb_lbvh_child(node, 0u), c1 = pb_lbvh_child(node, 1u);
    if (pb_lbvh_inside(x, c1)) {
      if (pb_lt_sp < PB_LBVH_STACK)
        pb_lt_stack[pb_lt_sp++] = (c1.lo_ref.w & PB_LBVH_LEAF) != 0u ? (PB_LBVH_LEAF | (node << 1) | 1u) : c1.lo_ref.w;
      else
        atomicAdd(info.stack_overflow, 1u);
    }
    if (pb_lbvh_inside(x, c0)) {
      if ((c0.lo_ref.w & PB_LBVH_LEAF) != 0u) {
        first = c0.lo_ref.w & ~PB_LBVH_LEAF;
        count = c0.hi_count.w;
        return true;
      }
      pb_lt_node = c0.lo_ref.w;
    }
  }
}

#endif
