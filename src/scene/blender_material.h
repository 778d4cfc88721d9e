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
  /* Resolves glTF textures[tex] to an index of pb_scene.textures, decoded
   * as sRGB or linear texels; `where` names the JSON path for its errors. */
  pb_result (*texture)(void *user, int32_t tex, int srgb, const char *where, int32_t *out);
  /* Adds a scene warning (one line, without the file name). */
  pb_result (*warn)(void *user, const char *line);
} pb_blender_material_io;

/* Sets m to a Blender shader of `model` with Blender 3.4's defaults (the
 * reader starts from these; code-built scenes and tests use them too). */
void pb_blender_material_defaults(pb_material *m, pb_material_model model);

/* Fills m's Blender model from `ext` (the extension object of
 * materials[index]). Errors are one line "FILE: materials[i].extensions.
 * PHOTONBRIDGE_blender.MEMBER: why" with PB_ERR_SCENE_INVALID (wrong JSON
 * type, a non-finite number, a value outside its range, an unknown model,
 * a texture that does not exist). Unknown members are ignored. */
pb_result pb_blender_material_read(const pb_blender_material_io *io, int index, const pb_gltf_value *ext,
                                   pb_material *m);

#endif
