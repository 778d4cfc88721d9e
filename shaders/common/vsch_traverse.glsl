// One photon through the view-sample cluster hierarchy (seed 004 4.3, 4.5,
// 4.6, 4.7), shared by vsch_count.comp (PB_VSCH_FILL undefined: counts the
// photon's list insertions and adds its trivially accepted and directional
// flux) and vsch_fill.comp (PB_VSCH_FILL: writes the same insertions as
// (node, photon) pairs; the traversal order is the same, so the k-th
// insertion of either is the same node). The includer defines
// void pb_vsch_list(uint g) (one insertion into node g's list).
//
// The paper's iterative traversal (4.3): a stack of child masks, one per
// level; "the first bit of the 32-bit child mask becomes the active node,
// and the bit is removed". Where the paper keeps a node key (5 bits per
// level), the stack here keeps each level's node coordinates: the dense
// levels are indexed by (x, y), the clusters of a tile by the rank of their
// slice in the tile's mask (the paper's compact list of the final level).
//
// The photon is the sphere of radius r around its position (4.3: "a
// spherical influence region"), in view space. At a node whose box it
// intersects:
//   rejected (4.5)  the angle between the photon's direction wi (unit,
//                   towards where it came from) and the cone axis exceeds
//                   pi/2 + alpha: no sample below has wi above its tangent
//                   plane;
//   enclosed        the box lies inside the sphere: the photon reaches every
//                   sample below and traversal stops there. Cluster-trivial
//                   (4.6): when the angle is below pi/2 - alpha every sample
//                   below faces it, and its irradiance E = Phi / (pi r^2)
//                   is added to the node (fixed point, PB_VSCH_TRIVIAL_WORDS)
//                   instead of a list; otherwise it goes into the node's
//                   list;
//   a cluster       intersected, not enclosed: into the cluster's list;
//   else            its occupied children are tested.
// Thin walls (derived; the paper's scenes have none): the sphere reaches
// through a wall to the other side, so a photon counts at a sample only on
// the sample's side (its face's normal n_p within 90 degrees of the
// sample's n_g, the gather's same-side test) and not beyond an edge of the
// sample's face where a wall stands (common/kernel_edges.glsl); vsch_shade
// tests both per sample. Here the photon's normal is tested against the
// node's cone as wi is: rejected where the angle exceeds pi/2 + alpha (no
// sample below is on its side), and the node is trivially accepted (or
// takes the bucket) only where every sample below passes both tests: the
// angle below pi/2 - alpha and no sample's edge within 2 r (node word 15;
// 2 r: the photon's disc reaches that far from a sample, so none of it is
// beyond an edge and no edge renormalisation is due). Otherwise an
// enclosed node's photon goes into its list (directional: the traversal
// descends, and at a cluster the photon is listed), shaded per sample.
// Caustic photons always go into lists (their own sum at shading).
// Directional (4.7, PB_VSCH_DIRECTIONAL): the other photons never go into
// lists; an enclosed node, or an intersected cluster, adds the photon's
// irradiance to the bucket of the octant of its view-space direction. The
// paper adds a partly covered cluster's photon in full ("when a photon is
// found to enclose a node, or intersect a leaf node, it adds its
// contribution"), which is right for photons much larger than a cluster
// (its radii: 0.2-5 m) but adds pi r^2 / (the cluster's area) too much
// light for photons smaller than one (our footprints). Derived here: the
// bucket gets E times phi, the share of the cluster's box that the
// sphere's bounding cube covers (the product over the box's axes of the
// covered fraction, axes thinner than r / 1000 counting 1), times pi / 4
// where two or more axes are cut (a disc covers pi / 4 of its square), so
// that the cluster's mean irradiance carries the photon's flux once.
#ifndef PB_VSCH_TRAVERSE_GLSL
#define PB_VSCH_TRAVERSE_GLSL

// 0: skip, 1: descend, 2: recorded (stop).
uint pb_vsch_visit(uint g, uint L, vec3 c, float r, vec3 wi, vec3 pn, vec3 wiv, bool caustic, vec3 E, float emax) {
  if (vd[pb_node_word(g, 7u)] == 0u) return 0u;
  // Every value a decision depends on is `precise` (no contraction into
  // fused multiply-adds): vsch_count and vsch_fill are separate modules,
  // and the compiler must make the same decisions in both, or a photon's
  // pairs would not fit the slots its count reserved.
  vec3 lo = pb_node_lo(g), hi = pb_node_hi(g);
  precise vec3 dq = c - clamp(c, lo, hi);
  precise float d2 = dot(dq, dq), r2 = r * r;
  if (d2 > r2) return 0u;
  float alpha = pb_node_alpha(g);
  vec3 axis = pb_node_axis(g, L);
  precise float ca = dot(wi, axis), cn = dot(pn, axis);
  precise float ang = acos(clamp(ca, -1.0, 1.0)), angn = acos(clamp(cn, -1.0, 1.0));
  if ((vp.flags & PB_VSCH_NO_CONE) == 0u && max(ang, angn) > 0.5 * PB_VSCH_PI + alpha) {
#ifndef PB_VSCH_FILL
    atomicAdd(vd[PB_VSCH_H_REJECTED], 1u);
#endif
    return 0u;
  }
  precise vec3 fa = max(abs(c - lo), abs(c - hi));
  precise float f2 = dot(fa, fa);
  bool enclosed = f2 <= r2;
  bool directional = (vp.flags & PB_VSCH_DIRECTIONAL) != 0u && !caustic;
  if (!enclosed && L != 0u) return 1u;
  // Every sample below on the photon's side, and none with an edge within
  // 2 r (above). The edge word is a float >= 0 (+inf: none), compared as
  // floats; both modules read the same word.
  precise float r2x = 2.0 * r;
  bool sided = angn < 0.5 * PB_VSCH_PI - alpha && uintBitsToFloat(vd[pb_node_word(g, 15u)]) > r2x;
  if (directional && !sided) {
    if (L != 0u) return 1u;
    pb_vsch_list(g);
    return 2u;
  }
  if (directional) {
#ifndef PB_VSCH_FILL
    float phi = 1.0;
    if (!enclosed) {
      uint cut = 0u;
      for (int k = 0; k < 3; ++k) {
        float ext = hi[k] - lo[k];
        if (ext <= 1e-3 * r) continue;
        float cov = (min(hi[k], c[k] + r) - max(lo[k], c[k] - r)) / ext;
        if (cov < 1.0) cut++;
        phi *= clamp(cov, 0.0, 1.0);
      }
      if (cut >= 2u) phi *= 0.25 * PB_VSCH_PI;
    }
    uint b = vp.dir_off + g * PB_VSCH_DIR_WORDS + pb_octant(wiv) * 6u;
    vec3 e = E * phi;
    pb_add64(b, pb_fixed(e.x, emax));
    pb_add64(b + 2u, pb_fixed(e.y, emax));
    pb_add64(b + 4u, pb_fixed(e.z, emax));
    atomicAdd(vd[PB_VSCH_H_DIRECTIONAL], 1u);
#endif
    return 2u;
  }
  if (enclosed && !caustic && sided && (vp.flags & PB_VSCH_NO_TRIVIAL) == 0u && ang < 0.5 * PB_VSCH_PI - alpha) {
#ifndef PB_VSCH_FILL
    uint b = vp.triv_off + g * PB_VSCH_TRIVIAL_WORDS;
    float le = dot(E, vec3(0.2126, 0.7152, 0.0722));
    vec3 wd = (wi + 1.0) * 0.5 * le;
    pb_add64(b, pb_fixed(E.x, emax));
    pb_add64(b + 2u, pb_fixed(E.y, emax));
    pb_add64(b + 4u, pb_fixed(E.z, emax));
    pb_add64(b + 6u, pb_fixed(wd.x, emax));
    pb_add64(b + 8u, pb_fixed(wd.y, emax));
    pb_add64(b + 10u, pb_fixed(wd.z, emax));
    pb_add64(b + 12u, pb_fixed(le, emax));
    atomicAdd(vd[PB_VSCH_H_TRIVIAL], 1u);
#endif
    return 2u;
  }
  pb_vsch_list(g);
  return 2u;
}

void pb_vsch_traverse(vec3 c, float r, vec3 wi, vec3 pn, vec3 wiv, bool caustic, vec3 E, float emax) {
  const uint top = PB_VSCH_LEVELS;
  uint mask[PB_VSCH_LEVELS + 1], cx[PB_VSCH_LEVELS + 1], cy[PB_VSCH_LEVELS + 1];
  uint nx = vd[PB_VSCH_H_NX + top], ny = vd[PB_VSCH_H_NY + top];
  for (uint y0 = 0u; y0 < ny; ++y0)
    for (uint x0 = 0u; x0 < nx; ++x0) {
      uint g = pb_level_node(top, x0, y0);
      if (pb_vsch_visit(g, top, c, r, wi, pn, wiv, caustic, E, emax) != 1u) continue;
      uint cur = top;
      mask[cur] = vd[pb_node_word(g, 6u)];
      cx[cur] = x0, cy[cur] = y0;
      while (cur <= top) {
        if (mask[cur] == 0u) {
          cur++;
          continue;
        }
        uint i = uint(findLSB(mask[cur]));
        mask[cur] &= mask[cur] - 1u;
        uint L = cur - 1u, cg, ccx = 0u, ccy = 0u;
        if (cur == 1u) {
          uint tg = pb_level_node(1u, cx[1], cy[1]);
          uint tm = vd[pb_node_word(tg, 6u)];
          cg = vd[pb_node_word(tg, 14u)] + uint(bitCount(tm & ((1u << i) - 1u)));
        } else {
          ccx = cx[cur] * PB_VSCH_BRANCH_X + (i % PB_VSCH_BRANCH_X);
          ccy = cy[cur] * PB_VSCH_BRANCH_Y + (i / PB_VSCH_BRANCH_X);
          cg = pb_level_node(L, ccx, ccy);
        }
        if (pb_vsch_visit(cg, L, c, r, wi, pn, wiv, caustic, E, emax) == 1u) {
          mask[L] = vd[pb_node_word(cg, 6u)];
          cx[L] = ccx, cy[L] = ccy;
          cur = L;
        }
      }
    }
}

#endif
