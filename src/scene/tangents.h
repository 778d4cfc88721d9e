/* Per-vertex tangent frames for normal mapping (glTF 2.0, 3.7.2.1: TANGENT
 * is a VEC4, xyz the unit tangent along +u, w = +-1 the handedness; the
 * bitangent is cross(normal, tangent.xyz) * w).
 *
 * Kept apart from the loader so that it can be re-run on re-posed vertices
 * (animation): it reads world-space positions, normals and uvs only. */
#ifndef PB_SCENE_TANGENTS_H
#define PB_SCENE_TANGENTS_H

#include <stdint.h>

#include "core/result.h"

/* Fills tangents[v] for every vertex v < vertex_count.
 *  given: NULL, or given[v] != 0 where tangents[v] already holds a tangent
 *    from the file (world space); it is kept, only re-orthogonalised against
 *    the normal (Gram-Schmidt) with its w reduced to a sign.
 *  Every other vertex gets a tangent generated from the uv mapping of the
 *    triangles that use it: per triangle dP/du and dP/dv (Lengyel's method,
 *    unnormalised, so larger triangles weigh more), summed per vertex,
 *    T = normalize(dP/du - n (n . dP/du)) and w the sign of
 *    dot(cross(n, T), -dP/dv). The minus: glTF's uv origin is the image's
 *    top-left, so the normal map's +Y (image up) runs along -v; this is the
 *    frame MikkTSpace gives on the flipped v of Blender's exporter.
 *  A vertex with no usable uv mapping (degenerate uvs, no triangle) gets an
 *  arbitrary unit tangent orthogonal to its normal and w = +1: never NaN.
 * Normals are expected unit length; a zero normal gets the tangent (1,0,0,1).
 * Returns PB_ERR_NOMEM only. */
pb_result pb_tangents_generate(const float (*positions)[3], const float (*normals)[3],
                               const float (*uvs)[2], uint32_t vertex_count,
                               const uint32_t (*triangles)[3], uint32_t triangle_count,
                               const uint8_t *given, float (*tangents)[4]);

/* Any unit vector orthogonal to unit n (Duff et al. 2017's basis). */
void pb_tangent_any(const float n[3], float t[3]);
/* That basis whole: t (pb_tangent_any's) and b, with n right-handed; the
 * GLSL pb_basis (shaders/common/basis.glsl). */
void pb_basis_any(const float n[3], float t[3], float b[3]);

#endif
