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

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
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
  std::vector<std::vector<int32_t>> prim_joints, prim_weights;  // per primitive, in prims' order
  std::vector<std::vector<pb_gltf_target>> prim_targets;
  std::vector<pb_gltf_skin> skins;
  std::vector<std::vector<int32_t>> skin_joints;
  std::vector<const char *> variant_names;
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
  // Extension values (pb_gltf_value trees): every container's items in a
  // vector of its own, kept here so the pointers stay valid.
  std::vector<std::unique_ptr<std::vector<pb_gltf_value>>> value_items;
  std::vector<std::unique_ptr<std::vector<const char *>>> value_keys;
  std::vector<std::unique_ptr<pb_gltf_value>> value_roots;
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

// An optional number member.
pb_result check_number(const char *path, const Json &o, const char *key, const std::string &where) {
  auto it = o.is_object() ? o.find(key) : o.end();
  if (it == o.end() || it->is_number()) return PB_OK;
  return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: %s is not a number", path, member_path(where, key).c_str(), it->dump().c_str());
}
// An optional array of numbers, of `n` of them when n > 0.
pb_result check_numbers(const char *path, const Json &o, const char *key, const std::string &where, size_t n = 0) {
  auto it = o.is_object() ? o.find(key) : o.end();
  if (it == o.end()) return PB_OK;
  std::string w = member_path(where, key);
  if (!it->is_array() || (n && it->size() != n))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: not an array of %s numbers", path, w.c_str(), n ? std::to_string(n).c_str() : "");
  for (size_t i = 0; i < it->size(); ++i)
    if (!(*it)[i].is_number())
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s[%zu]: %s is not a number", path, w.c_str(), i, (*it)[i].dump().c_str());
  return PB_OK;
}
// A material's textureInfo: index, texCoord, and KHR_texture_transform's
// members (offset and scale two numbers, rotation a number, texCoord an
// index), which tinygltf keeps as untyped values.
pb_result check_texture_info(const char *path, const Json &t, const std::string &w) {
  pb_result x = check_id(path, t, "index", w);
  if (x == PB_OK) x = check_id(path, t, "texCoord", w);
  auto ext = t.is_object() ? t.find("extensions") : t.end();
  if (x != PB_OK || ext == t.end() || !ext->is_object() || !ext->contains("KHR_texture_transform")) return x;
  const Json &tt = (*ext)["KHR_texture_transform"];
  std::string tw = w + ".extensions.KHR_texture_transform";
  if (!tt.is_object()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: not an object", path, tw.c_str());
  x = check_numbers(path, tt, "offset", tw, 2);
  if (x == PB_OK) x = check_numbers(path, tt, "scale", tw, 2);
  if (x == PB_OK) x = check_number(path, tt, "rotation", tw);
  if (x == PB_OK) x = check_id(path, tt, "texCoord", tw);
  return x;
}

// accessor.sparse: tinygltf reads its members as int (truncating) and
// refuses missing ones with messages that name no JSON path.
pb_result check_sparse(const char *path, const Json &o, const std::string &w) {
  auto it = o.is_object() ? o.find("sparse") : o.end();
  if (it == o.end()) return PB_OK;
  std::string sw = w + ".sparse";
  if (!it->is_object()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: not an object", path, sw.c_str());
  auto c = it->find("count");
  if (c == it->end() || !c->is_number_unsigned() || c->get<unsigned long long>() < 1 || c->get<unsigned long long>() > INT32_MAX)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.count: %s is not an integer from 1 to 2^31-1", path, sw.c_str(),
                   c == it->end() ? "missing, which" : c->dump().c_str());
  for (const char *k : {"indices", "values"}) {
    std::string kw = sw + "." + k;
    auto p = it->find(k);
    if (p == it->end() || !p->is_object())
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: missing or not an object", path, kw.c_str());
    if (p->find("bufferView") == p->end()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.bufferView: missing", path, kw.c_str());
    pb_result x = check_id(path, *p, "bufferView", kw);
    if (x == PB_OK) x = check_offset(path, *p, "byteOffset", kw);
    if (x != PB_OK) return x;
    auto off = p->find("byteOffset");
    if (off != p->end() && off->get<unsigned long long>() > INT32_MAX)
      return pb_fail(PB_ERR_LIMIT, "%s: %s.byteOffset: %s is over 2^31-1", path, kw.c_str(), off->dump().c_str());
    if (std::string(k) == "indices") {
      auto ct = p->find("componentType");
      if (ct == p->end() || !ct->is_number_integer())
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.componentType: missing or not an integer", path, kw.c_str());
    }
  }
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
    if (x == PB_OK) x = check_numbers(path, o, "weights", w);
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
      auto tg = p.is_object() ? p.find("targets") : p.end();
      if (x == PB_OK && tg != p.end()) {
        if (!tg->is_array()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.targets: not an array", path, pw.c_str());
        for (size_t t = 0; t < tg->size() && x == PB_OK; ++t) {
          std::string tw = pw + ".targets[" + std::to_string(t) + "]";
          const Json &o2 = (*tg)[t];
          if (!o2.is_object()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: not an object", path, tw.c_str());
          for (auto a = o2.begin(); a != o2.end() && x == PB_OK; ++a) x = check_id(path, o2, a.key().c_str(), tw);
        }
      }
    }
    if (x == PB_OK) x = check_numbers(path, o, "weights", w);
    return x;
  });
  each("skins", [&](const Json &o, const std::string &w) {
    pb_result x = check_id(path, o, "inverseBindMatrices", w);
    if (x == PB_OK) x = check_id(path, o, "skeleton", w);
    if (x == PB_OK && (!o.is_object() || !o.contains("joints")))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.joints: missing (a skin needs at least one joint)", path, w.c_str());
    return x == PB_OK ? check_id_array(path, o, "joints", w) : x;
  });
  each("accessors", [&](const Json &o, const std::string &w) {
    pb_result x = check_id(path, o, "bufferView", w);
    if (x == PB_OK) x = check_offset(path, o, "byteOffset", w);
    return x == PB_OK ? check_sparse(path, o, w) : x;
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
      if (x == PB_OK && pbr != o.end() && pbr->is_object() && pbr->contains(t))
        x = check_texture_info(path, (*pbr)[t], w + ".pbrMetallicRoughness." + t);
    for (const char *t : {"normalTexture", "occlusionTexture", "emissiveTexture"})
      if (x == PB_OK && o.is_object() && o.contains(t)) x = check_texture_info(path, o[t], w + "." + t);
    auto ext = o.is_object() ? o.find("extensions") : o.end();
    // tinygltf keeps only objects as extensions: a PHOTONBRIDGE_blender of
    // another type would vanish instead of being refused.
    if (x == PB_OK && ext != o.end() && ext->is_object()) {
      auto pb = ext->find("PHOTONBRIDGE_blender");
      if (pb != ext->end() && !pb->is_object())
        x = pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.extensions.PHOTONBRIDGE_blender: %s, expected an object", path,
                    w.c_str(), pb->is_string() ? "a string" : pb->is_array() ? "an array" : pb->is_number() ? "a number"
                                                                                                          : "not an object");
    }
    if (x == PB_OK && ext != o.end() && ext->is_object() && ext->contains("KHR_materials_volume")) {
      const Json &v = (*ext)["KHR_materials_volume"];
      std::string vw = w + ".extensions.KHR_materials_volume";
      for (const char *k : {"thicknessFactor", "attenuationDistance"})
        if (x == PB_OK) x = check_number(path, v, k, vw);
      if (x == PB_OK) x = check_numbers(path, v, "attenuationColor", vw, 3);
    }
    return x;
  });
  return r;
}

// An image's data URI (embedded glTF from three.js and other writers; Blender
// 3.4's "glTF Embedded" uses bufferViews instead) must be one tinygltf
// decodes as an image (its IsDataURI: exactly
// "data:image/png;base64," or "data:image/jpeg;base64,") with strict base64:
// tinygltf's decoder skips bad characters instead of failing. The decoded
// bytes are bounded by the file's own size limit (3 bytes per 4 characters);
// the image's pixel size is checked by load.c from its header, as for files.
pb_result check_image_data_uri(const char *path, size_t i, const std::string &u) {
  if (u.rfind("data:", 0) != 0) return PB_OK;
  size_t comma = u.find(',');
  std::string head = u.substr(0, comma == std::string::npos ? u.size() : comma);
  if (comma == std::string::npos || head.size() < 7 || head.compare(head.size() - 7, 7, ";base64") != 0)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: images[%zu].uri: data URI is not base64", path, i);
  std::string media = head.substr(5, head.size() - 12);
  if (media != "image/png" && media != "image/jpeg") {
    if (media.size() > 40) media = media.substr(0, 40) + "...";
    for (char &c : media)
      if ((unsigned char)c < 0x20 || (unsigned char)c > 0x7e) c = '?';
    return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: images[%zu].uri: data URI of media type '%s' (only image/png and image/jpeg are supported)",
                   path, i, media.c_str());
  }
  long long sz = b64_size(u.substr(comma + 1));
  if (sz < 0) return pb_fail(PB_ERR_SCENE_PARSE, "%s: images[%zu].uri: malformed base64 data", path, i);
  if (sz == 0) return pb_fail(PB_ERR_IMAGE, "%s: images[%zu].uri: data URI holds no image bytes", path, i);
  return PB_OK;
}

// What tinygltf refuses itself with messages that name no JSON path (or
// trusts, as the byte offset of an image's bufferView): checked here first so
// that the error reads "FILE: accessors[3].count: ...". `declared` holds each
// buffer's byteLength.
pb_result precheck_objects(const char *path, const Json &j, const std::vector<unsigned long long> &declared) {
  pb_result ir = precheck_ids(path, j);
  if (ir != PB_OK) return ir;
  bool bad = false;
  // tinygltf drops an extension that is not an object; ours must say so.
  const Json *cams = array_member(j, "cameras", &bad);
  for (size_t i = 0; cams && i < cams->size(); ++i) {
    const Json &c = (*cams)[i];
    auto ext = c.is_object() ? c.find("extensions") : c.end();
    if (ext == c.end() || !ext->is_object()) continue;
    auto pbx = ext->find("PHOTONBRIDGE_blender");
    if (pbx != ext->end() && !pbx->is_object())
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: cameras[%zu].extensions.PHOTONBRIDGE_blender: not an object", path, i);
  }
  bad = false;
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
    pb_result r = check_image_data_uri(path, i, uri->get<std::string>());
    if (r != PB_OK) return r;
  }
  return PB_OK;
}

// JSON has no NaN or Infinity, but Python's json module writes them (the
// Blender add-on's writer is Python): when a file does not parse, find the
// first such token (or a number literal beyond double range) outside strings
// and name its JSON path, so that the error says which value is broken
// ("nodes[2].extensions.PHOTONBRIDGE_blender.light.power: NaN"). Returns
// false when there is none.
struct JsonFrame {
  bool object;
  std::string key;
  size_t index;
};

std::string frame_path(const std::vector<JsonFrame> &st) {
  std::string p;
  for (const JsonFrame &f : st) {
    if (f.object) p += (p.empty() ? "" : ".") + f.key;
    else p += "[" + std::to_string(f.index) + "]";
  }
  return p.empty() ? "(top level)" : p;
}

bool find_nonfinite(const std::string &t, std::string *path, std::string *token) {
  std::vector<JsonFrame> st;
  bool want_key = false;
  for (size_t i = 0; i < t.size(); ++i) {
    char c = t[i];
    if (c == '"') {
      size_t j = i + 1;
      std::string s;
      while (j < t.size() && t[j] != '"') {
        if (t[j] == '\\' && j + 1 < t.size()) ++j;
        s += t[j++];
      }
      if (!st.empty() && st.back().object && want_key) st.back().key = s;
      i = j;
    } else if (c == '{') {
      st.push_back({true, "", 0});
      want_key = true;
    } else if (c == '[') {
      st.push_back({false, "", 0});
      want_key = false;
    } else if (c == '}' || c == ']') {
      if (!st.empty()) st.pop_back();
      want_key = false;
    } else if (c == ':') {
      want_key = false;
    } else if (c == ',') {
      if (!st.empty() && !st.back().object) st.back().index++;
      want_key = !st.empty() && st.back().object;
    } else if (c == 'N' || c == 'I' || (c == '-' && i + 1 < t.size() && t[i + 1] == 'I')) {
      size_t j = i + (c == '-');
      for (const char *lit : {"NaN", "Infinity"}) {
        size_t n = std::strlen(lit);
        if (t.compare(j, n, lit) != 0) continue;
        *token = t.substr(i, j - i + n);
        *path = frame_path(st);
        return true;
      }
    } else if (c == '-' || (c >= '0' && c <= '9')) {
      // A literal beyond double range (1e999) is no JSON number either for
      // the parser: name it too.
      size_t j = i + 1;
      while (j < t.size() && (std::isdigit((unsigned char)t[j]) || t[j] == '.' || t[j] == 'e' || t[j] == 'E' ||
                              t[j] == '+' || t[j] == '-'))
        ++j;
      std::string num = t.substr(i, j - i);
      if (std::isinf(std::strtod(num.c_str(), nullptr))) {
        *token = num;
        *path = frame_path(st);
        return true;
      }
      i = j - 1;
    }
  }
  return false;
}

// Checks what tinygltf would take on trust: required extensions and buffers.
pb_result precheck(const char *path, const std::string &text, bool is_glb, long long bin_len,
                   const pb_gltf_read_desc *desc, std::set<std::string> *approved) {
  pb_result dr = check_depth(path, text);
  if (dr != PB_OK) return dr;
  Json j = Json::parse(text, nullptr, false);
  if (j.is_discarded()) {
    std::string where, token;
    if (find_nonfinite(text, &where, &token)) {
      bool literal = token[0] == 'N' || token.find("Infinity") != std::string::npos;
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: %s is not a finite number (%s)", path, where.c_str(),
                     token.size() > 40 ? (token.substr(0, 40) + "...").c_str() : token.c_str(),
                     literal ? "JSON has no NaN or Infinity" : "beyond the range of a double");
    }
    return pb_fail(PB_ERR_SCENE_PARSE, "%s: not valid JSON", path);
  }
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
      "KHR_materials_unlit",  "KHR_materials_variants", "KHR_mesh_quantization",
      "PHOTONBRIDGE_blender"};
  auto req = j.find("extensionsRequired");
  if (req != j.end()) {
    if (!req->is_array()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: extensionsRequired: not an array", path);
    for (size_t i = 0; i < req->size(); ++i) {
      const Json &e = (*req)[i];
      if (!e.is_string()) return pb_fail(PB_ERR_SCENE_INVALID, "%s: extensionsRequired[%zu]: not a string", path, i);
      std::string name = e.get<std::string>();
      bool ok = false;
      for (const char *s : supported) ok |= name == s;
      // Quantized attributes are read-critical and load.c refuses integer
      // positions, normals and tangents: a file that requires them cannot
      // be drawn correctly.
      if (name == "KHR_mesh_quantization") ok = false;
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
    pb_result r = pb_gltf_resolve_uri(path, desc->dir, u.c_str(), desc->allow_external_files, where, &file);
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

// tinygltf's extension value -> pb_gltf_value (depth is bounded by
// check_depth: at most MAX_JSON_DEPTH levels).
void fill_value(Impl &m, const tinygltf::Value &v, pb_gltf_value *out) {
  *out = pb_gltf_value{};
  if (v.IsBool()) {
    out->type = PB_GLTF_BOOL;
    out->boolean = v.Get<bool>() ? 1 : 0;
  } else if (v.IsNumber()) {
    out->type = PB_GLTF_NUMBER;
    out->is_integer = v.IsInt() ? 1 : 0;
    out->number = v.GetNumberAsDouble();
  } else if (v.IsString()) {
    out->type = PB_GLTF_STRING;
    out->string = v.Get<std::string>().c_str();
  } else if (v.IsArray()) {
    out->type = PB_GLTF_ARRAY;
    const tinygltf::Value::Array &a = v.Get<tinygltf::Value::Array>();
    m.value_items.emplace_back(new std::vector<pb_gltf_value>(a.size()));
    std::vector<pb_gltf_value> &items = *m.value_items.back();
    for (size_t i = 0; i < a.size(); ++i) fill_value(m, a[i], &items[i]);
    out->count = a.size();
    out->items = items.data();
  } else if (v.IsObject()) {
    out->type = PB_GLTF_OBJECT;
    const tinygltf::Value::Object &o = v.Get<tinygltf::Value::Object>();
    m.value_items.emplace_back(new std::vector<pb_gltf_value>(o.size()));
    m.value_keys.emplace_back(new std::vector<const char *>());
    std::vector<pb_gltf_value> &items = *m.value_items.back();
    std::vector<const char *> &keys = *m.value_keys.back();
    size_t i = 0;
    for (auto &kv : o) {
      keys.push_back(kv.first.c_str());
      fill_value(m, kv.second, &items[i++]);
    }
    out->count = o.size();
    out->items = items.data();
    out->keys = keys.data();
  }
}

const pb_gltf_value *extension_value(Impl &m, const tinygltf::ExtensionMap &ext, const char *name) {
  auto it = ext.find(name);
  if (it == ext.end()) return nullptr;
  m.value_roots.emplace_back(new pb_gltf_value);
  fill_value(m, it->second, m.value_roots.back().get());
  return m.value_roots.back().get();
}

// load.c decodes images itself, with size limits; tinygltf only keeps the
// reference (uri or bufferView), and for a data URI the bytes it decoded
// (check_image_data_uri approved the URI first).
bool keep_image_reference(tinygltf::Image *image, const int, std::string *, std::string *, int, int,
                          const unsigned char *bytes, int size, void *) {
  if (image->bufferView < 0 && image->uri.empty() && bytes && size > 0) image->image.assign(bytes, bytes + size);
  return true;
}

const char *s(const std::string &x) { return x.c_str(); }

double num_or(const tinygltf::Value &v, const char *key, double dflt) {
  if (!v.IsObject() || !v.Has(key)) return dflt;
  const tinygltf::Value &x = v.Get(key);
  return x.IsNumber() ? x.GetNumberAsDouble() : dflt;
}

// cameras[i].extensions.PHOTONBRIDGE_blender, member by member (gltf_doc.h).
void camera_blender(const tinygltf::Value &v, pb_gltf_camera_blender *x) {
  x->present = 1;
  x->type = x->sensor_fit = x->panorama_type = nullptr;
  if (!v.IsObject()) {
    x->bad_member = "";
    x->bad_expect = "an object";
    return;
  }
  auto str = [&](const char *key, const char **out) {
    if (!v.Has(key)) return;
    const tinygltf::Value &m = v.Get(key);
    if (m.IsString()) *out = m.Get<std::string>().c_str();
    else if (!x->bad_member) x->bad_member = key, x->bad_expect = "a string";
  };
  auto num = [&](const char *key, double *out) {
    *out = NAN;
    if (!v.Has(key)) return;
    const tinygltf::Value &m = v.Get(key);
    if (m.IsNumber()) *out = m.GetNumberAsDouble();
    else if (!x->bad_member) x->bad_member = key, x->bad_expect = "a number";
  };
  str("type", &x->type);
  str("sensorFit", &x->sensor_fit);
  num("lens", &x->lens);
  num("sensorWidth", &x->sensor_width);
  num("sensorHeight", &x->sensor_height);
  num("orthoScale", &x->ortho_scale);
  num("shiftX", &x->shift_x);
  num("shiftY", &x->shift_y);
  num("clipStart", &x->clip_start);
  num("clipEnd", &x->clip_end);
  num("aspect", &x->aspect);
  str("panoramaType", &x->panorama_type);
  num("focusDistance", &x->focus_distance);
  num("apertureFstop", &x->aperture_fstop);
  num("apertureBlades", &x->aperture_blades);
  num("apertureRotation", &x->aperture_rotation);
  num("apertureRatio", &x->aperture_ratio);
  num("fisheyeFov", &x->fisheye_fov);
  num("fisheyeLens", &x->fisheye_lens);
  num("latitudeMin", &x->latitude_min);
  num("latitudeMax", &x->latitude_max);
  num("longitudeMin", &x->longitude_min);
  num("longitudeMax", &x->longitude_max);
}

// Element k of an array member of numbers, or dflt.
double num_at(const tinygltf::Value &v, const char *key, int k, double dflt) {
  if (!v.IsObject() || !v.Has(key)) return dflt;
  const tinygltf::Value &a = v.Get(key);
  if (!a.IsArray() || (int)a.ArrayLen() <= k || !a.Get(k).IsNumber()) return dflt;
  return a.Get(k).GetNumberAsDouble();
}

// KHR_texture_transform of a textureInfo (its members' types are checked by
// precheck_materials).
pb_gltf_texture_transform tex_transform(const tinygltf::ExtensionMap &ext) {
  pb_gltf_texture_transform t{};
  t.scale[0] = t.scale[1] = 1;
  t.texcoord = -1;
  auto it = ext.find("KHR_texture_transform");
  if (it == ext.end()) return t;
  const tinygltf::Value &v = it->second;
  t.present = 1;
  for (int k = 0; k < 2; ++k) {
    t.offset[k] = num_at(v, "offset", k, 0);
    t.scale[k] = num_at(v, "scale", k, 1);
  }
  t.rotation = num_or(v, "rotation", 0);
  double tc = num_or(v, "texCoord", -1);
  t.texcoord = tc >= 0 && tc <= INT32_MAX ? (int32_t)tc : -1;
  return t;
}

void fill_tex(pb_gltf_texture_ref *t, int index, int texcoord, double scale, const tinygltf::ExtensionMap &ext) {
  t->index = index;
  t->texcoord = texcoord;
  t->scale = scale;
  t->transform = tex_transform(ext);
}

// The buffers, bufferViews and accessors as parsed.
void convert_data(Impl &m) {
  tinygltf::Model &g = m.model;
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
    x.sparse_info.indices_view = x.sparse_info.values_view = -1;
    if (x.sparse) {
      // precheck_ids has checked that these were integers in int range.
      x.sparse_info.count = (uint64_t)a.sparse.count;
      x.sparse_info.indices_view = a.sparse.indices.bufferView;
      x.sparse_info.indices_offset = (uint64_t)a.sparse.indices.byteOffset;
      x.sparse_info.indices_ct = a.sparse.indices.componentType;
      x.sparse_info.values_view = a.sparse.values.bufferView;
      x.sparse_info.values_offset = (uint64_t)a.sparse.values.byteOffset;
    }
    if (a.minValues.size() >= 3 && a.maxValues.size() >= 3) {
      x.has_min_max = 1;
      for (int k = 0; k < 3; ++k) {
        x.min[k] = a.minValues[(size_t)k];
        x.max[k] = a.maxValues[(size_t)k];
      }
    }
    m.accessors.push_back(x);
  }
}

// Meshes and their primitives (attributes, JOINTS_n / WEIGHTS_n sets, morph targets).
void convert_meshes(Impl &m) {
  tinygltf::Model &g = m.model;
  m.prims.resize(g.meshes.size());
  size_t nprims = 0;
  for (auto &mesh : g.meshes) nprims += mesh.primitives.size();
  m.prim_joints.resize(nprims);
  m.prim_weights.resize(nprims);
  m.prim_targets.resize(nprims);
  size_t pk = 0;  // primitive number over all meshes
  for (size_t i = 0; i < g.meshes.size(); ++i) {
    for (auto &p : g.meshes[i].primitives) {
      pb_gltf_primitive x{};
      x.mode = p.mode;
      auto find = [](const std::map<std::string, int> &a, const std::string &k) {
        auto it = a.find(k);
        return it == a.end() ? -1 : it->second;
      };
      auto at = [&](const char *k) { return find(p.attributes, k); };
      x.position = at("POSITION");
      x.normal = at("NORMAL");
      x.texcoord0 = at("TEXCOORD_0");
      x.texcoord1 = at("TEXCOORD_1");
      x.color0 = at("COLOR_0");
      x.tangent = at("TANGENT");
      x.indices = p.indices;
      x.material = p.material;
      // JOINTS_n / WEIGHTS_n: up to one past the highest n present.
      for (auto &a : p.attributes) {
        for (int w = 0; w < 2; ++w) {
          const char *pre = w ? "WEIGHTS_" : "JOINTS_";
          size_t pl = strlen(pre);
          if (a.first.compare(0, pl, pre) != 0 || a.first.size() == pl || a.first.size() > pl + 4 ||
              a.first.find_first_not_of("0123456789", pl) != std::string::npos)
            continue;
          size_t n = (size_t)std::stoul(a.first.substr(pl));
          std::vector<int32_t> &v = w ? m.prim_weights[pk] : m.prim_joints[pk];
          if (v.size() <= n) v.resize(n + 1, -1);
          v[n] = a.second;
        }
      }
      for (auto &t : p.targets)
        m.prim_targets[pk].push_back(pb_gltf_target{find(t, "POSITION"), find(t, "NORMAL"), find(t, "TANGENT")});
      x.joints = m.prim_joints[pk].data();
      x.joint_set_count = m.prim_joints[pk].size();
      x.weights = m.prim_weights[pk].data();
      x.weight_set_count = m.prim_weights[pk].size();
      x.targets = m.prim_targets[pk].data();
      x.target_count = m.prim_targets[pk].size();
      auto ve = p.extensions.find("KHR_materials_variants");
      if (ve != p.extensions.end() && ve->second.Has("mappings") && ve->second.Get("mappings").IsArray())
        x.variant_mapping_count = ve->second.Get("mappings").ArrayLen();
      m.prims[i].push_back(x);
      pk++;
    }
  }
  for (size_t i = 0; i < g.meshes.size(); ++i) {
    pb_gltf_mesh x{};
    x.name = s(g.meshes[i].name);
    x.primitives = m.prims[i].data();
    x.primitive_count = m.prims[i].size();
    x.weights = g.meshes[i].weights.data();
    x.weight_count = g.meshes[i].weights.size();
    m.meshes.push_back(x);
  }
}

// Skins, the file's material variants, nodes and scenes.
void convert_nodes(Impl &m) {
  tinygltf::Model &g = m.model;
  m.skin_joints.resize(g.skins.size());
  for (size_t i = 0; i < g.skins.size(); ++i) {
    const tinygltf::Skin &sk = g.skins[i];
    for (int jn : sk.joints) m.skin_joints[i].push_back(jn);
    pb_gltf_skin x{};
    x.name = s(sk.name);
    x.inverse_bind_matrices = sk.inverseBindMatrices;
    x.skeleton = sk.skeleton;
    x.joints = m.skin_joints[i].data();
    x.joint_count = m.skin_joints[i].size();
    m.skins.push_back(x);
  }
  auto rv = g.extensions.find("KHR_materials_variants");
  if (rv != g.extensions.end() && rv->second.Has("variants") && rv->second.Get("variants").IsArray()) {
    const tinygltf::Value &vs = rv->second.Get("variants");
    for (size_t k = 0; k < vs.ArrayLen(); ++k) {
      const tinygltf::Value &v = vs.Get((int)k);
      m.variant_names.push_back(v.Has("name") && v.Get("name").IsString() ? v.Get("name").Get<std::string>().c_str() : "");
    }
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
      // -2: present but not a light index (load_light.c reports it as missing).
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
    x.weights = n.weights.data();
    x.weight_count = n.weights.size();
    x.blender = extension_value(m, n.extensions, "PHOTONBRIDGE_blender");
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
}

// Cameras (with their PHOTONBRIDGE_blender extension) and KHR_lights_punctual lights.
void convert_cameras_lights(Impl &m) {
  tinygltf::Model &g = m.model;
  for (auto &c : g.cameras) {
    pb_gltf_camera x{};
    x.name = s(c.name);
    x.type = s(c.type);
    x.perspective = c.type == "perspective";
    x.orthographic = c.type == "orthographic";
    x.yfov = c.perspective.yfov;
    x.aspect_ratio = c.perspective.aspectRatio;
    x.xmag = c.orthographic.xmag;
    x.ymag = c.orthographic.ymag;
    x.znear = x.orthographic ? c.orthographic.znear : c.perspective.znear;
    x.zfar = x.orthographic ? c.orthographic.zfar : c.perspective.zfar;
    auto e = c.extensions.find("PHOTONBRIDGE_blender");
    if (e != c.extensions.end()) camera_blender(e->second, &x.blender);
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
}

// Materials with the KHR extensions read here (gltf_doc.h pb_gltf_material).
void convert_materials(Impl &m) {
  tinygltf::Model &g = m.model;
  for (auto &mt : g.materials) {
    pb_gltf_material x{};
    auto &pbr = mt.pbrMetallicRoughness;
    x.name = s(mt.name);
    for (size_t k = 0; k < 4; ++k) x.base_color[k] = pbr.baseColorFactor.size() == 4 ? pbr.baseColorFactor[k] : 1.0;
    fill_tex(&x.base_color_tex, pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, 1,
             pbr.baseColorTexture.extensions);
    x.metallic = pbr.metallicFactor;
    x.roughness = pbr.roughnessFactor;
    fill_tex(&x.metallic_roughness_tex, pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord, 1,
             pbr.metallicRoughnessTexture.extensions);
    fill_tex(&x.normal_tex, mt.normalTexture.index, mt.normalTexture.texCoord, mt.normalTexture.scale,
             mt.normalTexture.extensions);
    fill_tex(&x.emissive_tex, mt.emissiveTexture.index, mt.emissiveTexture.texCoord, 1, mt.emissiveTexture.extensions);
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
    x.unlit = ext("KHR_materials_unlit") != nullptr;
    x.attenuation_color[0] = x.attenuation_color[1] = x.attenuation_color[2] = 1;
    if (auto *e = ext("KHR_materials_volume")) {
      x.has_volume = 1;
      x.thickness = num_or(*e, "thicknessFactor", 0);
      x.attenuation_distance = num_or(*e, "attenuationDistance", 0);
      for (int k = 0; k < 3; ++k) x.attenuation_color[k] = num_at(*e, "attenuationColor", k, 1);
    }
    x.iridescence_ior = 1.3;
    x.iridescence_thickness_min = 100;
    x.iridescence_thickness_max = 400;
    x.has_clearcoat = ext("KHR_materials_clearcoat") != nullptr;
    x.has_sheen = ext("KHR_materials_sheen") != nullptr;
    if (auto *e = ext("KHR_materials_iridescence")) {
      // A member that is there but not a number reads as NaN, which the
      // loader refuses (load_material.c), rather than as its default.
      auto num = [&](const char *k, double dflt) {
        if (!e->IsObject() || !e->Has(k)) return dflt;
        const tinygltf::Value &v = e->Get(k);
        return v.IsNumber() ? v.GetNumberAsDouble() : std::nan("");
      };
      x.has_iridescence = 1;
      x.iridescence = num("iridescenceFactor", 0);
      x.iridescence_ior = num("iridescenceIor", 1.3);
      x.iridescence_thickness_min = num("iridescenceThicknessMinimum", 100);
      x.iridescence_thickness_max = num("iridescenceThicknessMaximum", 400);
      x.iridescence_textures = e->IsObject() && (e->Has("iridescenceTexture") || e->Has("iridescenceThicknessTexture"));
    }
    x.alpha_mode = s(mt.alphaMode);
    x.alpha_cutoff = mt.alphaCutoff;
    x.double_sided = mt.doubleSided;
    x.blender = extension_value(m, mt.extensions, "PHOTONBRIDGE_blender");
    m.materials.push_back(x);
  }
}

// Textures, images (kept undecoded) and samplers.
void convert_textures(Impl &m) {
  tinygltf::Model &g = m.model;
  for (auto &t : g.textures) {
    int32_t fs = -1;
    auto e = t.extensions.find("PHOTONBRIDGE_blender");
    if (e != t.extensions.end() && e->second.IsObject() && e->second.Has("source")) {
      const tinygltf::Value &v = e->second.Get("source");
      fs = v.IsInt() ? v.GetNumberAsInt() : -2;
      if (fs < 0) fs = -2;
    }
    m.textures.push_back(pb_gltf_texture{t.source, t.sampler, fs});
  }
  for (auto &im : g.images) {
    pb_gltf_image x{};
    x.name = s(im.name);
    x.uri = s(im.uri);
    x.mime_type = s(im.mimeType);
    x.buffer_view = im.bufferView;
    if (!im.image.empty()) {
      x.data = im.image.data();
      x.data_size = im.image.size();
    }
    m.images.push_back(x);
  }
  for (auto &sm : g.samplers) m.samplers.push_back(pb_gltf_sampler{sm.magFilter, sm.minFilter, sm.wrapS, sm.wrapT});
}

// The parsed model as the plain-C document (gltf_doc.h), one concept at a
// time; every pointer points into m, which the document keeps.
void convert(Impl &m, pb_gltf_doc *doc) {
  tinygltf::Model &g = m.model;
  doc->generator = s(g.asset.generator);
  for (auto &e : g.extensionsUsed) m.ext_used.push_back(s(e));
  for (auto &e : g.extensionsRequired) m.ext_required.push_back(s(e));
  doc->default_scene = g.defaultScene;
  doc->blender = extension_value(m, g.extensions, "PHOTONBRIDGE_blender");
  convert_data(m);
  convert_meshes(m);
  convert_nodes(m);
  convert_cameras_lights(m);
  convert_materials(m);
  convert_textures(m);

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
  doc->variant_names = m.variant_names.data();
  doc->variant_count = m.variant_names.size();

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
  PB_SET(skins, skin_count, skins);
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
  char *dir = pb_dirname(path);
  if (!dir) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
  pb_gltf_read_desc at = *desc;
  at.dir = dir;
  r = pb_gltf_doc_parse(path, data, n, &at, doc);
  free(dir);
  return r;
}

extern "C" pb_result pb_gltf_doc_parse(const char *path, const uint8_t *data, size_t n,
                                       const pb_gltf_read_desc *desc, pb_gltf_doc *doc) {
  std::memset(doc, 0, sizeof *doc);
  pb_result r = PB_OK;
  // A .blend (its "BLENDER" header; Blender 3+ may compress it with zstd,
  // older ones with gzip): the artist's first try, which deserves better
  // than "not valid JSON".
  size_t pl = std::strlen(path);
  bool blend_name = pl >= 6 && std::strcmp(path + pl - 6, ".blend") == 0;
  bool compressed = (n >= 4 && std::memcmp(data, "\x28\xb5\x2f\xfd", 4) == 0) ||
                    (n >= 2 && data[0] == 0x1f && data[1] == 0x8b);
  if ((n >= 7 && std::memcmp(data, "BLENDER", 7) == 0) || (blend_name && compressed))
    return pb_fail(PB_ERR_SCENE_PARSE, "%s is a Blender file: render it from Blender with the photonbridge "
                   "add-on, or export glTF (File > Export > glTF 2.0)", path);

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

    // No folder (a memory load without one): tinygltf is given none, and
    // fs_read refuses every file (the precheck approved none).
    std::string base = desc->dir ? desc->dir : "";
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
