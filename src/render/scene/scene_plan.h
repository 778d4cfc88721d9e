/* What the GPU pipeline compiles in for a scene ("the scene
 * pays only for what it uses"). The passes switch code paths with
 * specialization constants set from the scene's PB_FEATURE_* flags
 * taken from this plan (frame.c's pass setup, photon_trace.c, photon_rsm.c),
 * and `info` and render --json report it. */
#ifndef PB_RENDER_SCENE_PLAN_H
#define PB_RENDER_SCENE_PLAN_H

#include <stdint.h>

#include "scene/scene.h"

typedef struct pb_render_plan {
  int eye_chains;        /* mirror/glass eye paths (SC_SPECULAR) */
  int emitter_sampling;  /* shadow rays to emissive triangles (SC_EMISSIVE) */
  int unlit;             /* KHR_materials_unlit surfaces: their colour on
                            camera paths (SC_EMISSIVE's emission code) */
  int vertex_colors;     /* COLOR_0 uploaded (pb_gpu_frame.color_base) */
  int media;             /* absorbing media on transmission paths */
  int textures;          /* texture fetches (SC_TEXTURES) */
  int vertex_normals;    /* interpolated shading normals (SC_HAS_NORMALS) */
  int photons;           /* photon stages: the scene has a light other than
                            emissive triangles, or a world (and not
                            --direct-only) */
  int caustic_photons;   /* photons follow specular chains (photon_trace's
                            SC_SPECULAR) */
  int refraction;        /* photons refract (SC_TRANSMISSION) */
  int blender_materials; /* Blender materials (PHOTONBRIDGE_blender: Principled
                            BSDF, ...; SC_BLENDER): their closures, glossy eye
                            paths through them */
  int multi_ggx;         /* of them, a Multiscatter GGX distribution (--json;
                            the code compiled follows `closures`) */
  int alpha;             /* transparent shadows through Alpha < 1 (SC_ALPHA) */
  int principled2;       /* a Principled v2 material (SC_PRINCIPLED2): the
                            v2 stack compiled in */
  uint32_t closures;     /* PB_CLOSURES_*: the closures the Blender
                            materials may make (SC_CLOSURES); 0 without
                            them */
  int normal_maps;       /* normal-mapped shading normals in the eye passes
                            (tangents uploaded, pb_gpu_frame.tangent_base)
                            and, with photons, seed 001's eq. 20 correction
                            of the indirect light (shading_correction.h) */
  int soft_lights;       /* sphere, area and soft-sun lights: sampled by
                            area or solid angle in the direct pass, seen by
                            camera rays and specular chains (SC_SOFT_LIGHTS) */
  int world;             /* world light: background of camera rays and
                            specular chains, BSDF-sampled (+ map-sampled)
                            direct light, photons from it (SC_WORLD) */
  int world_map;         /* its radiance is an environment map (importance
                            sampled) rather than a constant */
} pb_render_plan;

/* The names of PB_CLOSURES_*'s bits, lowest first (info, --json). */

/* direct_only: render --direct-only (no photon stages). */
void pb_render_plan_of(const pb_scene *s, int direct_only, pb_render_plan *out);

/* The plan as a JSON object under `key` (info --json, render --json). */
struct pb_json;
void pb_render_plan_json(struct pb_json *j, const char *key, const pb_render_plan *p);

#endif
