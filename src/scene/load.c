/* glTF -> pb_scene: every index, offset, stride and count is checked before
 * any data is read, then the node tree is flattened into world-space arrays.
 * Errors are one line "FILE: JSON-PATH: why" (pb_fail). See gltf_doc.h for
 * what the shim has (and has not) checked, load_internal.h for how the
 * loader's files share the work (this one: the entry points, the order of
 * the steps, the helpers). */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/fs.h"
#include "scene/anim.h"
#include "scene/blender_lights.h"
#include "scene/load_internal.h"

/* ---- growth helpers ---------------------------------------------------- */

pb_result load_grow(loader *L, void **p, uint32_t *cap, uint64_t need, size_t elem, const char *what) {
  if (need <= *cap) return PB_OK;
  if (need > UINT32_MAX / 2)
    return pb_fail(PB_ERR_LIMIT, "%s: too many %s (%llu)", L->path, what, (unsigned long long)need);
  uint64_t c = *cap ? *cap : 64;
  while (c < need) c *= 2;
  if (c > SIZE_MAX / elem) /* a 32-bit host: the byte size would wrap */
    return pb_fail(PB_ERR_LIMIT, "%s: too many %s (%llu) for this machine's address space", L->path, what,
                   (unsigned long long)need);
  void *q = realloc(*p, (size_t)c * elem);
  if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for %llu %s", L->path, (unsigned long long)c, what);
  *p = q;
  *cap = (uint32_t)c;
  return PB_OK;
}

pb_result load_warn(loader *L, const char *fmt, ...) {
  char buf[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  if (pb_scene_warn(L->s, "%s", buf) != PB_OK)
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  return PB_OK;
}

void load_copy_name(char dst[PB_NAME_MAX], const char *a, const char *b) {
  const char *src = (a && a[0]) ? a : (b ? b : "");
  snprintf(dst, PB_NAME_MAX, "%s", src);
}

/* ---- transforms: scene/xform.h ------------------------------------------ */

mat4 load_node_local(const pb_gltf_node *n) {
  if (n->has_matrix) {
    mat4 r;
    memcpy(r.m, n->matrix, sizeof r.m);
    return r;
  }
  return trs_matrix(n->translation, n->rotation, n->scale);
}

/* ---- the steps ------------------------------------------------------------ */

/* The loader's per-image and per-node tables, and the materials (with
 * room for glTF's default material). */
static pb_result alloc_tables(loader *L) {
  pb_gltf_doc *d = L->doc;
  pb_scene *s = L->s;
  /* A Mix Shader's second shader is a material of its own (blender_material.c). */
  for (size_t i = 0; i < d->material_count; ++i)
    if (d->materials[i].blender && d->materials[i].blender->type == PB_GLTF_OBJECT &&
        pb_gltf_value_get(d->materials[i].blender, "mix"))
      L->mix_capacity++;
  s->materials = calloc(d->material_count + L->mix_capacity + 1, sizeof *s->materials);
  L->image_cache = calloc(d->image_count + 1, sizeof *L->image_cache);
  L->image_cache_f = calloc(d->image_count + 1, sizeof *L->image_cache_f);
  L->image_linear = calloc(d->image_count + 1, sizeof *L->image_linear);
  L->image_w = calloc(d->image_count + 1, sizeof *L->image_w);
  L->image_h = calloc(d->image_count + 1, sizeof *L->image_h);
  L->node_state = calloc(d->node_count + 1, 1);
  L->parent = malloc((d->node_count + 1) * sizeof *L->parent);
  if (!s->materials || !L->image_cache || !L->image_cache_f || !L->image_linear || !L->image_w || !L->image_h || !L->node_state || !L->parent)
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  return PB_OK;
}

/* KHR_materials_clearcoat, _sheen and _iridescence are the plain-glTF form of
 * layers that a material's PHOTONBRIDGE_blender model renders itself (the
 * writer writes both, as Blender's exporter does): nothing is lost while
 * every material using one has the Blender model. (A plain material's
 * thin film is warned about where it is read, load_material.c.) */
static int read_through_blender(const pb_gltf_doc *d, const char *e) {
  int coat = strcmp(e, "KHR_materials_clearcoat") == 0, sheen = strcmp(e, "KHR_materials_sheen") == 0;
  if (strcmp(e, "KHR_materials_iridescence") == 0) return 1;
  if (!coat && !sheen) return 0;
  for (size_t i = 0; i < d->material_count; ++i) {
    const pb_gltf_material *m = &d->materials[i];
    if ((coat ? m->has_clearcoat : m->has_sheen) && !m->blender) return 0;
  }
  return 1;
}

/* extensionsUsed that nothing here reads: warned. */
static pb_result warn_extensions(loader *L) {
  pb_gltf_doc *d = L->doc;
  pb_result r;
  for (size_t i = 0; i < d->extensions_used_count; ++i) {
    const char *e = d->extensions_used[i];
    static const char *const known[] = {"KHR_lights_punctual", "KHR_materials_specular", "KHR_materials_transmission",
                                        "KHR_materials_ior", "KHR_materials_emissive_strength", "KHR_texture_transform",
                                        "KHR_materials_unlit", "KHR_materials_volume", "KHR_materials_variants",
                                        "PHOTONBRIDGE_blender"};
    int ok = 0;
    for (size_t k = 0; k < sizeof known / sizeof *known; ++k) ok |= strcmp(e, known[k]) == 0;
    ok |= read_through_blender(d, e);
    if (!ok && (r = load_warn(L, "extensionsUsed[%zu]: '%s' is ignored", i, e)) != PB_OK) return r;
  }
  return PB_OK;
}

static pb_result load(loader *L) {
  pb_gltf_doc *d = L->doc;
  pb_scene *s = L->s;
  pb_result r;
  /* Materials first (textures are decoded only when a material uses them). */
  if ((r = alloc_tables(L)) != PB_OK) return r;
  for (size_t i = 0; i < d->material_count; ++i) {
    if ((r = load_material(L, (int)i, &s->materials[i])) != PB_OK) return r;
    s->material_count++;
  }
  s->material_count += L->mix_count;
  if ((r = load_check_nodes(L)) != PB_OK) return r;
  if ((r = pb_skins_load(L->path, d, &L->deform)) != PB_OK) return r;
  if ((r = pb_morph_weights_load(L->path, d, &L->deform)) != PB_OK) return r;
  if ((r = load_anims(L)) != PB_OK) return r;
  /* PHOTONBRIDGE_blender's root: film and world (blender_lights.c). */
  if (d->blender && (r = pb_blender_read_root(L->path, L->dir, d->blender, L->desc, s)) != PB_OK) return r;
  /* The scene to show: `scene`, else scenes[0], else every root node. */
  if ((r = load_scene_nodes(L)) != PB_OK) return r;
  if ((r = load_deform_finish(L)) != PB_OK) return r;
  s->animation_count = (uint32_t)d->animation_count;
  s->animation_channel_count = (uint32_t)d->animation_channel_count;
  if ((r = warn_extensions(L)) != PB_OK) return r;
  struct pb_scene_anim *an = L->anim;
  if (an) { /* s owns it from here */
    s->anim = an;
    L->anim = NULL;
    load_anim_range(an, &s->anim_start, &s->anim_end);
  }
  pb_scene_finalize(s);
  if ((r = load_tangents(L)) != PB_OK) return r;
  if (s->camera_count == 0) {
    if ((r = load_default_camera(L)) != PB_OK) return r;
    if ((r = load_warn(L, "cameras: none in the scene; using a default camera framing the bounds")) != PB_OK) return r;
  }
  if (an && (r = load_anim_finish(L, an)) != PB_OK) return r;
  if (s->triangle_count == 0 && (r = load_warn(L, "meshes: no triangles to render")) != PB_OK) return r;
  if (s->light_count == 0 && !(s->features & (PB_FEATURE_EMISSIVE | PB_FEATURE_UNLIT)) && !s->world.present &&
      (r = load_warn(L, "lights: none, no world and no emissive material: the render will be black")) != PB_OK)
    return r;
  return PB_OK;
}

static pb_load_desc load_defaults(const pb_load_desc *desc_in) {
  pb_load_desc desc = desc_in ? *desc_in : (pb_load_desc){0};
  if (!desc.max_file_bytes) desc.max_file_bytes = 2ull << 30;
  if (!desc.max_image_dim) desc.max_image_dim = 16384;
  if (!desc.max_image_pixels) desc.max_image_pixels = 64ull << 20;
  if (!desc.max_triangles) desc.max_triangles = 64ull << 20;
  return desc;
}

/* The parsed document (owned: destroyed here) into `out`. */
static pb_result load_doc(const char *name, const char *dir, const pb_load_desc *desc, pb_gltf_doc *doc, pb_scene *out) {
  loader L;
  memset(&L, 0, sizeof L);
  L.path = name;
  L.dir = dir;
  L.desc = desc;
  L.doc = doc;
  L.s = out;
  L.default_material = -1;
  out->path = strdup(name);
  out->light_units = desc->light_units;
  snprintf(out->generator, sizeof out->generator, "%s", doc->generator ? doc->generator : "");
  pb_result r = out->path ? load(&L) : pb_fail(PB_ERR_NOMEM, "%s: out of memory", name);

  for (size_t i = 0; i < doc->image_count && L.image_cache; ++i) free(L.image_cache[i]);
  for (size_t i = 0; i < doc->image_count && L.image_cache_f; ++i) free(L.image_cache_f[i]);
  free(L.image_cache);
  free(L.image_cache_f);
  free(L.image_linear);
  free(L.image_w);
  free(L.image_h);
  free(L.texture_src);
  free(L.node_state);
  free(L.parent);
  pb_scene_anim_destroy(L.anim);
  pb_deform_destroy(&L.deform);
  free(L.world);
  free(L.tan);
  free(L.tan_given);
  pb_gltf_doc_destroy(doc);
  if (r != PB_OK) pb_scene_destroy(out);
  return r;
}

pb_result pb_scene_load(const char *path, const pb_load_desc *desc_in, pb_scene *out) {
  memset(out, 0, sizeof *out);
  pb_load_desc desc = load_defaults(desc_in);
  pb_gltf_doc doc;
  pb_gltf_read_desc rd = {desc.allow_external_files, desc.max_file_bytes, NULL};
  pb_result r = pb_gltf_doc_read(path, &rd, &doc);
  if (r != PB_OK) return r;
  char *dir = pb_dirname(path);
  if (!dir) {
    pb_gltf_doc_destroy(&doc);
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
  }
  r = load_doc(path, dir, &desc, &doc, out);
  free(dir);
  return r;
}

pb_result pb_scene_load_memory(const char *name, const char *base_dir, const void *data, size_t size,
                               const pb_load_desc *desc_in, pb_scene *out) {
  memset(out, 0, sizeof *out);
  pb_load_desc desc = load_defaults(desc_in);
  if (!name || !name[0]) name = "<memory>";
  if ((uint64_t)size > desc.max_file_bytes)
    return pb_fail(PB_ERR_LIMIT, "%s: input is %zu bytes, over the limit of %llu", name, size,
                   (unsigned long long)desc.max_file_bytes);
  static const uint8_t none[1] = {0};
  pb_gltf_doc doc;
  pb_gltf_read_desc rd = {desc.allow_external_files, desc.max_file_bytes, base_dir};
  pb_result r = pb_gltf_doc_parse(name, size ? (const uint8_t *)data : none, size, &rd, &doc);
  if (r != PB_OK) return r;
  return load_doc(name, base_dir, &desc, &doc, out);
}
