// Screen-space photon splatting (seed 001 section 24.3), shared by
// splat_count.comp and splat_splat.comp: the buffers both read, the culling
// of 24.2.1 and the kernel of eq. 2-8. Needs shared/pb_gpu.h,
// shared/pb_photon.h, shared/pb_splat.h and common/camera.glsl first, and
// `frame` (pb_gpu_frame) declared.

layout(std430, set = 0, binding = PB_SPLAT_BIND_PHOTONS) readonly buffer Photons { pb_gpu_photon photons[]; };
layout(std430, set = 0, binding = PB_SPLAT_BIND_COUNTS) readonly buffer MapCounts { pb_gpu_photon_counts map_counts; };
layout(std430, set = 0, binding = PB_SPLAT_BIND_TILES) buffer Tiles { uint tiles[]; };
layout(std430, set = 0, binding = PB_SPLAT_BIND_STATS) buffer Stats { pb_gpu_splat_stats stats; };
layout(push_constant) uniform SplatPush { pb_gpu_splat_push sp; };

const float PB_SPLAT_PI = 3.14159265358979323846;

uint pb_splat_gid() {
  return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
}

// Photons of the map this pass reads.
uint pb_splat_stored() {
  return (sp.flags & PB_SPLAT_USE_COUNTS) != 0u ? min(map_counts.stored, sp.capacity) : min(sp.stored, sp.capacity);
}

// Seed 001 24.2.1: "We also do not store photons at surfaces with normals
// facing away from the camera or photons that are located outside of the
// camera frustum". Our photon map is shared with the other estimators, so
// the culling happens here, before the tile count, instead of at storage.
// Returns 0 kept (on screen: px in the window), 1 kept off screen, 2 culled
// (facing), 3 culled (depth). px: image position (pixels, this image's
// origin, crops included); z: camera depth.
uint pb_splat_cull(pb_gpu_photon p, out vec2 px, out float z) {
  pb_gpu_camera c = frame.cam;
  vec3 to_eye = c.orthographic != 0u ? -c.forward : c.position - p.position;
  if (!(dot(p.normal, to_eye) > 0.0)) {
    px = vec2(0.0);
    z = 0.0;
    return 2u;
  }
  if (!pb_camera_project(c, p.position, px, z) || z < c.clip_near || (c.clip_far > 0.0 && z > c.clip_far))
    return 3u;
  px -= vec2(float(frame.key_x0), float(frame.key_y0));
  bool on = px.x >= 0.0 && px.y >= 0.0 && px.x < float(frame.width) && px.y < float(frame.height);
  return on ? 0u : 1u;
}

// The tile of image position px (clamped into the image: photons off screen
// take the count of the nearest tile).
uint pb_splat_tile(vec2 px) {
  uint tx = uint(clamp(px.x, 0.0, float(frame.width) - 1.0)) / sp.tile;
  uint ty = uint(clamp(px.y, 0.0, float(frame.height) - 1.0)) / sp.tile;
  return min(ty, sp.tiles_y - 1u) * sp.tiles_x + min(tx, sp.tiles_x - 1u);
}
