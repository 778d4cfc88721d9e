/* The scene model to POV-Ray 3.7 SDL, with the units of shared/VALIDATION.md
 * so that POV-Ray's linear EXR (+FE, assumed_gamma 1.0) is directly
 * comparable with photonbridge's renderers and Cycles.
 *
 * Mappings (each confirmed by a POV-Ray render in tests/unit/test_pov_render.c):
 *   coordinates  glTF is right-handed Y-up, POV-Ray left-handed Y-up: every
 *                position and normal is written as (x, y, -z), a mirror of
 *                the world; the camera's right/up/direction vectors are
 *                mirrored the same way, which mirrors the picture back (an
 *                asymmetric scene renders unmirrored).
 *   camera       perspective, `up` |1|, `right` |aspect| (aspect = W/H of the
 *                image size given, POV-Ray then runs with the same +W/+H),
 *                `direction` |0.5 / tan(yfov/2)|: the vertical field of view
 *                is glTF's yfov exactly (horizontal angle 2 atan(aspect
 *                tan(yfov/2)), written as a comment).
 *   point light  POV-Ray's fall-off is 2 / (1 + (d/f)^2) (fade_distance f,
 *                fade_power 2) and its diffuse term has no 1/pi, so colour
 *                C = I / (2 pi f^2) gives rho/pi I cos / d^2 x 1/(1 + (f/d)^2):
 *                relative error (f/d)^2; f = 1e-3 x the scene's bounding
 *                diagonal by default: error 1e-4 at a tenth of the diagonal,
 *                1e-6 at a full diagonal.
 *   spot light   POV-Ray attenuates by cos^tightness x smoothstep(cos falloff,
 *                cos radius, cos angle) (its cubic_spline), the very smooth
 *                step pb_light uses between cos outer and cos inner; so
 *                radius = inner cone, falloff = outer cone, tightness 0 make
 *                the cone exact (no residual), and the fall-off is the point
 *                light's.
 *   sun          `parallel` light, colour C = E / pi (no fall-off).
 *   diffuse      pigment rgb rho, finish diffuse 1 brilliance 1 ambient 0
 *                emission 0 (radiosity adds rho x the cosine-weighted mean
 *                incoming radiance, i.e. rho/pi x irradiance).
 *   mirror       pigment = base colour, reflection { 1 metallic }, diffuse 0.
 *   glass        rgbf <base, transmission>, fresnel reflection with
 *                conserve_energy, interior { ior }, closed meshes solid
 *                (inside_vector); photons target / reflection / refraction.
 * Approximations are reported (pb_pov_report), never silent: glossy
 * materials, emissive triangles (radiance via `emission`, lighting only
 * through radiosity), texture wrap modes other than repeat, alpha, normal
 * and metallic-roughness textures, light ranges, animation. */
#ifndef PB_POV_H
#define PB_POV_H

#include <stdint.h>

#include "core/result.h"
#include "scene/scene.h"

/* Global illumination settings. 0 is the default (medium). DIRECT: direct
 * light only (plus specular chains), no radiosity and no photons: the
 * analytic unit tests use it. */
typedef enum pb_pov_quality {
  PB_POV_QUALITY_DEFAULT = 0,
  PB_POV_DRAFT = 1,
  PB_POV_MEDIUM = 2,
  PB_POV_HIGH = 3,
  PB_POV_DIRECT = 4,
} pb_pov_quality;

extern const char *const pb_pov_quality_names[]; /* "draft", "medium", "high", "direct", NULL: index = quality - 1 */

typedef struct pb_pov_desc {
  uint32_t width, height; /* image size (fixes the aspect); 0: from the camera */
  int camera;             /* index into scene->cameras */
  pb_pov_quality quality;
  float fade_distance;    /* metres; 0: 1e-3 x the scene's bounding diagonal */
  double time;            /* seconds the caller posed an animated scene at
                             (pb_scene_set_time), for the file's notes; NAN
                             (or 0 in a zeroed desc of a static scene): the
                             file's own pose */
} pb_pov_desc;

/* What the export approximated or left out, one line each
 * ("material 'Brass': glossy metal (roughness 0.3) written as a mirror"). */
typedef struct pb_pov_report {
  char **notes;
  uint32_t note_count;
  uint32_t unsupported_count; /* notes about features POV-Ray shows differently */
  uint32_t emitter_count;     /* emissive materials used by triangles */
  uint32_t width, height;     /* the image size the SDL is written for */
  float fade_distance;        /* used for point and spot lights */
  int photons;                /* 1: photon mapping on (the scene has specular paths) */
  uint32_t texture_files;     /* PNGs written next to the .pov */
} pb_pov_report;

/* Writes `path` (atomically) and, for textured materials, PATHSTEM_mN.png
 * next to it (referenced by file name: run POV-Ray in that directory).
 * Errors: PB_ERR_USAGE (bad camera index), PB_ERR_SCENE_EMPTY (no
 * triangles), PB_ERR_IO, PB_ERR_NOMEM. `report` may be NULL; when given it is
 * filled on success and must be destroyed. */
pb_result pb_pov_export(const pb_scene *s, const pb_pov_desc *desc, const char *path,
                        pb_pov_report *report);
void pb_pov_report_destroy(pb_pov_report *r);

/* The unit mappings above, for tests and documentation. */
double pb_pov_point_color_scale(double fade_distance); /* 1 / (2 pi f^2) */
double pb_pov_parallel_color_scale(void);              /* 1 / pi */

/* Default fade distance for a scene (1e-3 x bounding diagonal, at least 1e-6). */
float pb_pov_default_fade_distance(const pb_scene *s);

#endif
