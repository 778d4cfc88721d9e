/* The scene model as a neutral dump for the benchmark peers that do not read
 * glTF: LuxCoreRender (pyluxcore 2.11) and Mitsuba 3. What photonbridge's
 * loader made is written, so the peers see the same triangles, normals,
 * uvs, camera and radiometric units as every photonbridge renderer.
 *
 * DIR holds, for both formats:
 *   mN.ply       binary little-endian PLY, one per material N that triangles
 *                use: world-space `x y z nx ny nz s t` (float) and `list
 *                uchar uint vertex_indices`, glTF uvs unchanged (both peers
 *                read v = 0 as the image's top row, as glTF does), through the
 *                base colour texture's KHR_texture_transform when it has one.
 *   tN.exr       each base colour texture used, decoded to linear float (the
 *                sRGB curve of IEC 61966-2-1, as photonbridge samples it).
 * and per format:
 *   luxcore      scene.scn (SDL properties) and render.cfg (PATHCPU, 2
 *                threads, box pixel filter, film size; scene.file =
 *                scene.scn). Load with pyluxcore.Properties("render.cfg") in
 *                DIR (file names are relative). The screen window is one
 *                pixel low to undo LuxCore's one-row camera offset.
 *   mitsuba      scene.xml (version 3.0.0; `spp` a default parameter), for
 *                mitsuba.load_file in an *_rgb variant.
 *
 * Units (radiometric, per shared/VALIDATION.md; I in W/sr, E in W/m^2):
 *   LuxCore  point: gain = 4 pi I (PointLight::Illuminate returns
 *            gain color / 4pi); spot: gain = I, no 4 pi (SpotLight returns
 *            gain color falloff / cos); sharpdistant: gain = E; emission:
 *            radiance = emission x gain; constantinfinite: radiance = gain.
 *            power and efficency are left 0 (their route is photometric).
 *   Mitsuba  point and spot `intensity` = I, directional `irradiance` = E,
 *            area `radiance` = L, constant `radiance` = L.
 * Materials are reduced to pb_material_kind: Lambert, mirror (constant
 * reflectance = base colour: glTF's Schlick Fresnel is lost), smooth glass
 * (exact dielectric Fresnel, IOR), glossy (a GGX approximation). Each
 * reduction that changes the picture is a note (report and a comment in the
 * file). What a format cannot hold is an error naming the element. */
#ifndef PB_PEER_H
#define PB_PEER_H

#include <stdint.h>

#include "core/result.h"
#include "scene/scene.h"

typedef enum pb_peer_format {
  PB_PEER_LUXCORE = 0,
  PB_PEER_MITSUBA = 1,
} pb_peer_format;

extern const char *const pb_peer_format_names[]; /* "luxcore", "mitsuba", NULL */

typedef struct pb_peer_desc {
  pb_peer_format format;
  uint32_t width, height; /* image size; fixes the aspect */
  int camera;             /* index into scene->cameras */
  uint32_t spp;           /* samples per pixel written as the default; 0: 64 */
  uint32_t threads;       /* render threads written; 0: 2 */
} pb_peer_desc;

typedef struct pb_peer_report {
  char **notes;           /* one line each: what the peer shows differently */
  uint32_t note_count;
  uint32_t ply_files;     /* meshes written (materials that triangles use) */
  uint32_t texture_files;
  uint32_t vertex_count;  /* summed over the PLYs */
  uint32_t triangle_count;
} pb_peer_report;

/* Writes the dump into directory `dir` (created if missing; files in it
 * replaced). Errors: PB_ERR_USAGE (bad camera index, bad format),
 * PB_ERR_SCENE_EMPTY (no triangles), PB_ERR_SCENE_UNSUPPORTED (something
 * the format cannot hold: "SCENE: lights[2] 'Area': ..."), PB_ERR_IO,
 * PB_ERR_NOMEM. `report` may be NULL; when given it is filled on success and
 * must be destroyed. */
pb_result pb_peer_export(const pb_scene *s, const pb_peer_desc *desc, const char *dir,
                         pb_peer_report *report);
void pb_peer_report_destroy(pb_peer_report *r);

/* The light unit mappings above, for tests and documentation. */
double pb_peer_luxcore_point_gain(double intensity); /* 4 pi I */
double pb_peer_luxcore_spot_gain(double intensity);  /* I */

#endif
