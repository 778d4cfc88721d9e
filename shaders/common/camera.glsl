// Camera rays and projection: src/scene/camera.c's pb_camera_ray_lens and
// pb_camera_view_project, for a pb_gpu_camera (shared/pb_gpu.h): the same
// steps in the same order (Cycles 3.4 kernel/camera/camera.h and
// projection.h), so both renderers trace the same rays.

// A point of the unit aperture for u in [0, 1)^2: Shirley and Chiu's
// concentric disc, or Cycles' regular_polygon_sample; x times inv_ratio
// (camera_sample_aperture).
vec2 pb_aperture_point(pb_gpu_camera c, vec2 u) {
  vec2 p;
  if (c.blades == 0.0) {
    float a = 2.0 * u.x - 1.0, b = 2.0 * u.y - 1.0, r, phi;
    if (a == 0.0 && b == 0.0) {
      r = 0.0;
      phi = 0.0;
    } else if (a * a > b * b) {
      r = a;
      phi = 0.78539816339744831 * (b / a);
    } else {
      r = b;
      phi = 1.5707963267948966 - 0.78539816339744831 * (a / b);
    }
    p = vec2(r * cos(phi), r * sin(phi));
  } else {
    float corners = c.blades, corner = floor(u.x * corners);
    float s = sqrt(u.x * corners - corner), w = u.y * s;
    s = 1.0 - s;
    float angle = 3.14159265358979324 / corners;
    vec2 q = vec2((s + w) * cos(angle), (s - w) * sin(angle));
    float rot = c.blade_rotation + corner * 2.0 * angle, cr = cos(rot), sr = sin(rot);
    p = vec2(cr * q.x - sr * q.y, sr * q.x + cr * q.y);
  }
  p.x *= c.inv_ratio;
  return p;
}

// Cycles' panorama_to_direction in its panorama frame; false where (u, v)
// has no ray (outside a fisheye's circle, off the mirror ball).
bool pb_pano_direction(pb_gpu_camera c, float u, float v, out vec3 d) {
  d = vec3(0.0);
  if (c.projection == PB_GPU_CAMERA_EQUIRECTANGULAR) {
    float phi = c.pano0 * u + c.pano1, theta = c.pano2 * v + c.pano3;
    d = vec3(sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta));
    return true;
  }
  if (c.projection == PB_GPU_CAMERA_FISHEYE_EQUIDISTANT || c.projection == PB_GPU_CAMERA_FISHEYE_EQUISOLID) {
    float theta;
    if (c.projection == PB_GPU_CAMERA_FISHEYE_EQUIDISTANT) {
      u = (u - 0.5) * 2.0;
      v = (v - 0.5) * 2.0;
      float r = sqrt(u * u + v * v);
      if (r > 1.0) return false;
      theta = r * c.pano0 * 0.5;
    } else {
      u = (u - 0.5) * c.pano2;
      v = (v - 0.5) * c.pano3;
      float r = sqrt(u * u + v * v), rmax = 2.0 * c.pano0 * sin(c.pano1 * 0.25);
      if (r > rmax) return false;
      // 2 asin(x) as 2 atan(x, sqrt(1 - x^2)): GLSL's asin is loose
      float x = min(r / (2.0 * c.pano0), 1.0);
      theta = 2.0 * atan(x, sqrt(max(1.0 - x * x, 0.0)));
    }
    float r = sqrt(u * u + v * v), cp = r != 0.0 ? u / r : 0.0, sp = r != 0.0 ? v / r : 0.0;
    d = vec3(cos(theta), -cp * sin(theta), sp * sin(theta));
    return true;
  }
  if (c.projection == PB_GPU_CAMERA_MIRRORBALL) {
    float x = 2.0 * u - 1.0, z = 2.0 * v - 1.0;
    if (x * x + z * z > 1.0) return false;
    float y = -sqrt(max(1.0 - x * x - z * z, 0.0)), k = 2.0 * -y;
    d = vec3(k * x, k * y + 1.0, k * z);
    return true;
  }
  return false;
}

// Panorama frame to world (camera.c pano_to_world): +x along the view
// (+y left, +z up); the mirror ball looks along -y.
vec3 pb_pano_to_world(pb_gpu_camera c, vec3 l) {
  return c.projection == PB_GPU_CAMERA_MIRRORBALL ? l.x * c.right - l.y * c.forward + l.z * c.up
                                                  : l.x * c.forward - l.y * c.right + l.z * c.up;
}

// The ray through image position p (pixels, top row first) and lens
// sample `lens` in [0, 1)^2 (unused without aperture): origin on the near
// clip plane, unit direction, t0 = the camera depth (panoramas: distance)
// of that origin over the ray's cosine, tmax = length to the far plane
// (infinite without one). False (tmax 0) where p has no ray.
bool pb_camera_ray_lens(pb_gpu_camera c, vec2 p, vec2 lens, out vec3 org, out vec3 dir, out float t0, out float tmax) {
  float sx = c.x0 + p.x * c.dx, sy = c.y0 + p.y * c.dy;
  bool thin = c.aperture > 0.0;
  vec2 a = thin ? pb_aperture_point(c, lens) * c.aperture : vec2(0.0);
  if (c.projection != PB_GPU_CAMERA_PLANAR) {
    vec3 l, q = vec3(0.0);
    if (!pb_pano_direction(c, sx, sy, l)) {
      org = c.position;
      dir = c.forward;
      t0 = 0.0;
      tmax = 0.0;
      return false;
    }
    l = normalize(l);
    if (thin) {
      vec3 U = vec3(1.0, 0.0, 0.0) - l.x * l;
      // along the frame's x itself Cycles' U is 0 / 0: any normal will do
      U = length(U) > 1e-6 ? normalize(U) : vec3(0.0, 1.0, 0.0);
      vec3 V = cross(l, U);
      q = U * a.x + V * a.y;
      l = normalize(l * c.focus - q);
    }
    dir = pb_pano_to_world(c, l);
    t0 = c.clip_near;
    org = c.position + pb_pano_to_world(c, q) + dir * t0;
    tmax = c.clip_far > 0.0 ? c.clip_far - c.clip_near : uintBitsToFloat(0x7f800000u);
    return true;
  }
  float cz;
  if (c.orthographic != 0u) {
    org = c.position + c.right * (sx + a.x) + c.up * (sy + a.y) + c.forward * c.clip_near;
    dir = normalize(c.forward * (thin ? c.focus : 1.0) - c.right * a.x - c.up * a.y);
    cz = dot(dir, c.forward);
    t0 = c.clip_near / cz;
    tmax = c.clip_far > 0.0 ? (c.clip_far - c.clip_near) / cz : uintBitsToFloat(0x7f800000u);
    return true;
  }
  vec3 pin = c.forward + c.right * sx + c.up * sy;
  if (thin) {
    vec3 o = c.right * a.x + c.up * a.y;
    org = c.position + o;
    dir = normalize(pin * c.focus - o);
    cz = 1.0 / length(pin);
  } else {
    org = c.position;
    dir = normalize(pin);
    cz = dot(dir, c.forward);
  }
  t0 = c.clip_near / cz;
  org += dir * t0;
  tmax = c.clip_far > 0.0 ? (c.clip_far - c.clip_near) / cz : uintBitsToFloat(0x7f800000u);
  return true;
}

// The pinhole ray (the lens centre's): motion vectors and reprojection.
void pb_camera_ray(pb_gpu_camera c, vec2 p, out vec3 org, out vec3 dir, out float t0, out float tmax) {
  c.aperture = 0.0;
  pb_camera_ray_lens(c, p, vec2(0.5), org, dir, t0, tmax);
}

// The camera depth of the point t along a camera ray from org (the
// G-buffer's depth AOV): along forward, or for a panorama the distance from
// the camera (Cycles' camera_z_depth).
float pb_camera_depth(pb_gpu_camera c, vec3 org, vec3 dir, float t0, float t) {
  if (c.projection != PB_GPU_CAMERA_PLANAR) return length(org + dir * t - c.position);
  return (t0 + t) * dot(dir, c.forward);
}

// World point to image position and camera depth; false behind the camera
// plane, outside a panorama's field or when not finite.
bool pb_camera_project(pb_gpu_camera c, vec3 p, out vec2 px, out float z) {
  vec3 d = p - c.position;
  px = vec2(0.0);
  if (c.projection != PB_GPU_CAMERA_PLANAR) {
    z = length(d);
    if (!(z > 0.0)) return false;
    d /= z;
    float f = dot(d, c.forward), r = dot(d, c.right), up = dot(d, c.up);
    vec3 l = c.projection == PB_GPU_CAMERA_MIRRORBALL ? vec3(r, -f, up) : vec3(f, -r, up);
    vec2 uv;
    if (c.projection == PB_GPU_CAMERA_EQUIRECTANGULAR) {
      uv = vec2((atan(l.y, l.x) - c.pano1) / c.pano0, (acos(clamp(l.z, -1.0, 1.0)) - c.pano3) / c.pano2);
    } else if (c.projection == PB_GPU_CAMERA_MIRRORBALL) {
      float y = l.y - 1.0, div = 2.0 * sqrt(max(-0.5 * y, 0.0));
      vec2 xz = div > 0.0 ? l.xz / div : l.xz;
      uv = 0.5 * (xz + 1.0);
    } else {
      float theta = acos(clamp(l.x, -1.0, 1.0)), rho = length(l.yz);
      vec2 cs = rho > 0.0 ? vec2(-l.y, l.z) / rho : vec2(1.0, 0.0);
      if (c.projection == PB_GPU_CAMERA_FISHEYE_EQUIDISTANT) {
        float r = 2.0 * theta / c.pano0;
        if (r > 1.0) return false;
        uv = 0.5 + 0.5 * r * cs;
      } else {
        if (theta > 0.5 * c.pano1) return false;
        uv = 0.5 + 2.0 * c.pano0 * sin(0.5 * theta) * cs / vec2(c.pano2, c.pano3);
      }
    }
    px = (uv - vec2(c.x0, c.y0)) / vec2(c.dx, c.dy);
    return !any(isinf(px)) && !any(isnan(px));
  }
  z = dot(d, c.forward);
  if (!(z > 0.0)) return false;
  vec2 s = vec2(dot(d, c.right), dot(d, c.up));
  if (c.orthographic == 0u) s /= z;
  px = (s - vec2(c.x0, c.y0)) / vec2(c.dx, c.dy);
  return !any(isinf(px)) && !any(isnan(px));
}
