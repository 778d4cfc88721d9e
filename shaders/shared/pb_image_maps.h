/* The environment maps of the image-space photon tracer (seed 003, Yao et
 * al. 2010, sections 3-5): k cube maps of the scene, each seen from one
 * environment-map centre (EMC), holding per texel the first surface along
 * the texel's direction: position, geometric normal, triangle and material.
 * Written by shaders/photon/image_maps.comp (rays cast from the centre through
 * the BVH), read by common/image_maps.glsl (the ray-map intersection of
 * section 5). Included after pb_gpu.h. Host side: src/render/image_maps.c.
 *
 * Cube layout (both sides use it, pb_cube_texel / pb_cube_dir): face
 * f = 2 a + (w_a < 0) for the major axis a of a direction w; within the
 * face, s = w_{(a+1)%3} / |w_a| and t = w_{(a+2)%3} / |w_a| in [-1, 1],
 * texel (i, j) = floor((s, t) * res / 2 + res / 2); texel index
 * (f res + j) res + i from the map's first texel. */
#ifndef PB_IMAGE_MAPS_SHARED_H
#define PB_IMAGE_MAPS_SHARED_H

/* At most this many maps (the CLI's --image-maps 1..15: seed 003 uses 8-15,
 * "k is typically set to 8 to 15", section 4.1). */
PB_CONST(PB_IMAGE_MAPS_MAX, 15u)

/* One texel, 32 bytes. prim = PB_GPU_MISS where the texel's ray left the
 * scene (distance infinite). */
PB_STRUCT(pb_gpu_image_texel) {
  PB_VEC3(position);   /* first hit along the texel's centre ray, metres */
  uint prim;           /* its triangle (pb_gpu_hit.prim) */
  PB_VEC3(normal);     /* unit geometric normal of that triangle */
  uint material;       /* tri_material[prim] */
} PB_END(pb_gpu_image_texel)

/* One map. */
PB_STRUCT(pb_gpu_image_map) {
  PB_VEC3(center);     /* the EMC, metres */
  uint first;          /* index of its first texel */
} PB_END(pb_gpu_image_map)

/* The set, at the start of the maps buffer, then pb_gpu_image_map[count]. */
PB_STRUCT(pb_gpu_image_maps_info) {
  uint count;          /* maps in use (k) */
  uint resolution;     /* texels per face side */
  uint march_steps;    /* samples of the ray's projection per map (section 5.1) */
  uint secant_steps;   /* false-position iterations after a bracket (3-5) */
  PB_VEC3(bounds_min); /* the scene's box: rays are clipped to it */
  float epsilon;       /* the angular error bound e of eq. 2 (0.001) */
  PB_VEC3(bounds_max);
  float start_offset;  /* metres skipped at the ray's origin */
} PB_END(pb_gpu_image_maps_info)

/* Counters of one trace (atomics; the images build of photon_trace.comp and
 * image_maps_query.comp), 32 bytes. A segment is one ray searched in every
 * map; its outcome is a hit (the nearest accepted point, type C or D of
 * section 5.2), an escape (every map: type A, no crossing) or a miss (no
 * accepted point, some map found only type B points: what no map sees). */
PB_STRUCT(pb_gpu_image_counts) {
  uint segments;
  uint hits;
  uint misses;
  uint escapes;
  uint type_b;         /* points rejected by e > epsilon, over all maps */
  uint type_c;         /* accepted points farther than another map's */
  uint pad0, pad1;
} PB_END(pb_gpu_image_counts)

/* Push constants of image_maps.comp (render the maps) and
 * image_maps_query.comp (tests: rays against the maps). */
PB_STRUCT(pb_gpu_image_maps_push) {
  uint first_map;      /* render: maps first_map .. first_map + map_count - 1 */
  uint map_count;
  uint resolution;     /* render: texels per face side of those maps */
  uint ray_count;      /* query: rays */
} PB_END(pb_gpu_image_maps_push)

/* What moved geometry touches (image_maps_touch.comp): the
 * box of the triangles that moved, old and new positions, and per map a
 * flag the pass sets when one of the map's texel rays (centre to its stored
 * surface point, or to infinity where it saw nothing) crosses the box: only
 * those texels can hold another first surface now, so only those maps are
 * rendered again. Bound at PB_IMAGE_BIND_COUNTS. 96 bytes. */
PB_STRUCT(pb_gpu_image_touch) {
  PB_VEC3(box_min);
  uint pad0;
  PB_VEC3(box_max);
  uint pad1;
  uint touched[16];    /* per map (PB_IMAGE_MAPS_MAX + 1 slots): 1 touched */
} PB_END(pb_gpu_image_touch)

#ifndef PB_GLSL
#include <stddef.h>
_Static_assert(sizeof(pb_gpu_image_touch) == 96, "pb_gpu_image_touch size");
_Static_assert(offsetof(pb_gpu_image_touch, box_max) == 16, "pb_gpu_image_touch.box_max");
_Static_assert(offsetof(pb_gpu_image_touch, touched) == 32, "pb_gpu_image_touch.touched");
_Static_assert(sizeof(pb_gpu_image_texel) == 32, "pb_gpu_image_texel size");
_Static_assert(offsetof(pb_gpu_image_texel, normal) == 16, "pb_gpu_image_texel.normal");
_Static_assert(sizeof(pb_gpu_image_map) == 16, "pb_gpu_image_map size");
_Static_assert(sizeof(pb_gpu_image_maps_info) == 48, "pb_gpu_image_maps_info size");
_Static_assert(offsetof(pb_gpu_image_maps_info, bounds_min) == 16, "pb_gpu_image_maps_info.bounds_min");
_Static_assert(offsetof(pb_gpu_image_maps_info, bounds_max) == 32, "pb_gpu_image_maps_info.bounds_max");
_Static_assert(sizeof(pb_gpu_image_counts) == 32, "pb_gpu_image_counts size");
_Static_assert(sizeof(pb_gpu_image_maps_push) == 16, "pb_gpu_image_maps_push size");
#endif

#endif
