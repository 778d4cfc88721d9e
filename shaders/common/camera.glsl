// Camera rays and projection: src/scene/camera.c's pb_camera_ray and
// pb_camera_view_project, for a pb_gpu_camera (shared/pb_gpu.h).

// The ray through image position p (pixels, top row first): origin on the
// near clip plane, unit direction, t0 = distance from the camera to that
// origin, tmax = length to the far plane (infinite without one).
void pb_camera_ray(pb_gpu_camera c, vec2 p, out vec3 org, out vec3 dir, out float t0, out float tmax) {
  float sx = c.x0 + p.x * c.dx, sy = c.y0 + p.y * c.dy;
  if (c.orthographic != 0u) {
    org = c.position + c.right * sx + c.up * sy;
    dir = c.forward;
  } else {
    org = c.position;
    dir = normalize(c.forward + c.right * sx + c.up * sy);
  }
  float cz = dot(dir, c.forward);
  t0 = c.clip_near / cz;
  org += dir * t0;
  tmax = c.clip_far > 0.0 ? (c.clip_far - c.clip_near) / cz : uintBitsToFloat(0x7f800000u);
}

// World point to image position and camera depth; false behind the camera
// plane or when not finite.
bool pb_camera_project(pb_gpu_camera c, vec3 p, out vec2 px, out float z) {
  vec3 d = p - c.position;
  z = dot(d, c.forward);
  px = vec2(0.0);
  if (!(z > 0.0)) return false;
  vec2 s = vec2(dot(d, c.right), dot(d, c.up));
  if (c.orthographic == 0u) s /= z;
  px = (s - vec2(c.x0, c.y0)) / vec2(c.dx, c.dy);
  return !any(isinf(px)) && !any(isnan(px));
}
