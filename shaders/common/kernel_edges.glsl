// Kernel renormalisation at the edges of a face, for a density estimate
// whose kernel is a disc in the tangent plane of the shading point (knn.comp;
// gather.comp has its own copy, per photon footprint, and the derivation:
// a kernel reaching past the line where this face meets a wall puts part of
// its mass where no photon of this face can be, so within one radius of the
// edge the estimate falls, to half at the edge itself; each contribution is
// divided by the share m of the kernel on this side of every edge found).
// For a disc of radius r centred at x and an edge at in-plane distance d,
// t = d / r and the mass beyond the line is, for the Epanechnikov kernel
// (2 / pi)(1 - rho^2) on the unit disc,
//   M(t) = 1/2 - (t (5 - 2 t^2) sqrt(1 - t^2) + 3 asin t) / (3 pi)
// (its integral over the segment x > t; M(0) = 1/2, M(1) = 0), and with
// several edges m = prod (1 - M(t_j)), bounded below by 1/4 (exact for one
// straight edge and at a right-angled corner). The edges are found as
// gather.comp finds them: PB_EDGE_RAYS rays in the tangent plane just above
// it, out to sqrt(2) times the reach; each face hit whose normal is more
// than 60 degrees from this face's gives one edge (its in-plane distance
// from the hit point and the face's plane). Include after common/scene.glsl.
#ifndef PB_KERNEL_EDGES_GLSL
#define PB_KERNEL_EDGES_GLSL

#define PB_EDGES_MAX 4
#define PB_EDGES_MIN_SHARE 0.25

float pb_edges_mass_beyond(float t) {
  if (t >= 1.0) return 0.0;
  t = max(t, 0.0);
  float s = sqrt(max(1.0 - t * t, 0.0));
  return 0.5 - (t * (5.0 - 2.0 * t * t) * s + 3.0 * asin(t)) / (3.0 * PB_PI);
}

// The edges of the face at x (geometric normal n) within `reach`: in-plane
// unit directions towards each and their distances; returns their number.
uint pb_edges_find(vec3 x, vec3 n, float reach, out vec3 edge_dir[PB_EDGES_MAX], out float edge_dist[PB_EDGES_MAX]) {
  uint edges = 0u;
  for (int k = 0; k < PB_EDGES_MAX; ++k) edge_dir[k] = vec3(0.0), edge_dist[k] = 0.0;
  if (!(reach > 0.0)) return 0u;
  vec3 an = abs(n);
  vec3 a = an.x <= an.y && an.x <= an.z ? vec3(1, 0, 0) : (an.y <= an.z ? vec3(0, 1, 0) : vec3(0, 0, 1));
  vec3 t = normalize(cross(n, a)), bt = cross(n, t);
  vec3 o = x + n * (1e-3 * reach);
  for (int k = 0; k < PB_EDGES_MAX; ++k) {
    float ang = float(k) * (2.0 * PB_PI / float(PB_EDGES_MAX));
    vec3 e = cos(ang) * t + sin(ang) * bt;
    float th, uh, vh;
    uint prim = pb_trace(o, e, 0.0, 1.4143 * reach, false, th, uh, vh);
    if (prim == PB_GPU_MISS) continue;
    pb_surface ws = pb_surface_from_hit(prim, uh, vh, e); // ws.ng faces x
    float cn = dot(ws.ng, n);
    if (cn > 0.5) continue;
    vec3 ew = -(ws.ng - n * cn);
    float le = length(ew);
    if (!(le > 1e-4)) continue;
    ew /= le;
    float d = th * dot(e, ws.ng) / dot(ew, ws.ng);
    if (!(d >= 0.0) || isinf(d)) continue;
    bool merged = false;
    for (uint j = 0u; j < edges; ++j)
      if (dot(edge_dir[j], ew) > 0.99) {
        edge_dist[j] = min(edge_dist[j], d);
        merged = true;
      }
    if (!merged) {
      edge_dir[edges] = ew;
      edge_dist[edges] = d;
      edges++;
    }
  }
  return edges;
}

// The share of a disc of radius r at x on this side of the edges.
float pb_edges_share(uint edges, float edge_dist[PB_EDGES_MAX], float r) {
  float share = 1.0;
  for (uint j = 0u; j < edges; ++j) share *= 1.0 - pb_edges_mass_beyond(edge_dist[j] / r);
  return max(share, PB_EDGES_MIN_SHARE);
}

#endif
