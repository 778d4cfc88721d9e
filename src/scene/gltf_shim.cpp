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

#include <sys/stat.h>

#include <cstdlib>
#include <cstring>
#include <deque>
#include <functional>
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
  std::vector<std::vector<pb_gltf_anim_sampler>> anim_samplers;
  std::vector<std::vector<pb_gltf_anim_channel>> anim_channels;
  std::vector<pb_gltf_animation> animations;
  std::vector<const char *> ext_used, ext_required;
  std::set<std::string> approved;  // files the URI check allowed
  // Extensions handed over whole (pb_gltf_value): the roots, every array of
  // elements or members, every member name and string. Deques, so that
  // growing them keeps what earlier values point to.
  std::deque<pb_gltf_value> value_roots;
  std::deque<std::vector<pb_gltf_value>> value_items;
  std::deque<std::vector<const char *>> value_keys;
  std::deque<std::string> value_strings;
};

struct FsCtx {
  std::set<std::string> *approved;
  uint64_t max_bytes;
  std::string base;  // the folder tinygltf joins URIs to
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
// tinygltf joins even an absolute URI to the folder ("dir//abs/file.bin"); an
// absolute URI the precheck allowed (--allow-external-files) is used as is.
std::string fs_expand(const std::string &p, void *u) {
  const std::string &b = static_cast<FsCtx *>(u)->base;
  std::string prefix = !b.empty() && b.back() == '/' ? b : b + "/";
  if (p.size() > prefix.size() && p.compare(0, prefix.size(), prefix) == 0 && p[prefix.size()] == '/')
    return p.substr(prefix.size());
  return p;
}
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
pb_result check_glb(const char *path, const uint8_t *d, size_t n, std::string *json_text,
                    long long *bin_len) {
  *bin_len = -1;
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
    } else if (chunk == 1) {
      *bin_len = clen;
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

// tinygltf copies "extras" and unknown extensions with a recursive parse; a
// file nested 100000 deep overflows the stack. glTF itself nests about 8 deep.
enum { MAX_JSON_DEPTH = 256 };
pb_result check_depth(const char *path, const std::string &text) {
  int depth = 0;
  bool in_str = false, esc = false;
  for (size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (in_str) {
      if (esc) esc = false;
      else if (c == '\\') esc = true;
      else if (c == '"') in_str = false;
    } else if (c == '"') {
      in_str = true;
    } else if (c == '[' || c == '{') {
      if (++depth > MAX_JSON_DEPTH)
        return pb_fail(PB_ERR_LIMIT, "%s: JSON nested deeper than %d levels (at byte %zu)", path, MAX_JSON_DEPTH, i);
    } else if (c == ']' || c == '}') {
      depth--;
    }
  }
  return PB_OK;
}

// An optional array member: nullptr when absent; *bad when not an array.
const Json *array_member(const Json &o, const char *key, bool *bad) {
  auto it = o.find(key);
  if (it == o.end()) return nullptr;
  if (!it->is_array()) *bad = true;
  return it->is_array() ? &*it : nullptr;
}
bool get_index(const Json &o, const char *key, long long *out) {
  auto it = o.find(key);
  if (it == o.end() || !it->is_number_integer()) return false;
  *out = it->get<long long>();
  return true;
}

// glTF ids are integers >= 0. tinygltf truncates big ones to int
// (4294967296 becomes 0) and drops other types (1.5, "1", null), so a broken
// reference would load as another object, or as none: refuse them here.
bool is_id(const Json &v) { return v.is_number_unsigned() && v.get<unsigned long long>() <= INT32_MAX; }
std::string member_path(const std::string &where, const char *key) {
  return where.empty() ? std::string(key) : where + "." + key;
}
pb_result check_id(const char *path, const Json &o, const char *key, const std::string &where) {
  auto it = o.is_object() ? o.find(key) : o.end();
  if (it == o.end() || is_id(*it)) return PB_OK;
  return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: %s is not an index (an integer from 0 to 2^31-1)", path,
                 member_path(where, key).c_str(), it->dump().c_str());
}
pb_result check_offset(const char *path, const Json &o, const char *key, const std::string &where) {
  auto it = o.is_object() ? o.find(key) : o.end();
  if (it == o.end() || it->is_number_unsigned()) return PB_OK;
  return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: %s is not a non-negative integer", path, member_path(where, key).c_str(),
                 it->dump().c_str());
}
pb_result check_id_array(const char *path, const Json &o, const char *key, const std::string &where) {
  auto it = o.is_object() ? o.find(key) : o.end();
  if (it == o.end()) return PB_OK;
  std::string w = member_path(where, key);
  if (!it->is_array()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: not an array", path, w.c_str());
  for (size_t i = 0; i < it->size(); ++i)
    if (!is_id((*it)[i]))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s[%zu]: %s is not an index (an integer from 0 to 2^31-1)", path, w.c_str(), i,
                     (*it)[i].dump().c_str());
  return PB_OK;
}

pb_result precheck_ids(const char *path, const Json &j) {
  pb_result r = check_id(path, j, "scene", "");
  auto each = [&](const char *key, const std::function<pb_result(const Json &, const std::string &)> &fn) {
    auto arr = j.find(key);
    if (r != PB_OK || arr == j.end() || !arr->is_array()) return;
    for (size_t i = 0; i < arr->size() && r == PB_OK; ++i)
      r = fn((*arr)[i], std::string(key) + "[" + std::to_string(i) + "]");
  };
  each("scenes", [&](const Json &o, const std::string &w) { return check_id_array(path, o, "nodes", w); });
  each("nodes", [&](const Json &o, const std::string &w) {
    pb_result x = check_id_array(path, o, "children", w);
    for (const char *k : {"mesh", "camera", "skin"})
      if (x == PB_OK) x = check_id(path, o, k, w);
    auto ext = o.is_object() ? o.find("extensions") : o.end();
    if (x == PB_OK && ext != o.end() && ext->is_object() && ext->contains("KHR_lights_punctual"))
      x = check_id(path, (*ext)["KHR_lights_punctual"], "light", w + ".extensions.KHR_lights_punctual");
    return x;
  });
  each("meshes", [&](const Json &o, const std::string &w) {
    auto prims = o.is_object() ? o.find("primitives") : o.end();
    pb_result x = PB_OK;
    for (size_t i = 0; prims != o.end() && prims->is_array() && i < prims->size() && x == PB_OK; ++i) {
      const Json &p = (*prims)[i];
      std::string pw = w + ".primitives[" + std::to_string(i) + "]";
      for (const char *k : {"indices", "material", "mode"})
        if (x == PB_OK) x = check_id(path, p, k, pw);
      auto at = p.is_object() ? p.find("attributes") : p.end();
      if (at != p.end() && at->is_object())
        for (auto a = at->begin(); a != at->end() && x == PB_OK; ++a)
          x = check_id(path, *at, a.key().c_str(), pw + ".attributes");
    }
    return x;
  });
  each("accessors", [&](const Json &o, const std::string &w) {
    pb_result x = check_id(path, o, "bufferView", w);
    return x == PB_OK ? check_offset(path, o, "byteOffset", w) : x;
  });
  each("bufferViews", [&](const Json &o, const std::string &w) {
    pb_result x = check_id(path, o, "buffer", w);
    return x == PB_OK ? check_offset(path, o, "byteOffset", w) : x;
  });
  each("textures", [&](const Json &o, const std::string &w) {
    pb_result x = check_id(path, o, "source", w);
    return x == PB_OK ? check_id(path, o, "sampler", w) : x;
  });
  each("images", [&](const Json &o, const std::string &w) { return check_id(path, o, "bufferView", w); });
  each("materials", [&](const Json &o, const std::string &w) {
    pb_result x = PB_OK;
    auto pbr = o.is_object() ? o.find("pbrMetallicRoughness") : o.end();
    for (const char *t : {"baseColorTexture", "metallicRoughnessTexture"})
      if (x == PB_OK && pbr != o.end() && pbr->is_object() && pbr->contains(t)) {
        std::string tw = w + ".pbrMetallicRoughness." + t;
        x = check_id(path, (*pbr)[t], "index", tw);
        if (x == PB_OK) x = check_id(path, (*pbr)[t], "texCoord", tw);
      }
    for (const char *t : {"normalTexture", "occlusionTexture", "emissiveTexture"})
      if (x == PB_OK && o.is_object() && o.contains(t)) {
        x = check_id(path, o[t], "index", w + "." + t);
        if (x == PB_OK) x = check_id(path, o[t], "texCoord", w + "." + t);
      }
    // tinygltf keeps only objects as extensions: a PHOTONBRIDGE_blender of
    // another type would vanish instead of being refused.
    auto ext = o.is_object() ? o.find("extensions") : o.end();
    if (x == PB_OK && ext != o.end() && ext->is_object()) {
      auto pb = ext->find("PHOTONBRIDGE_blender");
      if (pb != ext->end() && !pb->is_object())
        x = pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.extensions.PHOTONBRIDGE_blender: %s, expected an object", path,
                    w.c_str(), pb->is_string() ? "a string" : pb->is_array() ? "an array" : pb->is_number() ? "a number"
                                                                                                          : "not an object");
    }
    return x;
  });
  return r;
}

// What tinygltf refuses itself with messages that name no JSON path (or
// trusts, as the byte offset of an image's bufferView): checked here first so
// that the error reads "FILE: accessors[3].count: ...". `declared` holds each
// buffer's byteLength.
pb_result precheck_objects(const char *path, const Json &j, const std::vector<unsigned long long> &declared) {
  pb_result ir = precheck_ids(path, j);
  if (ir != PB_OK) return ir;
  bool bad = false;
  const Json *views = array_member(j, "bufferViews", &bad);
  if (bad) return pb_fail(PB_ERR_SCENE_INVALID, "%s: bufferViews: not an array", path);
  size_t n_views = views ? views->size() : 0;
  for (size_t i = 0; i < n_views; ++i) {
    const Json &v = (*views)[i];
    if (!v.is_object()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: bufferViews[%zu]: not an object", path, i);
    auto bl = v.find("byteLength");
    if (bl == v.end() || !bl->is_number_unsigned() || bl->get<unsigned long long>() < 1)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: bufferViews[%zu].byteLength: missing or not a positive integer", path, i);
    if (v.find("buffer") == v.end())
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: bufferViews[%zu].buffer: missing", path, i);
    auto st = v.find("byteStride");
    if (st != v.end()) {
      unsigned long long x = st->is_number_unsigned() ? st->get<unsigned long long>() : 0;
      if (x < 4 || x > 252 || x % 4)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: bufferViews[%zu].byteStride: %s is not a multiple of 4 in [4, 252]", path, i,
                       st->dump().c_str());
    }
  }
  const Json *accs = array_member(j, "accessors", &bad);
  if (bad) return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors: not an array", path);
  size_t n_acc = accs ? accs->size() : 0;
  static const char *const types[] = {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"};
  for (size_t i = 0; i < n_acc; ++i) {
    const Json &a = (*accs)[i];
    if (!a.is_object()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%zu]: not an object", path, i);
    auto c = a.find("count");
    if (c == a.end()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%zu].count: missing", path, i);
    if (!c->is_number_unsigned())
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%zu].count: %s is not a non-negative integer", path, i,
                     c->dump().c_str());
    auto t = a.find("type");
    if (t == a.end()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%zu].type: missing", path, i);
    bool ok = false;
    if (t->is_string())
      for (const char *x : types) ok |= t->get<std::string>() == x;
    if (!ok)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%zu].type: %s is not SCALAR, VEC2..4 or MAT2..4", path, i,
                     t->dump().c_str());
    long long ct = 0;
    if (!get_index(a, "componentType", &ct) || ct < 5120 || ct > 5126 || ct == 5124)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%zu].componentType: missing or not a glTF component type", path, i);
  }
  // tinygltf reads each indices accessor's bufferView while parsing.
  const Json *meshes = array_member(j, "meshes", &bad);
  for (size_t m = 0; meshes && m < meshes->size(); ++m) {
    const Json &mesh = (*meshes)[m];
    const Json *prims = mesh.is_object() ? array_member(mesh, "primitives", &bad) : nullptr;
    for (size_t p = 0; prims && p < prims->size(); ++p) {
      const Json &prim = (*prims)[p];
      long long ia = 0, bv = 0;
      if (!prim.is_object() || !get_index(prim, "indices", &ia)) continue;
      if (ia < 0 || (unsigned long long)ia >= n_acc)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: meshes[%zu].primitives[%zu].indices: accessor %lld does not exist (%zu accessors)",
                       path, m, p, ia, n_acc);
      if (!get_index((*accs)[(size_t)ia], "bufferView", &bv))
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%lld].bufferView: missing (used as meshes[%zu].primitives[%zu].indices)",
                       path, ia, m, p);
      if (bv < 0 || (unsigned long long)bv >= n_views)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%lld].bufferView: %lld does not exist (%zu bufferViews)", path, ia,
                       bv, n_views);
    }
  }
  // Images: tinygltf takes the address of an image bufferView's first byte
  // and base64-decodes data URIs before load.c sees them.
  const Json *images = array_member(j, "images", &bad);
  for (size_t i = 0; images && i < images->size(); ++i) {
    const Json &im = (*images)[i];
    if (!im.is_object()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: images[%zu]: not an object", path, i);
    long long bv = 0;
    if (get_index(im, "bufferView", &bv)) {
      if (bv < 0 || (unsigned long long)bv >= n_views)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: images[%zu].bufferView: %lld does not exist (%zu bufferViews)", path, i, bv,
                       n_views);
      const Json &v = (*views)[(size_t)bv];
      long long b = 0;
      get_index(v, "buffer", &b);
      if (b < 0 || (unsigned long long)b >= declared.size())
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: bufferViews[%lld].buffer: %lld does not exist (%zu buffers)", path, bv, b,
                       declared.size());
      long long off = 0;
      get_index(v, "byteOffset", &off);
      unsigned long long len = v["byteLength"].get<unsigned long long>();
      if (off < 0 || (unsigned long long)off >= declared[(size_t)b] || len > declared[(size_t)b] - (unsigned long long)off)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: bufferViews[%lld]: offset %lld + length %llu exceeds buffers[%lld] (%llu bytes)",
                       path, bv, off, len, b, declared[(size_t)b]);
      continue;
    }
    auto uri = im.find("uri");
    if (uri == im.end() || !uri->is_string())
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: images[%zu]: neither uri nor bufferView", path, i);
    if (uri->get<std::string>().rfind("data:", 0) == 0)
      return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: images[%zu].uri: embedded data URI images are not supported (export with separate or GLB images)",
                     path, i);
  }
  return PB_OK;
}

// Checks what tinygltf would take on trust: required extensions and buffers.
pb_result precheck(const char *path, const std::string &text, bool is_glb, long long bin_len,
                   const pb_gltf_read_desc *desc, std::set<std::string> *approved) {
  pb_result dr = check_depth(path, text);
  if (dr != PB_OK) return dr;
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

  std::vector<unsigned long long> declared_lengths;
  auto bufs = j.find("buffers");
  if (bufs == j.end()) return precheck_objects(path, j, declared_lengths);
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
    declared_lengths.push_back(declared);
    auto uri = b.find("uri");
    if (uri == b.end()) {
      if (!is_glb || i != 0)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: buffers[%zu]: no uri (only the first buffer of a .glb may omit it)", path, i);
      if (bin_len < 0)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: buffers[0]: no uri, and the file has no BIN chunk", path);
      if (declared > (unsigned long long)bin_len)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: buffers[0].byteLength: %llu exceeds the BIN chunk (%lld bytes)", path,
                       declared, bin_len);
      continue;
    }
    if (!uri->is_string()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: buffers[%zu].uri: not a string", path, i);
    std::string u = uri->get<std::string>();
    if (u.rfind("data:", 0) == 0) {
      size_t comma = u.find(',');
      if (comma == std::string::npos || comma < 7 || u.compare(comma - 7, 7, ";base64") != 0)
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
    struct stat st;
    bool regular = fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode);
    fclose(f);
    if (!regular) {
      pb_fail(PB_ERR_IO, "%s: %s: '%s' is not a regular file", path, where, u.c_str());
      free(file);
      return PB_ERR_IO;
    }
    long long sz = (long long)st.st_size;
    if ((unsigned long long)sz != declared) {
      pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: '%s' is %lld bytes, byteLength says %llu", path, where, u.c_str(), sz, declared);
      free(file);
      return PB_ERR_SCENE_INVALID;
    }
    approved->insert(file);
    free(file);
  }
  return precheck_objects(path, j, declared_lengths);
}

// load.c decodes images itself, with size limits; tinygltf only keeps the
// reference (uri or bufferView).
bool keep_image_reference(tinygltf::Image *, const int, std::string *, std::string *, int, int,
                          const unsigned char *, int, void *) {
  return true;
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

// A tinygltf value as a pb_gltf_value whose arrays live in m. The JSON
// nesting is bounded (check_depth), so the recursion is too.
pb_gltf_value convert_value(Impl &m, const tinygltf::Value &v) {
  pb_gltf_value x{};
  switch (v.Type()) {
  case tinygltf::BOOL_TYPE:
    x.type = PB_GLTF_BOOL;
    x.boolean = v.Get<bool>();
    break;
  case tinygltf::INT_TYPE:
  case tinygltf::REAL_TYPE:
    x.type = PB_GLTF_NUMBER;
    x.is_integer = v.IsInt();
    x.number = v.GetNumberAsDouble();
    break;
  case tinygltf::STRING_TYPE:
    x.type = PB_GLTF_STRING;
    m.value_strings.push_back(v.Get<std::string>());
    x.string = m.value_strings.back().c_str();
    break;
  case tinygltf::ARRAY_TYPE: {
    x.type = PB_GLTF_ARRAY;
    m.value_items.emplace_back();
    std::vector<pb_gltf_value> &items = m.value_items.back();
    items.resize(v.ArrayLen());
    for (size_t i = 0; i < items.size(); ++i) items[i] = convert_value(m, v.Get((int)i));
    x.items = items.data();
    x.count = items.size();
    break;
  }
  case tinygltf::OBJECT_TYPE: {
    x.type = PB_GLTF_OBJECT;
    std::vector<std::string> keys = v.Keys();
    m.value_items.emplace_back();
    std::vector<pb_gltf_value> &items = m.value_items.back();
    m.value_keys.emplace_back();
    std::vector<const char *> &names = m.value_keys.back();
    items.resize(keys.size());
    names.resize(keys.size());
    for (size_t i = 0; i < keys.size(); ++i) {
      m.value_strings.push_back(keys[i]);
      names[i] = m.value_strings.back().c_str();
      items[i] = convert_value(m, v.Get(keys[i]));
    }
    x.items = items.data();
    x.keys = names.data();
    x.count = items.size();
    break;
  }
  default:
    x.type = PB_GLTF_NULL;
  }
  return x;
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
      x.tangent = at("TANGENT");
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
    if (le != n.extensions.end()) {
      // -2: present but not a light index (load.c reports it as missing).
      double li = num_or(le->second, "light", -2);
      x.light = li >= 0 && li <= INT32_MAX && li == (double)(int32_t)li ? (int32_t)li : -2;
    }
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
    if (auto *e = ext("PHOTONBRIDGE_blender")) {
      m.value_roots.push_back(convert_value(m, *e));
      x.blender = &m.value_roots.back();
    }
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
  m.anim_samplers.resize(g.animations.size());
  m.anim_channels.resize(g.animations.size());
  for (size_t i = 0; i < g.animations.size(); ++i) {
    const tinygltf::Animation &a = g.animations[i];
    for (auto &sm : a.samplers) m.anim_samplers[i].push_back(pb_gltf_anim_sampler{sm.input, sm.output, s(sm.interpolation)});
    for (auto &ch : a.channels)
      m.anim_channels[i].push_back(pb_gltf_anim_channel{ch.sampler, ch.target_node, s(ch.target_path)});
    pb_gltf_animation x{};
    x.name = s(a.name);
    x.samplers = m.anim_samplers[i].data();
    x.sampler_count = m.anim_samplers[i].size();
    x.channels = m.anim_channels[i].data();
    x.channel_count = m.anim_channels[i].size();
    m.animations.push_back(x);
  }
  doc->animations = m.animations.data();
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
  long long bin_len = -1;
  if (is_glb) {
    r = check_glb(path, data, n, &text, &bin_len);
    if (r != PB_OK) return r;
  } else {
    text.assign(reinterpret_cast<const char *>(data), n);
  }

  std::unique_ptr<Impl> impl;
  try {
    impl.reset(new Impl);
    r = precheck(path, text, is_glb, bin_len, desc, &impl->approved);
    if (r != PB_OK) return r;

    char *dir = pb_dirname(path);
    std::string base = dir ? dir : ".";
    free(dir);
    FsCtx ctx{&impl->approved, desc->max_file_bytes, base};
    tinygltf::FsCallbacks fs{fs_exists, fs_expand, fs_read, fs_write, &ctx};
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(fs);
    loader.SetImageLoader(keep_image_reference, nullptr);
    std::string err, warn;
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
  } catch (const std::logic_error &e) {
    // out_of_range, invalid_argument, length_error: a check here that reads
    // past what it tested, never the file's fault (JSON is parsed without
    // exceptions, so a json::exception is the same kind of bug).
    return pb_fail(PB_ERR_INTERNAL, "%s: internal error while checking the file: %s", path, one_line(e.what()).c_str());
  } catch (const Json::exception &e) {
    return pb_fail(PB_ERR_INTERNAL, "%s: internal error while checking the file: %s", path, one_line(e.what()).c_str());
  } catch (const std::exception &e) {
    return pb_fail(PB_ERR_SCENE_PARSE, "%s: %s", path, one_line(e.what()).c_str());
  }
  doc->impl = impl.release();
  return PB_OK;
}

extern "C" const pb_gltf_value *pb_gltf_value_get(const pb_gltf_value *v, const char *key) {
  if (!v || v->type != PB_GLTF_OBJECT) return nullptr;
  for (size_t i = 0; i < v->count; ++i)
    if (std::strcmp(v->keys[i], key) == 0) return &v->items[i];
  return nullptr;
}

extern "C" const char *pb_gltf_value_type_name(const pb_gltf_value *v) {
  static const char *const names[] = {"null", "a boolean", "a number", "a string", "an array", "an object"};
  return v && (unsigned)v->type < sizeof names / sizeof *names ? names[v->type] : "absent";
}

extern "C" void pb_gltf_doc_destroy(pb_gltf_doc *doc) {
  if (!doc) return;
  delete static_cast<Impl *>(doc->impl);
  std::memset(doc, 0, sizeof *doc);
}
