/* The lights of a node: its PHOTONBRIDGE_blender light (blender_lights.c)
 * or else its KHR_lights_punctual one (checked first: check_light), in
 * world space. Part of the loader (load_internal.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/blender_lights.h"
#include "scene/load_internal.h"

/* nodes[node]'s KHR_lights_punctual light, checked before it is placed:
 * an index, a known type, a non-negative float intensity, colour and range,
 * spot cones in order (a hard-edged spot warned). */
static pb_result check_light(loader *L, int32_t node, pb_light_type *type_out) {
  pb_gltf_doc *d = L->doc;
  int32_t li = d->nodes[node].light;
  if (li == -2)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d].extensions.KHR_lights_punctual.light: missing or not a light index",
                   L->path, node);
  if (li < 0 || (size_t)li >= d->light_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d].extensions.KHR_lights_punctual.light: %d does not exist (%zu lights)",
                   L->path, node, li, d->light_count);
  const pb_gltf_light *g = &d->lights[li];
  pb_light_type type;
  char known[64];
  if (!pb_light_kind_parse(g->type, 0, &type, known, sizeof known))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: extensions.KHR_lights_punctual.lights[%d].type: '%s' is not %s", L->path,
                   li, g->type, known);
  const uint32_t kind = pb_light_kind_of(type)->flags;
  if (!fits_float(g->intensity) || g->intensity < 0)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: extensions.KHR_lights_punctual.lights[%d].intensity: %g is not a non-negative float",
                   L->path, li, g->intensity);
  for (int k = 0; k < 3; ++k)
    if (!fits_float(g->color[k]) || g->color[k] < 0)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: extensions.KHR_lights_punctual.lights[%d].color[%d]: %g is not a non-negative float",
                     L->path, li, k, g->color[k]);
  if (!fits_float(g->range) || g->range < 0)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: extensions.KHR_lights_punctual.lights[%d].range: %g is not a non-negative float", L->path, li, g->range);
  if ((kind & PB_LIGHT_CONE) && !(g->inner_cone >= 0 && g->inner_cone <= g->outer_cone && g->outer_cone > 0 &&
                                 g->outer_cone <= M_PI / 2 + 1e-6))
    return pb_fail(PB_ERR_SCENE_INVALID,
                   "%s: extensions.KHR_lights_punctual.lights[%d].spot: need 0 <= innerConeAngle (%g) < outerConeAngle (%g) <= pi/2",
                   L->path, li, g->inner_cone, g->outer_cone);
  /* Blender writes a spot of blend 0 as innerConeAngle = outerConeAngle
   * (inner = outer (1 - blend)), which glTF's schema forbids (inner <
   * outer) but which means what Cycles draws: a hard-edged cone. Every
   * renderer's falloff is a step when the two are equal (pb_spot_falloff). */
  pb_result wr;
  if ((kind & PB_LIGHT_CONE) && g->inner_cone == g->outer_cone &&
      (wr = load_warn(L, "extensions.KHR_lights_punctual.lights[%d].spot: innerConeAngle = outerConeAngle (%g, Blender's spot blend 0): a hard-edged spot",
                      li, g->outer_cone)) != PB_OK)
    return wr;
  *type_out = type;
  return PB_OK;
}

static pb_result add_light(loader *L, int32_t node, const mat4 *M) {
  pb_gltf_doc *d = L->doc;
  int32_t li = d->nodes[node].light;
  pb_light nl;
  memset(&nl, 0, sizeof nl); /* its type set by check_light */
  pb_result cr = check_light(L, node, &nl.type);
  if (cr != PB_OK) return cr;
  const pb_gltf_light *g = &d->lights[li];
  if ((cr = pb_light_place(&nl, M, L->path, node, 0)) != PB_OK) return cr;
  pb_scene *s = L->s;
  pb_result r = load_grow(L, (void **)&s->lights, &L->light_cap, (uint64_t)s->light_count + 1, sizeof *s->lights, "lights");
  if (r != PB_OK) return r;
  pb_light *l = &s->lights[s->light_count++];
  *l = nl;
  load_copy_name(l->name, d->nodes[node].name, g->name);
  if (!l->name[0]) snprintf(l->name, PB_NAME_MAX, "lights[%d]", li);
  for (int k = 0; k < 3; ++k) l->color[k] = (float)g->color[k];
  l->file_intensity = (float)g->intensity;
  /* shared/VALIDATION.md: standard = photometric (cd, lx): W = lm / 683;
   * Blender's unitless mode writes W/(4 pi) (point, spot) and W/m^2 (sun). */
  l->intensity = (float)(L->desc->light_units == PB_LIGHT_UNITS_UNITLESS ? g->intensity : g->intensity / PB_LUMENS_PER_WATT);
  if (pb_light_kind_of(l->type)->flags & PB_LIGHT_CONE) {
    l->inner_cone = (float)g->inner_cone;
    l->outer_cone = (float)g->outer_cone;
  }
  l->range = (float)g->range;
  return PB_OK;
}

/* PHOTONBRIDGE_blender's light replaces the node's KHR_lights_punctual
 * approximation of it (never both: no light counted twice). */
pb_result load_node_light(loader *L, int32_t node, const mat4 *M) {
  const pb_gltf_node *n = &L->doc->nodes[node];
  pb_result r;
  int blender_light = 0;
  if (n->blender) {
    pb_light bl;
    if ((r = pb_blender_read_light(L->path, node, n->name, n->blender, M, &bl, &blender_light)) != PB_OK) return r;
    if (blender_light) {
      if ((r = load_grow(L, (void **)&L->s->lights, &L->light_cap, (uint64_t)L->s->light_count + 1, sizeof *L->s->lights,
                         "lights")) != PB_OK)
        return r;
      L->s->lights[L->s->light_count++] = bl;
    }
  }
  if (!blender_light && n->light != -1) return add_light(L, node, M);
  return PB_OK;
}
