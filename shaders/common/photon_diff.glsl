// Photon differentials (seed 000 section 4; Igehy 1999, "Tracing Ray
// Differentials"). A photon carries dP = (dPu, dPv) and dD = (dDu, dDv), its
// position and direction differentiated by the two parameters of its last
// emission (light or diffuse re-emission), pre-scaled per seed 000 eq. 8 so
// that ONE global spacing Delta turns them into footprint semi-axes
// (Delta dPu, Delta dPv). Specular updates take the shading normal's
// derivative dN along dP (interpolated vertex normals; photon_trace.comp's
// pb_diff_dn), zero on flat-shaded triangles.
//
// Every division is guarded; pb_diff_guarded counts the guards hit by this
// invocation (the kernel adds it to the statistics once).
#ifndef PB_PHOTON_DIFF_GLSL
#define PB_PHOTON_DIFF_GLSL

uint pb_diff_guarded = 0u;

const float PB_DIFF_EPS = 1e-6;

// Keeps |x| >= eps with x's sign (0 counts as +).
float pb_guard_div(float x, float eps) {
  if (abs(x) >= eps) return x;
  pb_diff_guarded++;
  return x < 0.0 ? -eps : eps;
}

// Transfer (Igehy eq. 10-12): after travelling t along unit D to the plane
// through the hit with normal N,
//   dP' = (dP + t dD) - D ((dP + t dD).N) / (D.N)
// (the plane-projected offset: dP' lies in the tangent plane); dD unchanged.
void pb_diff_transfer(inout vec3 dPu, inout vec3 dPv, vec3 dDu, vec3 dDv, vec3 D, float t, vec3 N) {
  float dn = pb_guard_div(dot(D, N), PB_DIFF_EPS);
  vec3 a = dPu + t * dDu, b = dPv + t * dDv;
  dPu = a - D * (dot(a, N) / dn);
  dPv = b - D * (dot(b, N) / dn);
}

// Mirror reflection about N (Igehy eq. 14-15):
//   R = D - 2 (D.N) N,
//   dR = dD - 2 [(D.N) dN + (dD.N + D.dN) N];  dP unchanged.
void pb_diff_reflect(inout vec3 dDu, inout vec3 dDv, vec3 D, vec3 N, vec3 dNu, vec3 dNv) {
  float dn = dot(D, N);
  dDu -= 2.0 * (dn * dNu + (dot(dDu, N) + dot(D, dNu)) * N);
  dDv -= 2.0 * (dn * dNv + (dot(dDv, N) + dot(D, dNv)) * N);
}

// Refraction (Igehy eq. 16-19). N faces the incident side (D.N = -cos_i <
// 0), T = eta D - mu N with mu = eta (D.N) - (T.N), T.N = -cos_t, so
// mu = cos_t - eta cos_i:
//   dT = eta dD - (mu dN + dmu N),
//   dmu = (eta - eta^2 (D.N) / (T.N)) d(D.N) = (eta - eta^2 cos_i / cos_t) d(D.N),
//   d(D.N) = dD.N + D.dN.
// cos_t -> 0 (grazing exit near total internal reflection) is guarded.
void pb_diff_refract(inout vec3 dDu, inout vec3 dDv, vec3 D, vec3 N, vec3 dNu, vec3 dNv, float eta, float cos_i,
                     float cos_t) {
  float k = eta - eta * eta * cos_i / pb_guard_div(cos_t, 1e-4);
  float mu = cos_t - eta * cos_i;
  dDu = eta * dDu - mu * dNu - k * (dot(dDu, N) + dot(D, dNu)) * N;
  dDv = eta * dDv - mu * dNv - k * (dot(dDv, N) + dot(D, dNv)) * N;
}

// Scaled directional differentials of d = (cos phi sin theta, sin phi sin
// theta, cos theta) in the frame (t, b, n), seed 000 eq. 8: d/dcos(theta)
// times sin(theta) and d/dphi times 1/sin(theta). Unit, orthogonal to d and
// to each other; no division, so the poles (sin theta -> 0) need no guard.
void pb_diff_emission_dirs(vec3 t, vec3 b, vec3 n, float cos_theta, float sin_theta, float phi,
                           out vec3 dDu, out vec3 dDv) {
  float cp = cos(phi), sp = sin(phi);
  dDu = t * (-cp * cos_theta) + b * (-sp * cos_theta) + n * sin_theta;
  dDv = -t * sp + b * cp;
}

// Diffuse re-emission (seed 000 eq. 10-13): the photon is re-emitted with
// fresh eq.-8 differentials dD' (|dDu' x dDv'| = 1 and the global Delta for
// both new parameters), and its origin is moved back along -d' by v so that
// the new footprint at the hit has the old one's area:
//   A = pi |Delta dPu x Delta dPv| = A' = pi |Delta v dDu' x Delta v dDv'|
//   => v = sqrt(|dPu x dPv| / |dDu' x dDv'|) = sqrt(|dPu x dPv|).
// At the hit the new positional differentials are then v dD' (eq. 11).
void pb_diff_reemit(inout vec3 dPu, inout vec3 dPv, vec3 dDu_new, vec3 dDv_new) {
  float v = sqrt(length(cross(dPu, dPv)));
  if (isnan(v) || isinf(v)) {
    pb_diff_guarded++;
    v = 0.0;
  }
  dPu = v * dDu_new;
  dPv = v * dDv_new;
}

bool pb_finite3(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

// Semi-axis lengths of the skewed ellipse {a cos s + b sin s}: the singular
// values of [a b], sqrt of the eigenvalues of the Gram matrix
// [[a.a, a.b], [a.b, b.b]]. Returns (major, minor).
vec2 pb_ellipse_axes(vec3 a, vec3 b) {
  float aa = dot(a, a), bb = dot(b, b), ab = dot(a, b);
  float m = 0.5 * (aa + bb);
  float r = sqrt(max(0.0, 0.25 * (aa - bb) * (aa - bb) + ab * ab));
  float major = sqrt(m + r);
  float area = length(cross(a, b)); // = major * minor
  float minor = major > 0.0 ? area / major : 0.0;
  return vec2(major, min(minor, major));
}

#endif
