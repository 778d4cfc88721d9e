/* The lights and the world of the PHOTONBRIDGE_blender glTF extension
 * (exporters/blender/PHOTONBRIDGE_blender.md): Blender's own values,
 * converted here, in one place, with Cycles 3.4's conventions (scene.h's
 * pb_light and pb_world say what the converted values mean; the derivations
 * and measurements are in blender_lights.c). Internal to the loader. */
#ifndef PB_SCENE_BLENDER_LIGHTS_H
#define PB_SCENE_BLENDER_LIGHTS_H

#include "scene/gltf_doc.h"
#include "scene/scene.h"
#include "scene/xform.h"

/* The root extension object: checks `version`, reads render.filmTransparent
 * into s->film_opaque, colorManagement into s->view and `world` into s->world (its environment map loaded
 * and checked). Errors name the JSON path: PB_ERR_SCENE_INVALID for a wrong
 * type, a non-finite number or a value out of range, PB_ERR_SCENE_UNSUPPORTED
 * for another version or projection, PB_ERR_IO / PB_ERR_IMAGE / PB_ERR_LIMIT
 * for the map's file, whose uri resolves against `dir` (gltf_doc.h
 * pb_gltf_resolve_uri; NULL: no external files). */
pb_result pb_blender_read_root(const char *path, const char *dir, const pb_gltf_value *root,
                               const pb_load_desc *desc, pb_scene *s);

/* nodes[node].extensions.PHOTONBRIDGE_blender (`ext`): when it has a `light`
 * member, converts it with the node's world transform M into *out and sets
 * *has_light; the caller then ignores the node's KHR_lights_punctual light
 * (never both). */
pb_result pb_blender_read_light(const char *path, int node, const char *node_name, const pb_gltf_value *ext,
                                const mat4 *M, pb_light *out, int *has_light);

#endif
