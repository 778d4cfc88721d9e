/* pb_scene -> LuxCore SDL or Mitsuba 3 XML, meshes as PLY (see peer.h). */
#include "peer/peer.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "image/image.h"

const char *const pb_peer_format_names[] = {"luxcore", "mitsuba", NULL};

double pb_peer_luxcore_point_gain(double intensity) { return 4.0 * M_PI * intensity; }
double pb_peer_luxcore_spot_gain(double intensity) { return intensity; }

static const double rad2deg = 180.0 / M_PI;

typedef struct ctx {
  const pb_scene *s;
  const pb_peer_desc *d;
  const char *dir;
  const char *peer; /* "LuxCore" or "Mitsuba 3" */
  pb_peer_report rep;
  FILE *f;          /* the scene file being written */
} ctx;

static pb_result note(ctx *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static pb_result note(ctx *c, const char *fmt, ...) {
  char buf[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  char **n = realloc(c->rep.notes, (c->rep.note_count + 1) * sizeof *n);
  if (!n) return pb_fail(PB_ERR_NOMEM, "export-peer: out of memory");
  c->rep.notes = n;
  if (!(n[c->rep.note_count] = strdup(buf))) return pb_fail(PB_ERR_NOMEM, "export-peer: out of memory");
  c->rep.note_count++;
  return PB_OK;
}

void pb_peer_report_destroy(pb_peer_report *r) {
  for (uint32_t i = 0; i < r->note_count; ++i) free(r->notes[i]);
  free(r->notes);
  memset(r, 0, sizeof *r);
}

static void path_in(const ctx *c, const char *name, char *out, size_t n) {
  snprintf(out, n, "%s/%s", c->dir, name);
}

/* A name for a comment: printable ASCII, no "--" (XML) and no newline. */
static void comment_safe(const char *in, char *out, size_t n) {
  size_t j = 0;
  for (size_t i = 0; in[i] && j + 1 < n; ++i) {
    char ch = in[i];
    if (ch < 32 || ch > 126 || (ch == '-' && j > 0 && out[j - 1] == '-')) ch = '_';
    out[j++] = ch;
  }
  out[j] = 0;
}

/* ---- meshes ---------------------------------------------------------- */

static pb_result write_ply(ctx *c, uint32_t mat, uint32_t *vcount, uint32_t *tcount) {
  const pb_scene *s = c->s;
  const pb_material *m = &s->materials[mat];
  uint32_t *remap = malloc((size_t)s->vertex_count * sizeof *remap);
  if (!remap) return pb_fail(PB_ERR_NOMEM, "export-peer: out of memory");
  memset(remap, 0xff, (size_t)s->vertex_count * sizeof *remap);
  uint32_t nv = 0, nt = 0;
  for (uint32_t t = 0; t < s->triangle_count; ++t) {
    if (s->triangle_material[t] != mat) continue;
    ++nt;
    for (int k = 0; k < 3; ++k) {
      uint32_t v = s->triangles[t][k];
      if (remap[v] == UINT32_MAX) remap[v] = nv++;
    }
  }
  *vcount = nv;
  *tcount = nt;
  if (!nt) {
    free(remap);
    return PB_OK;
  }
  uint32_t *order = malloc((size_t)nv * sizeof *order);
  if (!order) {
    free(remap);
    return pb_fail(PB_ERR_NOMEM, "export-peer: out of memory");
  }
  for (uint32_t v = 0; v < s->vertex_count; ++v)
    if (remap[v] != UINT32_MAX) order[remap[v]] = v;
  char name[64], path[4096], nm[PB_NAME_MAX];
  snprintf(name, sizeof name, "m%u.ply", mat);
  path_in(c, name, path, sizeof path);
  comment_safe(m->name, nm, sizeof nm);
  FILE *f = fopen(path, "wb");
  if (!f) {
    free(remap);
    free(order);
    return pb_fail(PB_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
  }
  fprintf(f,
          "ply\nformat binary_little_endian 1.0\ncomment photonbridge export-peer: material %u '%s', world space\n"
          "element vertex %u\nproperty float x\nproperty float y\nproperty float z\n"
          "property float nx\nproperty float ny\nproperty float nz\nproperty float s\nproperty float t\n"
          "element face %u\nproperty list uchar uint vertex_indices\nend_header\n",
          mat, nm, nv, nt);
  const pb_texture *tex =
      m->base_color_tex >= 0 && (uint32_t)m->base_color_tex < s->texture_count ? &s->textures[m->base_color_tex] : NULL;
  for (uint32_t i = 0; i < nv; ++i) {
    uint32_t v = order[i];
    float rec[8];
    memcpy(rec, s->positions[v], 12);
    memcpy(rec + 3, s->normals[v], 12);
    float uv[2] = {0, 0};
    if (s->uvs) memcpy(uv, s->uvs[v], 8);
    if (tex) {
      float out[2];
      pb_texture_uv(tex, uv, s->uvs1 ? s->uvs1[v] : NULL, out);
      memcpy(uv, out, 8);
    }
    rec[6] = uv[0];
    rec[7] = uv[1];
    fwrite(rec, sizeof rec, 1, f); /* little-endian host (x86-64, aarch64) */
  }
  for (uint32_t t = 0; t < s->triangle_count; ++t) {
    if (s->triangle_material[t] != mat) continue;
    unsigned char three = 3;
    uint32_t idx[3] = {remap[s->triangles[t][0]], remap[s->triangles[t][1]], remap[s->triangles[t][2]]};
    fwrite(&three, 1, 1, f);
    fwrite(idx, sizeof idx, 1, f);
  }
  free(remap);
  free(order);
  if (ferror(f) | fclose(f)) return pb_fail(PB_ERR_IO, "%s: write failed", path);
  c->rep.ply_files++;
  c->rep.vertex_count += nv;
  c->rep.triangle_count += nt;
  return PB_OK;
}

/* The base colour texture times the base colour factor, linear float RGB,
 * top row first, as mN_base.exr. */
static pb_result write_texture(ctx *c, uint32_t mat, char *file, size_t n) {
  const pb_material *m = &c->s->materials[mat];
  const pb_texture *t = &c->s->textures[m->base_color_tex];
  snprintf(file, n, "m%u_base.exr", mat);
  char path[4096];
  path_in(c, file, path, sizeof path);
  float *px = malloc((size_t)t->width * t->height * 3 * sizeof *px);
  if (!px) return pb_fail(PB_ERR_NOMEM, "export-peer: out of memory");
  for (uint32_t y = 0; y < t->height; ++y)
    for (uint32_t x = 0; x < t->width; ++x) {
      float rgba[4];
      pb_texture_sample(t, (x + 0.5f) / (float)t->width, (y + 0.5f) / (float)t->height, rgba);
      float *o = px + ((size_t)y * t->width + x) * 3;
      for (int k = 0; k < 3; ++k) o[k] = rgba[k] * m->base_color[k];
    }
  pb_image_layer layer = {"", 3, px, NULL};
  pb_exr_desc d = {.width = t->width, .height = t->height, .layers = &layer, .layer_count = 1};
  pb_result r = pb_exr_write(path, &d);
  free(px);
  if (r == PB_OK) c->rep.texture_files++;
  return r;
}

/* ---- what neither format holds ---------------------------------------- */

static pb_result check_scene(ctx *c) {
  const pb_scene *s = c->s;
  const char *sp = s->path ? s->path : "scene";
  for (uint32_t i = 0; i < s->light_count; ++i) {
    const pb_light *l = &s->lights[i];
    /* The kinds both formats hold; any other is refused by its name. */
    float soft;
    const char *softness = pb_light_softness(l, &soft);
    if (l->type != PB_LIGHT_POINT && l->type != PB_LIGHT_SPOT && l->type != PB_LIGHT_DIRECTIONAL)
      return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: lights[%u] '%s': %s lights are not written to %s (model it as an "
                     "emissive mesh)", sp, i, l->name, pb_light_kind_name(l->type), c->peer);
    if (!pb_light_is_delta(l))
      return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: lights[%u] '%s': a soft light (%s %g) is not written to %s; only "
                     "delta point, spot and sun lights", sp, i, l->name, softness, soft, c->peer);
    if (l->range > 0) {
      pb_result r = note(c, "lights[%u] '%s': range %g m ignored (%s lights reach everywhere)", i, l->name, l->range, c->peer);
      if (r != PB_OK) return r;
    }
    if (l->no_shadow)
      return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: lights[%u] '%s': a light that casts no shadow has no %s counterpart",
                     sp, i, l->name, c->peer);
  }
  if (s->world.present && s->world.env)
    return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: world '%s': an environment map is not written to %s (only a constant "
                   "world colour)", sp, s->world.env_name, c->peer);
  const pb_camera *cam = &s->cameras[c->d->camera];
  if (cam->orthographic || cam->panorama)
    return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: cameras[%d] '%s': only perspective cameras are written to %s", sp,
                   c->d->camera, cam->name, c->peer);
  if (cam->shift[0] != 0 || cam->shift[1] != 0)
    return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: cameras[%d] '%s': lens shift is not written to %s", sp, c->d->camera,
                   cam->name, c->peer);
  if (cam->aperture_radius > 0) {
    pb_result r = note(c, "cameras[%d] '%s': depth of field dropped (a pinhole is written)", c->d->camera, cam->name);
    if (r != PB_OK) return r;
  }
  for (uint32_t i = 0; i < s->material_count; ++i) {
    const pb_material *m = &s->materials[i];
    if (m->blender.model == PB_MODEL_HOLDOUT)
      return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: materials[%u] '%s': a holdout has no %s counterpart", sp, i, m->name,
                     c->peer);
    if (m->unlit)
      return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: materials[%u] '%s': KHR_materials_unlit has no %s counterpart", sp, i,
                     m->name, c->peer);
  }
  return PB_OK;
}

/* Vertical tan(fov/2) of the picture w x h (pb_camera.fit). */
static double tan_half_vfov(const pb_camera *cam, uint32_t w, uint32_t h) {
  double t = tan(cam->yfov * 0.5);
  int horizontal = cam->fit == PB_CAMERA_FIT_HORIZONTAL || (cam->fit == PB_CAMERA_FIT_AUTO && w >= h);
  return horizontal ? t * (double)h / (double)w : t;
}

/* Notes for one material (what the reduction changes); kind out. */
static pb_result material_notes(ctx *c, uint32_t i, pb_bsdf_kind *kind) {
  const pb_material *m = &c->s->materials[i];
  pb_result r = PB_OK;
  *kind = pb_material_kind(m);
  if (m->blender.model != PB_MODEL_GLTF)
    r = note(c, "materials[%u] '%s': Blender %s reduced to its closest glTF kind", i, m->name,
             pb_blender_model_name(&m->blender));
  if (r == PB_OK && *kind == PB_BSDF_MIRROR)
    r = note(c, "materials[%u] '%s': metal written with constant reflectance = base colour (glTF's Schlick Fresnel, up "
             "to 1 - F0 brighter at grazing, is lost)", i, m->name);
  if (r == PB_OK && *kind == PB_BSDF_GLOSSY)
    r = note(c, "materials[%u] '%s': glossy (roughness %g, metallic %g) approximated by %s's GGX model", i, m->name,
             m->roughness, m->metallic, c->peer);
  if (r == PB_OK && (m->metallic_roughness_tex >= 0 || m->normal_tex >= 0 || m->emissive_tex >= 0))
    r = note(c, "materials[%u] '%s': metallic-roughness, normal and emissive textures ignored", i, m->name);
  if (r == PB_OK && m->alpha_mode != PB_ALPHA_OPAQUE)
    r = note(c, "materials[%u] '%s': alpha %s ignored (opaque)", i, m->name, m->alpha_mode == PB_ALPHA_MASK ? "mask" : "blend");
  if (r == PB_OK && (m->attenuation[0] > 0 || m->attenuation[1] > 0 || m->attenuation[2] > 0))
    r = note(c, "materials[%u] '%s': volume absorption ignored", i, m->name);
  if (r == PB_OK && m->base_color_tex >= 0 && c->s->textures[m->base_color_tex].wrap_s == PB_WRAP_MIRROR &&
      c->d->format == PB_PEER_LUXCORE)
    r = note(c, "materials[%u] '%s': mirrored-repeat wrap written as repeat", i, m->name);
  return r;
}

/* ---- LuxCore ---------------------------------------------------------- */

static pb_result write_luxcore(ctx *c, const uint32_t *used) {
  const pb_scene *s = c->s;
  const pb_camera *cam = &s->cameras[c->d->camera];
  FILE *f = c->f;
  const double a = (double)c->d->width / c->d->height;
  const double vfov = 2 * atan(tan_half_vfov(cam, c->d->width, c->d->height)) * rad2deg;
  fprintf(f, "# photonbridge export-peer --format luxcore: LuxCoreRender 2.11 SDL (peer.h)\n");
  fprintf(f, "# camera %d '%s'; image %ux%u\n", c->d->camera, cam->name, c->d->width, c->d->height);
  fprintf(f, "scene.camera.type = perspective\n");
  fprintf(f, "scene.camera.lookat.orig = %.9g %.9g %.9g\n", cam->position[0], cam->position[1], cam->position[2]);
  fprintf(f, "scene.camera.lookat.target = %.9g %.9g %.9g\n", cam->position[0] + cam->forward[0],
          cam->position[1] + cam->forward[1], cam->position[2] + cam->forward[2]);
  fprintf(f, "scene.camera.up = %.9g %.9g %.9g\n", cam->up[0], cam->up[1], cam->up[2]);
  /* PerspectiveCamera::InitRay maps film y to raster y as height - filmY - 1
   * on continuous coordinates: every row one pixel off (the picture one row
   * low, measured). The window moved up by one pixel (2 / height in screen
   * units) puts each row back where photonbridge's camera has it. */
  const double dy = 2.0 / c->d->height;
  fprintf(f, "# vertical field of view: the explicit screen window makes it so; the window is one pixel (2/H)\n"
             "# lower than -1..1 to undo LuxCore's one-row offset (InitRay: raster y = H - filmY - 1)\n");
  fprintf(f, "scene.camera.fieldofview = %.9g\n", vfov);
  fprintf(f, "scene.camera.screenwindow = %.9g %.9g %.9g %.9g\n", -a, a, -1 - dy, 1 - dy);
  fprintf(f, "scene.camera.cliphither = %.9g\n", cam->znear > 0 ? cam->znear : 1e-3);
  if (cam->zfar > 0) fprintf(f, "scene.camera.clipyon = %.9g\n", cam->zfar);
  for (uint32_t i = 0; i < s->light_count; ++i) {
    const pb_light *l = &s->lights[i];
    char nm[PB_NAME_MAX];
    comment_safe(l->name, nm, sizeof nm);
    const char *p = "scene.lights";
    fprintf(f, "# lights[%u] '%s'\n", i, nm);
    fprintf(f, "%s.l%u.color = %.9g %.9g %.9g\n", p, i, l->color[0], l->color[1], l->color[2]);
    switch (l->type) {
    case PB_LIGHT_POINT: {
      double g = pb_peer_luxcore_point_gain(l->intensity);
      fprintf(f, "# I = %.9g W/sr: gain = 4 pi I\n", l->intensity);
      fprintf(f, "%s.l%u.type = point\n%s.l%u.position = %.9g %.9g %.9g\n%s.l%u.gain = %.9g %.9g %.9g\n", p, i, p, i,
              l->position[0], l->position[1], l->position[2], p, i, g, g, g);
      break;
    }
    case PB_LIGHT_SPOT: {
      double g = pb_peer_luxcore_spot_gain(l->intensity);
      double outer = l->outer_cone * rad2deg, inner = l->inner_cone * rad2deg;
      fprintf(f, "# I0 = %.9g W/sr: gain = I0 (no 4 pi). LuxCore's profile is ((cos t - cos outer) / (cos inner - "
                 "cos outer))^4 / cos t, not glTF's smooth step\n", l->intensity);
      fprintf(f, "%s.l%u.type = spot\n%s.l%u.position = %.9g %.9g %.9g\n", p, i, p, i, l->position[0], l->position[1],
              l->position[2]);
      fprintf(f, "%s.l%u.target = %.9g %.9g %.9g\n", p, i, l->position[0] + l->direction[0],
              l->position[1] + l->direction[1], l->position[2] + l->direction[2]);
      fprintf(f, "%s.l%u.coneangle = %.9g\n%s.l%u.conedeltaangle = %.9g\n%s.l%u.gain = %.9g %.9g %.9g\n", p, i, outer,
              p, i, outer - inner, p, i, g, g, g);
      pb_result r = note(c, "lights[%u] '%s': LuxCore's spot profile (t^4 / cos) differs from glTF's smooth step "
                            "off the axis (exact on it)", i, l->name);
      if (r != PB_OK) return r;
      break;
    }
    case PB_LIGHT_DIRECTIONAL:
      fprintf(f, "# E = %.9g W/m^2: gain = E; direction = where the light travels\n", l->intensity);
      fprintf(f, "%s.l%u.type = sharpdistant\n%s.l%u.direction = %.9g %.9g %.9g\n%s.l%u.gain = %.9g %.9g %.9g\n", p, i,
              p, i, l->direction[0], l->direction[1], l->direction[2], p, i, l->intensity, l->intensity, l->intensity);
      break;
    default: break;
    }
  }
  if (s->world.present) {
    fprintf(f, "# world: constant radiance\nscene.lights.world.type = constantinfinite\n"
               "scene.lights.world.color = %.9g %.9g %.9g\nscene.lights.world.gain = 1 1 1\n",
            s->world.color[0], s->world.color[1], s->world.color[2]);
  }
  for (uint32_t i = 0; i < s->material_count; ++i) {
    if (!used[i]) continue;
    const pb_material *m = &s->materials[i];
    pb_bsdf_kind kind;
    pb_result r = material_notes(c, i, &kind);
    if (r != PB_OK) return r;
    char nm[PB_NAME_MAX], tex[64] = "";
    comment_safe(m->name, nm, sizeof nm);
    const char *p = "scene.materials";
    fprintf(f, "# materials[%u] '%s'\n", i, nm);
    if (m->base_color_tex >= 0) {
      char file[64];
      r = write_texture(c, i, file, sizeof file);
      if (r != PB_OK) return r;
      const pb_texture *t = &s->textures[m->base_color_tex];
      snprintf(tex, sizeof tex, "t%u", i);
      fprintf(f, "# base colour x factor, linear\nscene.textures.%s.type = imagemap\nscene.textures.%s.file = %s\n"
                 "scene.textures.%s.gamma = 1\nscene.textures.%s.wrap = %s\n",
              tex, tex, file, tex, tex, t->wrap_s == PB_WRAP_CLAMP ? "clamp" : "repeat");
    }
    char col[96];
    if (tex[0])
      snprintf(col, sizeof col, "%s", tex);
    else
      snprintf(col, sizeof col, "%.9g %.9g %.9g", m->base_color[0], m->base_color[1], m->base_color[2]);
    switch (kind) {
    case PB_BSDF_DIFFUSE: fprintf(f, "%s.m%u.type = matte\n%s.m%u.kd = %s\n", p, i, p, i, col); break;
    case PB_BSDF_MIRROR: fprintf(f, "%s.m%u.type = mirror\n%s.m%u.kr = %s\n", p, i, p, i, col); break;
    case PB_BSDF_GLASS:
      fprintf(f, "%s.m%u.type = glass\n%s.m%u.kr = 1 1 1\n%s.m%u.kt = %s\n%s.m%u.interiorior = %.9g\n"
                 "%s.m%u.exteriorior = 1\n",
              p, i, p, i, p, i, col, p, i, m->ior, p, i);
      break;
    case PB_BSDF_GLOSSY: {
      double rough = m->roughness;
      if (m->transmission > 0.5f) {
        fprintf(f, "%s.m%u.type = roughglass\n%s.m%u.kr = 1 1 1\n%s.m%u.kt = %s\n%s.m%u.interiorior = %.9g\n"
                   "%s.m%u.exteriorior = 1\n%s.m%u.uroughness = %.9g\n%s.m%u.vroughness = %.9g\n",
                p, i, p, i, p, i, col, p, i, m->ior, p, i, p, i, rough, p, i, rough);
      } else if (m->metallic > 0.5f) {
        fprintf(f, "scene.textures.f%u.type = fresnelcolor\nscene.textures.f%u.kr = %s\n", i, i, col);
        fprintf(f, "%s.m%u.type = metal2\n%s.m%u.fresnel = f%u\n%s.m%u.uroughness = %.9g\n%s.m%u.vroughness = %.9g\n", p,
                i, p, i, i, p, i, rough, p, i, rough);
      } else {
        double f0 = (m->ior - 1) / (m->ior + 1);
        f0 *= f0 * m->specular;
        fprintf(f, "%s.m%u.type = glossy2\n%s.m%u.kd = %s\n%s.m%u.ks = %.9g %.9g %.9g\n%s.m%u.uroughness = %.9g\n"
                   "%s.m%u.vroughness = %.9g\n",
                p, i, p, i, col, p, i, f0, f0, f0, p, i, rough, p, i, rough);
      }
      break;
    }
    }
    if (pb_material_is_emissive(m))
      fprintf(f, "# emission: radiance [W/(m^2 sr)] = emission x gain, from the front face only\n"
                 "%s.m%u.emission = %.9g %.9g %.9g\n%s.m%u.emission.gain = 1 1 1\n",
              p, i, m->emissive[0], m->emissive[1], m->emissive[2], p, i);
    fprintf(f, "scene.shapes.m%u.type = mesh\nscene.shapes.m%u.ply = m%u.ply\n", i, i, i);
    fprintf(f, "scene.objects.m%u.shape = m%u\nscene.objects.m%u.material = m%u\n", i, i, i, i);
  }
  if (ferror(f)) return pb_fail(PB_ERR_IO, "%s/scene.scn: write failed", c->dir);

  char path[4096];
  path_in(c, "render.cfg", path, sizeof path);
  FILE *g = fopen(path, "w");
  if (!g) return pb_fail(PB_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
  uint32_t spp = c->d->spp ? c->d->spp : 64, th = c->d->threads ? c->d->threads : 2;
  fprintf(g,
          "# photonbridge export-peer --format luxcore: render settings (run pyluxcore in this folder)\n"
          "scene.file = scene.scn\n"
          "renderengine.type = PATHCPU\nrenderengine.seed = 1\nnative.threads.count = %u\n"
          "sampler.type = SOBOL\nsampler.sobol.adaptive.strength = 0\n"
          "film.width = %u\nfilm.height = %u\n"
          "# one sample one pixel, as photonbridge's uniformly jittered 1-pixel box\nfilm.filter.type = NONE\n"
          "path.pathdepth.total = 64\npath.pathdepth.diffuse = 64\npath.pathdepth.glossy = 64\n"
          "path.pathdepth.specular = 64\npath.russianroulette.depth = 3\npath.russianroulette.cap = 0.5\n"
          "path.clamping.variance.maxvalue = 0\n"
          "batch.haltspp = %u\n"
          "film.outputs.0.type = RGB\nfilm.outputs.0.filename = render.exr\n",
          th, c->d->width, c->d->height, spp);
  if (ferror(g) | fclose(g)) return pb_fail(PB_ERR_IO, "%s: write failed", path);
  return PB_OK;
}

/* ---- Mitsuba 3 -------------------------------------------------------- */

static void rgb(FILE *f, const char *name, const float v[3], double k) {
  fprintf(f, "<rgb name=\"%s\" value=\"%.9g %.9g %.9g\"/>", name, v[0] * k, v[1] * k, v[2] * k);
}

/* Any unit vector not parallel to d. */
static void any_up(const float d[3], float up[3]) {
  up[0] = 0, up[1] = 1, up[2] = 0;
  if (fabsf(d[1]) > 0.9f) up[0] = 0, up[1] = 0, up[2] = 1;
}

static pb_result write_mitsuba(ctx *c, const uint32_t *used) {
  const pb_scene *s = c->s;
  const pb_camera *cam = &s->cameras[c->d->camera];
  FILE *f = c->f;
  const double vfov = 2 * atan(tan_half_vfov(cam, c->d->width, c->d->height)) * rad2deg;
  uint32_t spp = c->d->spp ? c->d->spp : 64;
  fprintf(f, "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!-- photonbridge export-peer, format mitsuba: Mitsuba 3 "
             "scene (peer.h); an *_rgb variant. Units: intensity W/sr, irradiance W/m2, radiance W/(m2 sr) -->\n");
  fprintf(f, "<scene version=\"3.0.0\">\n<default name=\"spp\" value=\"%u\"/>\n", spp);
  fprintf(f, "<integrator type=\"path\"><integer name=\"max_depth\" value=\"65\"/>"
             "<integer name=\"rr_depth\" value=\"5\"/></integrator>\n");
  fprintf(f, "<!-- camera %d; vertical field of view -->\n<sensor type=\"perspective\">\n", c->d->camera);
  fprintf(f, "  <string name=\"fov_axis\" value=\"y\"/><float name=\"fov\" value=\"%.9g\"/>\n", vfov);
  fprintf(f, "  <float name=\"near_clip\" value=\"%.9g\"/><float name=\"far_clip\" value=\"%.9g\"/>\n",
          cam->znear > 0 ? cam->znear : 1e-3, cam->zfar > 0 ? cam->zfar : 1e7);
  fprintf(f, "  <transform name=\"to_world\"><lookat origin=\"%.9g, %.9g, %.9g\" target=\"%.9g, %.9g, %.9g\" "
             "up=\"%.9g, %.9g, %.9g\"/></transform>\n",
          cam->position[0], cam->position[1], cam->position[2], cam->position[0] + cam->forward[0],
          cam->position[1] + cam->forward[1], cam->position[2] + cam->forward[2], cam->up[0], cam->up[1], cam->up[2]);
  fprintf(f, "  <sampler type=\"independent\"><integer name=\"sample_count\" value=\"$spp\"/></sampler>\n");
  fprintf(f, "  <film type=\"hdrfilm\"><integer name=\"width\" value=\"%u\"/><integer name=\"height\" value=\"%u\"/>"
             "<string name=\"pixel_format\" value=\"rgb\"/><string name=\"component_format\" value=\"float32\"/>"
             "<rfilter type=\"box\"/></film>\n</sensor>\n",
          c->d->width, c->d->height);
  for (uint32_t i = 0; i < s->light_count; ++i) {
    const pb_light *l = &s->lights[i];
    char nm[PB_NAME_MAX];
    comment_safe(l->name, nm, sizeof nm);
    fprintf(f, "<!-- lights[%u] '%s' -->\n", i, nm);
    switch (l->type) {
    case PB_LIGHT_POINT:
      fprintf(f, "<emitter type=\"point\"><point name=\"position\" x=\"%.9g\" y=\"%.9g\" z=\"%.9g\"/>", l->position[0],
              l->position[1], l->position[2]);
      rgb(f, "intensity", l->color, l->intensity);
      fprintf(f, "</emitter>\n");
      break;
    case PB_LIGHT_SPOT: {
      float up[3];
      any_up(l->direction, up);
      fprintf(f, "<!-- Mitsuba's profile is linear in the angle from beam_width to cutoff_angle, not glTF's smooth "
                 "step -->\n<emitter type=\"spot\"><transform name=\"to_world\"><lookat origin=\"%.9g, %.9g, %.9g\" "
                 "target=\"%.9g, %.9g, %.9g\" up=\"%g, %g, %g\"/></transform>",
              l->position[0], l->position[1], l->position[2], l->position[0] + l->direction[0],
              l->position[1] + l->direction[1], l->position[2] + l->direction[2], up[0], up[1], up[2]);
      fprintf(f, "<float name=\"cutoff_angle\" value=\"%.9g\"/><float name=\"beam_width\" value=\"%.9g\"/>",
              l->outer_cone * rad2deg, l->inner_cone * rad2deg);
      rgb(f, "intensity", l->color, l->intensity);
      fprintf(f, "</emitter>\n");
      pb_result r = note(c, "lights[%u] '%s': Mitsuba's spot profile (linear in angle) differs from glTF's smooth "
                            "step between the cones (exact inside the inner cone)", i, l->name);
      if (r != PB_OK) return r;
      break;
    }
    case PB_LIGHT_DIRECTIONAL:
      fprintf(f, "<emitter type=\"directional\"><vector name=\"direction\" x=\"%.9g\" y=\"%.9g\" z=\"%.9g\"/>",
              l->direction[0], l->direction[1], l->direction[2]);
      rgb(f, "irradiance", l->color, l->intensity);
      fprintf(f, "</emitter>\n");
      break;
    default: break;
    }
  }
  if (s->world.present) {
    fprintf(f, "<emitter type=\"constant\">");
    rgb(f, "radiance", s->world.color, 1);
    fprintf(f, "</emitter>\n");
  }
  for (uint32_t i = 0; i < s->material_count; ++i) {
    if (!used[i]) continue;
    const pb_material *m = &s->materials[i];
    pb_bsdf_kind kind;
    pb_result r = material_notes(c, i, &kind);
    if (r != PB_OK) return r;
    char nm[PB_NAME_MAX], file[64] = "";
    comment_safe(m->name, nm, sizeof nm);
    if (m->base_color_tex >= 0) {
      r = write_texture(c, i, file, sizeof file);
      if (r != PB_OK) return r;
    }
    fprintf(f, "<!-- materials[%u] '%s' -->\n", i, nm);
    const char *wrap = "repeat";
    if (file[0]) {
      pb_wrap w = s->textures[m->base_color_tex].wrap_s;
      wrap = w == PB_WRAP_CLAMP ? "clamp" : w == PB_WRAP_MIRROR ? "mirror" : "repeat";
    }
#define COLOR(name)                                                                                            \
  do {                                                                                                         \
    if (file[0])                                                                                               \
      fprintf(f, "<texture type=\"bitmap\" name=\"%s\"><string name=\"filename\" value=\"%s\"/>"              \
                 "<boolean name=\"raw\" value=\"true\"/><string name=\"filter_type\" value=\"%s\"/>"           \
                 "<string name=\"wrap_mode\" value=\"%s\"/></texture>",                                        \
              name, file, s->textures[m->base_color_tex].nearest ? "nearest" : "bilinear", wrap);              \
    else                                                                                                       \
      rgb(f, name, m->base_color, 1);                                                                          \
  } while (0)
    const double alpha = (double)m->roughness * m->roughness;
    switch (kind) {
    case PB_BSDF_DIFFUSE:
      fprintf(f, "<bsdf type=\"twosided\" id=\"b%u\"><bsdf type=\"diffuse\">", i);
      COLOR("reflectance");
      fprintf(f, "</bsdf></bsdf>\n");
      break;
    case PB_BSDF_MIRROR:
      fprintf(f, "<bsdf type=\"twosided\" id=\"b%u\"><bsdf type=\"conductor\"><string name=\"material\" "
                 "value=\"none\"/>", i);
      COLOR("specular_reflectance");
      fprintf(f, "</bsdf></bsdf>\n");
      break;
    case PB_BSDF_GLASS:
      fprintf(f, "<bsdf type=\"dielectric\" id=\"b%u\"><float name=\"int_ior\" value=\"%.9g\"/>"
                 "<float name=\"ext_ior\" value=\"1\"/>", i, m->ior);
      COLOR("specular_transmittance");
      fprintf(f, "</bsdf>\n");
      break;
    case PB_BSDF_GLOSSY:
      if (m->transmission > 0.5f) {
        fprintf(f, "<bsdf type=\"roughdielectric\" id=\"b%u\"><string name=\"distribution\" value=\"ggx\"/>"
                   "<float name=\"alpha\" value=\"%.9g\"/><float name=\"int_ior\" value=\"%.9g\"/>"
                   "<float name=\"ext_ior\" value=\"1\"/>", i, alpha, m->ior);
        COLOR("specular_transmittance");
        fprintf(f, "</bsdf>\n");
      } else if (m->metallic > 0.5f) {
        fprintf(f, "<bsdf type=\"twosided\" id=\"b%u\"><bsdf type=\"roughconductor\"><string name=\"material\" "
                   "value=\"none\"/><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha\" value=\"%.9g\"/>",
                i, alpha);
        COLOR("specular_reflectance");
        fprintf(f, "</bsdf></bsdf>\n");
      } else {
        fprintf(f, "<bsdf type=\"twosided\" id=\"b%u\"><bsdf type=\"roughplastic\"><string name=\"distribution\" "
                   "value=\"ggx\"/><float name=\"alpha\" value=\"%.9g\"/><float name=\"int_ior\" value=\"%.9g\"/>"
                   "<float name=\"ext_ior\" value=\"1\"/>", i, alpha, m->ior);
        COLOR("diffuse_reflectance");
        fprintf(f, "</bsdf></bsdf>\n");
      }
      break;
    }
#undef COLOR
    fprintf(f, "<shape type=\"ply\"><string name=\"filename\" value=\"m%u.ply\"/>"
               "<boolean name=\"face_normals\" value=\"false\"/><ref id=\"b%u\"/>", i, i);
    if (pb_material_is_emissive(m)) {
      fprintf(f, "<emitter type=\"area\">");
      rgb(f, "radiance", m->emissive, 1);
      fprintf(f, "</emitter>");
    }
    fprintf(f, "</shape>\n");
  }
  fprintf(f, "</scene>\n");
  if (ferror(f)) return pb_fail(PB_ERR_IO, "%s/scene.xml: write failed", c->dir);
  return PB_OK;
}

pb_result pb_peer_export(const pb_scene *s, const pb_peer_desc *desc, const char *dir, pb_peer_report *report) {
  if (report) memset(report, 0, sizeof *report);
  if (desc->format != PB_PEER_LUXCORE && desc->format != PB_PEER_MITSUBA)
    return pb_fail(PB_ERR_USAGE, "export-peer: unknown format %d", (int)desc->format);
  if (desc->camera < 0 || (uint32_t)desc->camera >= s->camera_count)
    return pb_fail(PB_ERR_USAGE, "export-peer: camera %d out of range (the scene has %u)", desc->camera,
                   s->camera_count);
  if (!desc->width || !desc->height) return pb_fail(PB_ERR_USAGE, "export-peer: image size 0");
  if (!s->triangle_count) return pb_fail(PB_ERR_SCENE_EMPTY, "%s: no triangles to export", s->path ? s->path : "scene");
  ctx c = {.s = s, .d = desc, .dir = dir, .peer = desc->format == PB_PEER_LUXCORE ? "LuxCore" : "Mitsuba 3"};
  pb_result r = check_scene(&c);
  if (r != PB_OK) goto fail;
  if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
    r = pb_fail(PB_ERR_IO, "%s: cannot create the folder: %s", dir, strerror(errno));
    goto fail;
  }
  if (s->colors) {
    r = note(&c, "vertex colours (COLOR_0) ignored");
    if (r != PB_OK) goto fail;
  }
  uint32_t *used = calloc(s->material_count ? s->material_count : 1, sizeof *used);
  if (!used) {
    r = pb_fail(PB_ERR_NOMEM, "export-peer: out of memory");
    goto fail;
  }
  for (uint32_t i = 0; i < s->material_count && r == PB_OK; ++i) {
    uint32_t nv = 0, nt = 0;
    r = write_ply(&c, i, &nv, &nt);
    used[i] = nt;
  }
  if (r == PB_OK) {
    char path[4096];
    path_in(&c, desc->format == PB_PEER_LUXCORE ? "scene.scn" : "scene.xml", path, sizeof path);
    c.f = fopen(path, "w");
    if (!c.f) {
      r = pb_fail(PB_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
    } else {
      r = desc->format == PB_PEER_LUXCORE ? write_luxcore(&c, used) : write_mitsuba(&c, used);
      /* The notes as comments at the end of the file, too. */
      for (uint32_t i = 0; r == PB_OK && i < c.rep.note_count; ++i) {
        char line[600];
        comment_safe(c.rep.notes[i], line, sizeof line);
        if (desc->format == PB_PEER_LUXCORE)
          fprintf(c.f, "# note: %s\n", line);
        else
          fprintf(c.f, "<!-- note: %s -->\n", line);
      }
      if ((ferror(c.f) | fclose(c.f)) && r == PB_OK) r = pb_fail(PB_ERR_IO, "%s: write failed", path);
    }
  }
  free(used);
  if (r != PB_OK) goto fail;
  if (report)
    *report = c.rep;
  else
    pb_peer_report_destroy(&c.rep);
  return PB_OK;
fail:
  pb_peer_report_destroy(&c.rep);
  return r;
}
