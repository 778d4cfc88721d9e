/* Reads materials[i].extensions.PHOTONBRIDGE_blender (the contract in
 * exporters/blender/PHOTONBRIDGE_blender.md) into a pb_material: the model
 * (principled, diffuse, emission, holdout), every input with Blender's
 * default where the file leaves it out, and the texture links. load.c calls
 * it after the material's plain glTF form has been read; the extension then
 * replaces that form (scene.h, pb_blender_material). */
#ifndef PB_BLENDER_MATERIAL_H
#define PB_BLENDER_MATERIAL_H

#include <stdint.h>

#include "core/result.h"
#include "scene/gltf_doc.h"
#include "scene/scene.h"

typedef struct pb_blender_material_io {
  const char *path; /* the scene file, first on every message */
  void *user;
  /* Resolves a textureInfo (textures[ref->index], its uv set and
   * KHR_texture_transform) to an index of pb_scene.textures, decoded as sRGB
   * or linear texels, as glTF's own textures are; `where` names the JSON
   * path for its errors. */
  pb_result (*texture)(void *user, const pb_gltf_texture_ref *ref, int srgb, const char *where, int32_t *out);
  /* Adds a scene warning (one line, without the file name). */
  pb_result (*warn)(void *user, const char *line);
  /* The root's extensions.PHOTONBRIDGE_blender (NULL: none): its "blender"
   * version decides the Smith G2 of the GGX lobes (3.5+: height-correlated). */
  const pb_gltf_value *root;
  /* Stores a Mix Shader's second shader as a material of the scene and
   * gives its index (NULL: a "mix" is warned about and left out). */
  pb_result (*add_material)(void *user, const pb_material *m, uint32_t *index);
} pb_blender_material_io;

/* Sets m to a Blender shader of `model` with Blender 3.4's defaults (the
 * reader starts from these; code-built scenes and tests use them too). */
void pb_blender_material_defaults(pb_material *m, pb_material_model model);

/* Sets m to a Principled v2 BSDF (Blender 4.x) with a new node's defaults in
 * Blender 4.5 (and the v1 slots' approximation of them). */
void pb_blender_material_defaults_v2(pb_material *m);

/* Fills m's Blender model from `ext` (the extension object of
 * materials[index]). Errors are one line "FILE: materials[i].extensions.
 * PHOTONBRIDGE_blender.MEMBER: why" with PB_ERR_SCENE_INVALID (wrong JSON
 * type, a non-finite number, a value outside its range, an unknown model,
 * a texture that does not exist). Unknown members are ignored. A "mix"
 * (a Mix Shader of the model and a second shader, "mix.shader") stores the
 * second shader through io->add_material and sets m->blender.mix_with. */
pb_result pb_blender_material_read(const pb_blender_material_io *io, int index, const pb_gltf_value *ext,
                                   pb_material *m);

/* Cycles 3.4's tangent for a Principled BSDF whose Tangent input is left
 * unlinked: radial about the object's Z axis in Blender's generated
 * coordinates (the Tangent node, direction Radial, axis Z:
 * (-(g.y - 1/2), g.x - 1/2, 0) in object space, g = (p - min) / size over the
 * mesh's bounding box), transformed as a normal. Here for a vertex pl of a
 * glTF mesh in its local frame (Blender's exporter writes x, z, -y of
 * Blender's axes), the mesh's bounds bmin, bmax in that frame and the node's
 * normal matrix N (column-major 3x3, inverse transpose). out: world space,
 * unit; false when it vanishes (on the axis). */
int pb_blender_radial_tangent(const double pl[3], const double bmin[3], const double bmax[3], const double N[9],
                              float out[3]);

/* Does the material need pb_blender_radial_tangent's tangents? */
int pb_blender_needs_tangent(const pb_material *m);

#endif
