// Orthonormal basis around a unit normal (Duff et al. 2017, "Building an
// orthonormal basis, revisited"; the reference's v3_basis, the host's
// pb_basis_any in scene/tangents.h): the BSDF frame and the frame the packed
// photon record stores its footprint axes in (common/photon_pack.glsl).
#ifndef PB_BASIS_GLSL
#define PB_BASIS_GLSL
void pb_basis(vec3 n, out vec3 t, out vec3 b) {
  float s = n.z >= 0.0 ? 1.0 : -1.0; // copysignf(1, n.z): -0 counts as negative there
  if (n.z == 0.0 && floatBitsToUint(n.z) != 0u) s = -1.0;
  float a = -1.0 / (s + n.z);
  float c = n.x * n.y * a;
  t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
  b = vec3(c, s + n.y * n.y * a, -n.y);
}

#endif
