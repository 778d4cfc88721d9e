// The tinygltf shim: parses a .gltf/.glb with tinygltf and exposes the result
// as the plain-C pb_gltf_doc (gltf_doc.h). C++ stays inside this file.
//
// Before tinygltf sees the file, this shim checks what tinygltf would trust or
// do unsafely: the GLB container (magic, version, chunk lengths), the
// required extensions, and every buffer URI (inside the scene folder, base64
// well formed, size equal to byteLength). tinygltf's own file search also looks
// in the current directory; our file-system callbacks refuse anything that the
// URI check did not approve.

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_USE_CPP14
#include <tiny_gltf.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <set>
#include <string>
#include <vector>

extern "C" {
#include "core/fs.h"
#include "scene/gltf_doc.h"
}

namespace {

struct Impl {
  tinygltf::Model model;
  std::vector<pb_gltf_buffer> buffers;
  std::vector<pb_gltf_buffer_view> views;
  std::vector<pb_gltf_accessor> accessors;
  std::vector<std::vector<pb_gltf_primitive>> prims;
  std::vector<pb_gltf_mesh> meshes;
  std::vector<std::vector<int32_t>> children;
  std::vector<pb_gltf_node> nodes;
  std::vector<std::vector<int32_t>> scene_nodes;
  std::vector<pb_gltf_scene> scenes;
  std::vector<pb_gltf_camera> cameras;
  std::vector<pb_gltf_light> lights;
  std::vector<pb_gltf_material> materials;
  std::vector<pb_gltf_texture> textures;
  std::vector<pb_gltf_image> images;
  std::vector<pb_gltf_sampler> samplers;
  std::vector<const char *> ext_used, ext_required;
  std::set<std::string> approved;  // files the URI check allowed
};

struct FsCtx {
  std::set<std::string> *approved;
  uint64_t max_bytes;
};

std::string one_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' '))
    s.pop_back();
  for (char &c : s)
    if (c == '\n' || c == '\r') c = ';';
  return s;
}

// tinygltf joins the folder and the URI itself; compare canonical paths.
bool approved(const FsCtx *ctx, const std::string &p) {
  char *real = realpath(p.c_str(), nullptr);
  bool ok = real && ctx->approved->count(real) != 0;
  free(real);
  return ok;
}
bool fs_exists(const std::string &p, void *u) {
  return approved(static_cast<FsCtx *>(u), p);
}
std::string fs_expand(const std::string &p, void *) { return p; }
bool fs_read(std::vector<unsigned char> *out, std::string *err,
             const std::string &p, void *u) {
  auto *ctx = static_cast<FsCtx *>(u);
  if (!approved(ctx, p)) {
    if (err) *err = "refused";
    return false;
  }
  uint8_t *data = nullptr;
  size_t n = 0;
  if (pb_read_file(p.c_str(), ctx->max_bytes, &data, &n) != PB_OK) {
    if (err) *err = pb_error_message();
    pb_error_clear();
    return false;
  }
  out->assign(data, data + n);
  free(data);
  return true;
}
bool fs_write(std::string *err, const std::string &, const std::vector<unsigned char> &,
              void *) {
  if (err) *err = "writing is disabled";
  return false;
}

uint32_t rd32(const uint8_t *p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
         (uint32_t)p[3] << 24;
}

// GLB container (glTF 2.0 spec, "Binary glTF Layout"): 12-byte header, a JSON
// chunk first, then an optional BIN chunk. Every length is checked against the
// file so tinygltf never reads past it.
pb_result check_glb(const char *path, const uint8_t *d, size_t n, std::string *json_text) {
  if (n < 12) return pb_fail(PB_ERR_SCENE_PARSE, "%s: GLB header: file is %zu bytes, shorter than the 12-byte header", path, n);
  uint32_t version = rd32(d + 4), length = rd32(d + 8);
  if (version != 2)
    return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: GLB header: version %u (only glTF 2.0 is supported)", path, version);
  if (length != n)
    return pb_fail(PB_ERR_SCENE_PARSE, "%s: GLB header: declared length %u differs from the file size %zu", path, length, n);
  size_t off = 12;
  int chunk = 0;
  while (off < n) {
    if (n - off < 8)
      return pb_fail(PB_ERR_SCENE_PARSE, "%s: GLB chunk %d: truncated chunk header at byte %zu", path, chunk, off);
    uint32_t clen = rd32(d + off), ctype = rd32(d + off + 4);
    if (clen > n - off - 8)
      return pb_fail(PB_ERR_SCENE_PARSE, "%s: GLB chunk %d: length %u exceeds the %zu bytes left in the file", path, chunk, clen, n - off - 8);
    if (clen % 4 != 0)
      return pb_fail(PB_ERR_SCENE_PARSE, "%s: GLB chunk %d: length %u is not a multiple of 4", path, chunk, clen);
    if (chunk == 0) {
      if (ctype != 0x4E4F534Au)
        return pb_fail(PB_ERR_SCENE_PARSE, "%s: GLB chunk 0: type 0x%08x, expected JSON", path, ctype);
      json_text->assign(reinterpret_cast<const char *>(d + off + 8), clen);
    } else if (chunk == 1 && ctype != 0x004E4942u) {
      // Unknown chunks after JSON are allowed by the spec, but the BIN chunk,
      // if present, must be the second one; tinygltf assumes so.
      return pb_fail(PB_ERR_SCENE_PARSE, "%s: GLB chunk 1: type 0x%08x, expected BIN", path, ctype);
    }
    off += 8 + clen;
    chunk++;
  }
  if (chunk == 0) return pb_fail(PB_ERR_SCENE_PARSE, "%s: GLB: no JSON chunk", path);
  return PB_OK;
}

bool is_b64(unsigned char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
         c == '+' || c == '/';
}

// Decoded size of a strict base64 payload, or -1 when malformed.
long long b64_size(const std::string &s) {
  size_t n = s.size();
  if (n % 4 != 0) return -1;
  size_t pad = 0;
  for (size_t i = 0; i < n; ++i) {
    unsigned char c = (unsigned char)s[i];
    if (c == '=') {
      if (i < n - 2) return -1;
      pad++;
    } else if (pad || !is_b64(c)) {
      return -1;
    }
  }
  return (long long)(n / 4 * 3 - pad);
}

using Json = nlohmann::json;

// Checks what tinygltf would take on trust: required extensions and buffers.
pb_result precheck(const char *path, const std::string &text, bool is_glb,
                   const pb_gltf_read_desc *desc, std::set<std::string> *approved) {
  Json j = Json::parse(text, nullptr, false);
  if (j.is_discarded())
    return pb_fail(PB_ERR_SCENE_PARSE, "%s: not valid JSON", path);
  if (!j.is_object()) return pb_fail(PB_ERR_SCENE_PARSE, "%s: top level is not a JSON object", path);
  auto asset = j.find("asset");
  if (asset == j.end() || !asset->is_object())
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: asset: missing (required by glTF 2.0)", path);
  auto ver = asset->find("version");
  if (ver == asset->end() || !ver->is_string())
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: asset.version: missing", path);
  std::string v = ver->get<std::string>();
  if (v.rfind("2.", 0) != 0)
    return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: asset.version: '%s' (only glTF 2.x is supported)", path, v.c_str());

  static const char *const supported[] = {
      "KHR_lights_punctual",  "KHR_materials_specular", "KHR_materials_transmission",
      "KHR_materials_ior",    "KHR_materials_emissive_strength", "KHR_texture_transform",
      "KHR_materials_volume", "KHR_materials_clearcoat", "KHR_materials_sheen",
      "KHR_mesh_quantization"};
  auto req = j.find("extensionsRequired");
  if (req != j.end()) {
    if (!req->is_array()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: extensionsRequired: not an array", path);
    for (size_t i = 0; i < req->size(); ++i) {
      const Json &e = (*req)[i];
      if (!e.is_string()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: extensionsRequired[%zu]: not a string", path, i);
      std::string name = e.get<std::string>();
      bool ok = false;
      for (const char *s : supported) ok |= name == s;
      // Quantized attributes and texture transforms are read-critical; we
      // accept the names only where load.c handles the data (it refuses
      // non-float positions), so list them as unsupported when required.
      if (name == "KHR_texture_transform" || name == "KHR_mesh_quantization") ok = false;
      if (!ok)
        return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: extensionsRequired[%zu]: '%s' is not supported (re-export without it%s)", path, i, name.c_str(),
                       name == "KHR_draco_mesh_compression" ? ", i.e. with Blender's 'Compression' off" : "");
    }
  }

  auto bufs = j.find("buffers");
  if (bufs == j.end()) return PB_OK;
  if (!bufs->is_array()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: buffers: not an array", path);
  for (size_t i = 0; i < bufs->size(); ++i) {
    const Json &b = (*bufs)[i];
    if (!b.is_object()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: buffers[%zu]: not an object", path, i);
    auto bl = b.find("byteLength");
    if (bl == b.end() || !bl->is_number_integer() || bl->get<long long>() < 1)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: buffers[%zu].byteLength: missing or not a positive integer", path, i);
    unsigned long long declared = bl->get<unsigned long long>();
    if (declared > desc->max_file_bytes)
      return pb_fail(PB_ERR_LIMIT, "%s: buffers[%zu].byteLength: %llu bytes is over the limit", path, i, declared);
    auto uri = b.find("uri");
    if (uri == b.end()) {
      if (!is_glb || i != 0)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: buffers[%zu]: no uri (only the first buffer of a .glb may omit it)", path, i);
      continue;
    }
    if (!uri->is_string()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: buffers[%zu].uri: not a string", path, i);
    std::string u = uri->get<std::string>();
    if (u.rfind("data:", 0) == 0) {
      size_t comma = u.find(',');
      if (comma == std::string::npos || u.compare(comma - 7, 7, ";base64") != 0)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: buffers[%zu].uri: data URI is not base64", path, i);
      long long sz = b64_size(u.substr(comma + 1));
      if (sz < 0)
        return pb_fail(PB_ERR_SCENE_PARSE, "%s: buffers[%zu].uri: malformed base64 data", path, i);
      if ((unsigned long long)sz < declared)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: buffers[%zu].uri: %lld bytes of data, byteLength says %llu", path, i, sz, declared);
      continue;
    }
    char where[64];
    snprintf(where, sizeof where, "buffers[%zu].uri", i);
    char *file = nullptr;
    pb_result r = pb_gltf_resolve_uri(path, u.c_str(), desc->allow_external_files, where, &file);
    if (r != PB_OK) return r;
    FILE *f = fopen(file, "rb");
    if (!f) {
      pb_fail(PB_ERR_IO, "%s: %s: cannot open '%s': %s", path, where, u.c_str(), strerror(errno));
      free(file);
      return PB_ERR_IO;
    }
    fseek(f, 0, SEEK_END);
    long sz = ftell(f);
    fclose(f);
    if (sz < 0 || (unsigned long long)sz != declared) {
      pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: '%s' is %ld bytes, byteLength says %llu", path, where, u.c_str(), sz, declared);
      free(file);
      return PB_ERR_SCENE_INVALID;
    }
    approved->insert(file);
    free(file);
  }
  return PB_OK;
}

const char *s(const std::string &x) { return x.c_str(); }

void fill_tex(pb_gltf_texture_ref *t, int index, int texcoord, double scale) {
  t->index = index;
  t->texcoord = texcoord;
  t->scale = scale;
}

double num_or(const tinygltf::Value &v, const char *key, double dflt) {
  if (!v.IsObject() || !v.Has(key)) return dflt;
  const tinygltf::Value &x = v.Get(key);
  return x.IsNumber() ? x.GetNumberAsDouble() : dflt;
}

void convert(Impl &m, pb_gltf_doc *doc) {
  tinygltf::Model &g = m.model;
  doc->generator = s(g.asset.generator);
  for (auto &e : g.extensionsUsed) m.ext_used.push_back(s(e));
  for (auto &e : g.extensionsRequired) m.ext_required.push_back(s(e));
  doc->default_scene = g.defaultScene;

  for (auto &b : g.buffers) {
    pb_gltf_buffer x{};
    x.data = b.data.data();
    x.size = b.data.size();
    x.byte_length = b.data.size();
    x.uri = s(b.uri);
    m.buffers.push_back(x);
  }
  for (auto &v : g.bufferViews) {
    pb_gltf_buffer_view x{};
    x.buffer = v.buffer;
    x.byte_offset = v.byteOffset;
    x.byte_length = v.byteLength;
    x.byte_stride = (uint32_t)v.byteStride;
    m.views.push_back(x);
  }
  for (auto &a : g.accessors) {
    pb_gltf_accessor x{};
    x.buffer_view = a.bufferView;
    x.byte_offset = a.byteOffset;
    x.component_type = a.componentType;
    int nc = tinygltf::GetNumComponentsInType((uint32_t)a.type);
    x.components = nc < 0 ? 0 : nc;
    x.count = a.count;
    x.normalized = a.normalized;
    x.sparse = a.sparse.isSparse;
    if (a.minValues.size() >= 3 && a.maxValues.size() >= 3) {
      x.has_min_max = 1;
      for (int k = 0; k < 3; ++k) {
        x.min[k] = a.minValues[(size_t)k];
        x.max[k] = a.maxValues[(size_t)k];
      }
    }
    m.accessors.push_back(x);
  }
  m.prims.resize(g.meshes.size());
  for (size_t i = 0; i < g.meshes.size(); ++i) {
    for (auto &p : g.meshes[i].primitives) {
      pb_gltf_primitive x{};
      x.mode = p.mode;
      auto at = [&](const char *k) {
        auto it = p.attributes.find(k);
        return it == p.attributes.end() ? -1 : it->second;
      };
      x.position = at("POSITION");
      x.normal = at("NORMAL");
      x.texcoord0 = at("TEXCOORD_0");
      x.indices = p.indices;
      x.material = p.material;
      x.has_targets = !p.targets.empty();
      m.prims[i].push_back(x);
    }
  }
  for (size_t i = 0; i < g.meshes.size(); ++i) {
    pb_gltf_mesh x{};
    x.name = s(g.meshes[i].name);
    x.primitives = m.prims[i].data();
    x.primitive_count = m.prims[i].size();
    m.meshes.push_back(x);
  }
  m.children.resize(g.nodes.size());
  for (size_t i = 0; i < g.nodes.size(); ++i) {
    auto &n = g.nodes[i];
    for (int c : n.children) m.children[i].push_back(c);
    pb_gltf_node x{};
    x.name = s(n.name);
    x.children = m.children[i].data();
    x.child_count = m.children[i].size();
    x.mesh = n.mesh;
    x.camera = n.camera;
    x.skin = n.skin;
    x.light = -1;
    auto le = n.extensions.find("KHR_lights_punctual");
    if (le != n.extensions.end()) x.light = (int32_t)num_or(le->second, "light", -2);
    x.has_matrix = n.matrix.size() == 16;
    for (size_t k = 0; k < 16; ++k) x.matrix[k] = x.has_matrix ? n.matrix[k] : (k % 5 == 0);
    x.translation[0] = x.translation[1] = x.translation[2] = 0;
    x.rotation[0] = x.rotation[1] = x.rotation[2] = 0;
    x.rotation[3] = 1;
    x.scale[0] = x.scale[1] = x.scale[2] = 1;
    if (n.translation.size() == 3) for (size_t k = 0; k < 3; ++k) x.translation[k] = n.translation[k];
    if (n.rotation.size() == 4) for (size_t k = 0; k < 4; ++k) x.rotation[k] = n.rotation[k];
    if (n.scale.size() == 3) for (size_t k = 0; k < 3; ++k) x.scale[k] = n.scale[k];
    m.nodes.push_back(x);
  }
  m.scene_nodes.resize(g.scenes.size());
  for (size_t i = 0; i < g.scenes.size(); ++i) {
    for (int r : g.scenes[i].nodes) m.scene_nodes[i].push_back(r);
    pb_gltf_scene x{};
    x.name = s(g.scenes[i].name);
    x.nodes = m.scene_nodes[i].data();
    x.node_count = m.scene_nodes[i].size();
    m.scenes.push_back(x);
  }
  for (auto &c : g.cameras) {
    pb_gltf_camera x{};
    x.name = s(c.name);
    x.type = s(c.type);
    x.perspective = c.type == "perspective";
    x.yfov = c.perspective.yfov;
    x.aspect_ratio = c.perspective.aspectRatio;
    x.znear = c.perspective.znear;
    x.zfar = c.perspective.zfar;
    m.cameras.push_back(x);
  }
  for (auto &l : g.lights) {
    pb_gltf_light x{};
    x.name = s(l.name);
    x.type = s(l.type);
    x.color[0] = x.color[1] = x.color[2] = 1;
    if (l.color.size() == 3) for (size_t k = 0; k < 3; ++k) x.color[k] = l.color[k];
    x.intensity = l.intensity;
    x.range = l.range;
    x.inner_cone = l.spot.innerConeAngle;
    x.outer_cone = l.spot.outerConeAngle;
    m.lights.push_back(x);
  }
  for (auto &mt : g.materials) {
    pb_gltf_material x{};
    auto &pbr = mt.pbrMetallicRoughness;
    x.name = s(mt.name);
    for (size_t k = 0; k < 4; ++k) x.base_color[k] = pbr.baseColorFactor.size() == 4 ? pbr.baseColorFactor[k] : 1.0;
    fill_tex(&x.base_color_tex, pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, 1);
    x.metallic = pbr.metallicFactor;
    x.roughness = pbr.roughnessFactor;
    fill_tex(&x.metallic_roughness_tex, pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord, 1);
    fill_tex(&x.normal_tex, mt.normalTexture.index, mt.normalTexture.texCoord, mt.normalTexture.scale);
    fill_tex(&x.emissive_tex, mt.emissiveTexture.index, mt.emissiveTexture.texCoord, 1);
    for (size_t k = 0; k < 3; ++k) x.emissive[k] = mt.emissiveFactor.size() == 3 ? mt.emissiveFactor[k] : 0.0;
    x.emissive_strength = 1;
    x.specular = 1;
    x.specular_color[0] = x.specular_color[1] = x.specular_color[2] = 1;
    x.ior = 1.5;
    auto ext = [&](const char *k) -> const tinygltf::Value * {
      auto it = mt.extensions.find(k);
      return it == mt.extensions.end() ? nullptr : &it->second;
    };
    if (auto *e = ext("KHR_materials_emissive_strength")) x.emissive_strength = num_or(*e, "emissiveStrength", 1);
    if (auto *e = ext("KHR_materials_specular")) {
      x.has_specular = 1;
      x.specular = num_or(*e, "specularFactor", 1);
      if (e->Has("specularColorFactor")) {
        const tinygltf::Value &c = e->Get("specularColorFactor");
        if (c.IsArray() && c.ArrayLen() == 3)
          for (int k = 0; k < 3; ++k)
            x.specular_color[k] = c.Get(k).IsNumber() ? c.Get(k).GetNumberAsDouble() : 1;
      }
    }
    if (auto *e = ext("KHR_materials_transmission")) x.transmission = num_or(*e, "transmissionFactor", 0);
    if (auto *e = ext("KHR_materials_ior")) x.ior = num_or(*e, "ior", 1.5);
    x.alpha_mode = s(mt.alphaMode);
    x.alpha_cutoff = mt.alphaCutoff;
    x.double_sided = mt.doubleSided;
    m.materials.push_back(x);
  }
  for (auto &t : g.textures) m.textures.push_back(pb_gltf_texture{t.source, t.sampler});
  for (auto &im : g.images) {
    pb_gltf_image x{};
    x.name = s(im.name);
    x.uri = s(im.uri);
    x.mime_type = s(im.mimeType);
    x.buffer_view = im.bufferView;
    m.images.push_back(x);
  }
  for (auto &sm : g.samplers) m.samplers.push_back(pb_gltf_sampler{sm.magFilter, sm.minFilter, sm.wrapS, sm.wrapT});

  size_t channels = 0;
  for (auto &a : g.animations) channels += a.channels.size();
  doc->animation_count = g.animations.size();
  doc->animation_channel_count = channels;
  doc->skin_count = g.skins.size();

#define PB_SET(field, count, vec) doc->field = m.vec.data(), doc->count = m.vec.size()
  PB_SET(buffers, buffer_count, buffers);
  PB_SET(buffer_views, buffer_view_count, views);
  PB_SET(accessors, accessor_count, accessors);
  PB_SET(meshes, mesh_count, meshes);
  PB_SET(nodes, node_count, nodes);
  PB_SET(scenes, scene_count, scenes);
  PB_SET(cameras, camera_count, cameras);
  PB_SET(lights, light_count, lights);
  PB_SET(materials, material_count, materials);
  PB_SET(textures, texture_count, textures);
  PB_SET(images, image_count, images);
  PB_SET(samplers, sampler_count, samplers);
#undef PB_SET
  doc->extensions_used = m.ext_used.data();
  doc->extensions_used_count = m.ext_used.size();
  doc->extensions_required = m.ext_required.data();
  doc->extensions_required_count = m.ext_required.size();
}

}  // namespace

extern "C" pb_result pb_gltf_doc_read(const char *path, const pb_gltf_read_desc *desc,
                                      pb_gltf_doc *doc) {
  std::memset(doc, 0, sizeof *doc);
  uint8_t *data = nullptr;
  size_t n = 0;
  pb_result r = pb_read_file(path, desc->max_file_bytes, &data, &n);
  if (r != PB_OK) return r;
  std::unique_ptr<uint8_t, decltype(&free)> hold(data, &free);

  bool is_glb = n >= 4 && std::memcmp(data, "glTF", 4) == 0;
  std::string text;
  if (is_glb) {
    r = check_glb(path, data, n, &text);
    if (r != PB_OK) return r;
  } else {
    text.assign(reinterpret_cast<const char *>(data), n);
  }

  std::unique_ptr<Impl> impl;
  try {
    impl.reset(new Impl);
    r = precheck(path, text, is_glb, desc, &impl->approved);
    if (r != PB_OK) return r;

    FsCtx ctx{&impl->approved, desc->max_file_bytes};
    tinygltf::FsCallbacks fs{fs_exists, fs_expand, fs_read, fs_write, &ctx};
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(fs);
    std::string err, warn;
    char *dir = pb_dirname(path);
    std::string base = dir ? dir : ".";
    free(dir);
    bool ok = is_glb ? loader.LoadBinaryFromMemory(&impl->model, &err, &warn, data,
                                                   (unsigned)n, base)
                     : loader.LoadASCIIFromString(&impl->model, &err, &warn, text.c_str(),
                                                  (unsigned)text.size(), base);
    if (!ok)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s", path,
                     one_line(err.empty() ? "tinygltf could not read the file" : err).c_str());
    convert(*impl, doc);
  } catch (const std::bad_alloc &) {
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory while parsing", path);
  } catch (const std::exception &e) {
    return pb_fail(PB_ERR_SCENE_PARSE, "%s: %s", path, one_line(e.what()).c_str());
  }
  doc->impl = impl.release();
  return PB_OK;
}

extern "C" void pb_gltf_doc_destroy(pb_gltf_doc *doc) {
  if (!doc) return;
  delete static_cast<Impl *>(doc->impl);
  std::memset(doc, 0, sizeof *doc);
}
