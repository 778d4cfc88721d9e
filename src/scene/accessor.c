/* glTF accessors (accessor.h): bounds, alignment and shape checks before any
 * element is read, and element reads with sparse substitution. */
#include "scene/accessor.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

uint32_t pb_component_size(int32_t ct) {
  switch (ct) {
  case PB_CT_BYTE: case PB_CT_UBYTE: return 1;
  case PB_CT_SHORT: case PB_CT_USHORT: return 2;
  case PB_CT_UINT: case PB_CT_FLOAT: return 4;
  default: return 0;
  }
}

/* bufferViews[view] and its buffer exist and the view lies inside the
 * buffer; *bytes = the view's first byte. */
static pb_result check_view(const char *path, const pb_gltf_doc *d, int32_t view, const char *user, const uint8_t **bytes) {
  if (view < 0 || (size_t)view >= d->buffer_view_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: %d does not exist (%zu bufferViews)", path, user, view,
                   d->buffer_view_count);
  const pb_gltf_buffer_view *v = &d->buffer_views[view];
  if (v->buffer < 0 || (size_t)v->buffer >= d->buffer_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: bufferViews[%d].buffer: %d does not exist (%zu buffers)", path, view,
                   v->buffer, d->buffer_count);
  const pb_gltf_buffer *b = &d->buffers[v->buffer];
  if (v->byte_offset > b->size || v->byte_length > b->size - v->byte_offset)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: bufferViews[%d]: offset %llu + length %llu exceeds buffers[%d] (%llu bytes)",
                   path, view, (unsigned long long)v->byte_offset, (unsigned long long)v->byte_length, v->buffer,
                   (unsigned long long)b->size);
  *bytes = b->data + v->byte_offset;
  return PB_OK;
}

/* n packed elements of `elem` bytes at `offset` into bufferViews[view]
 * (sparse indices or values: no byteStride allowed, glTF 2.0 5.1.2/5.1.3),
 * aligned to their `csize`-byte components. */
static pb_result check_packed(const char *path, const pb_gltf_doc *d, int32_t idx, const char *which, int32_t view,
                              uint64_t offset, uint64_t n, uint32_t elem, uint32_t csize, const uint8_t **out) {
  char user[96];
  snprintf(user, sizeof user, "accessors[%d].sparse.%s.bufferView", idx, which);
  const uint8_t *bytes = NULL;
  pb_result r = check_view(path, d, view, user, &bytes);
  if (r != PB_OK) return r;
  const pb_gltf_buffer_view *v = &d->buffer_views[view];
  if (v->byte_stride)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d].sparse.%s: bufferViews[%d] has a byteStride (%u), which sparse data must not have",
                   path, idx, which, view, v->byte_stride);
  if (offset % csize || (v->byte_offset + offset) % csize)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d].sparse.%s.byteOffset: %llu is not aligned to its %u-byte components",
                   path, idx, which, (unsigned long long)offset, csize);
  /* n <= accessor count < 2^32 and elem <= 64: no overflow. */
  if (offset > v->byte_length || n * elem > v->byte_length - offset)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d].sparse.%s: %llu elements of %u bytes at offset %llu exceed bufferViews[%d] (%llu bytes)",
                   path, idx, which, (unsigned long long)n, elem, (unsigned long long)offset, view,
                   (unsigned long long)v->byte_length);
  *out = bytes + offset;
  return PB_OK;
}

static uint32_t packed_index(const uint8_t *p, int32_t ct, uint64_t k) {
  switch (ct) {
  case PB_CT_UBYTE: return p[k];
  case PB_CT_USHORT: { uint16_t x; memcpy(&x, p + 2 * k, 2); return x; }
  default: { uint32_t x; memcpy(&x, p + 4 * k, 4); return x; }
  }
}

/* accessor.sparse (glTF 2.0 3.6.2.3): count in [1, accessor count],
 * indices of an unsigned integer type, strictly increasing and below the
 * accessor's count, values of the accessor's own element type. */
static pb_result check_sparse(const char *path, const pb_gltf_doc *d, int32_t idx, pb_span *out) {
  const pb_gltf_accessor *a = &d->accessors[idx];
  const pb_gltf_sparse *sp = &a->sparse_info;
  if (sp->count < 1 || sp->count > a->count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d].sparse.count: %llu is not in [1, %llu] (the accessor's count)", path,
                   idx, (unsigned long long)sp->count, (unsigned long long)a->count);
  int32_t ict = sp->indices_ct;
  if (ict != PB_CT_UBYTE && ict != PB_CT_USHORT && ict != PB_CT_UINT)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d].sparse.indices.componentType: %d is not 5121, 5123 or 5125", path,
                   idx, ict);
  uint32_t isz = pb_component_size(ict);
  pb_result r = check_packed(path, d, idx, "indices", sp->indices_view, sp->indices_offset, sp->count, isz, isz,
                             &out->sparse_idx);
  if (r == PB_OK)
    r = check_packed(path, d, idx, "values", sp->values_view, sp->values_offset, sp->count, out->elem,
                     pb_component_size(a->component_type), &out->sparse_val);
  if (r != PB_OK) return r;
  uint64_t prev = 0;
  for (uint64_t k = 0; k < sp->count; ++k) {
    uint64_t i = packed_index(out->sparse_idx, ict, k);
    if (i >= a->count)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d].sparse.indices: index %llu at element %llu is out of range (count %llu)",
                     path, idx, (unsigned long long)i, (unsigned long long)k, (unsigned long long)a->count);
    if (k > 0 && i <= prev)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d].sparse.indices: element %llu (%llu) does not increase on %llu",
                     path, idx, (unsigned long long)k, (unsigned long long)i, (unsigned long long)prev);
    prev = i;
  }
  out->sparse_count = sp->count;
  out->sparse_ict = ict;
  return PB_OK;
}

pb_result pb_accessor_check(const char *path, const pb_gltf_doc *d, int32_t idx, const char *where, int components,
                            const int32_t *types, pb_span *out) {
  memset(out, 0, sizeof *out);
  if (idx < 0 || (size_t)idx >= d->accessor_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: accessor %d does not exist (%zu accessors)", path, where, idx,
                   d->accessor_count);
  const pb_gltf_accessor *a = &d->accessors[idx];
  if (a->components != components)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: has %d components, %s needs %d", path, idx, a->components,
                   where, components);
  int ok = 0;
  for (const int32_t *t = types; *t; ++t) ok |= *t == a->component_type;
  if (!ok)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: componentType %d is not allowed for %s", path, idx,
                   a->component_type, where);
  uint32_t csize = pb_component_size(a->component_type);
  uint32_t elem = csize * (uint32_t)components;
  out->count = a->count;
  out->elem = elem;
  out->stride = elem;
  out->ct = a->component_type;
  out->normalized = a->normalized;
  if (a->count == 0) return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: count is 0", path, idx);
  pb_result r;
  if (a->buffer_view == -1) {
    /* All zeros, per the spec: no bytes in the file back the count. */
    if (a->count > UINT32_MAX)
      return pb_fail(PB_ERR_LIMIT, "%s: accessors[%d]: count %llu is over the limit", path, idx, (unsigned long long)a->count);
    return a->sparse ? check_sparse(path, d, idx, out) : PB_OK;
  }
  char user[64];
  snprintf(user, sizeof user, "accessors[%d].bufferView", idx);
  const uint8_t *bytes = NULL;
  if ((r = check_view(path, d, a->buffer_view, user, &bytes)) != PB_OK) return r;
  const pb_gltf_buffer_view *v = &d->buffer_views[a->buffer_view];
  uint32_t stride = v->byte_stride ? v->byte_stride : elem;
  if (v->byte_stride && (v->byte_stride < elem || v->byte_stride > 252 || v->byte_stride % 4))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: bufferViews[%d].byteStride: %u is invalid for accessors[%d] (element %u bytes)",
                   path, a->buffer_view, v->byte_stride, idx, elem);
  if (a->byte_offset % csize || (v->byte_offset + a->byte_offset) % csize)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d].byteOffset: %llu is not aligned to its %u-byte components", path,
                   idx, (unsigned long long)a->byte_offset, csize);
  /* Needed bytes: offset + stride * (count - 1) + elem, computed without
   * overflow (count < 2^32 is checked first). */
  if (a->count > UINT32_MAX || a->byte_offset > v->byte_length)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: count %llu x stride %u exceeds bufferViews[%d] (%llu bytes)",
                   path, idx, (unsigned long long)a->count, stride, a->buffer_view, (unsigned long long)v->byte_length);
  uint64_t need = a->byte_offset + (uint64_t)stride * (a->count - 1) + elem;
  if (need > v->byte_length)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: count %llu x stride %u exceeds bufferViews[%d] (%llu bytes)",
                   path, idx, (unsigned long long)a->count, stride, a->buffer_view, (unsigned long long)v->byte_length);
  out->base = bytes + a->byte_offset;
  out->stride = stride;
  return a->sparse ? check_sparse(path, d, idx, out) : PB_OK;
}

/* Where element i's bytes are: its sparse value when listed (binary search
 * of the strictly increasing indices), else the base; NULL: zero. */
static const uint8_t *element(const pb_span *sp, uint64_t i) {
  if (sp->sparse_count) {
    uint64_t lo = 0, hi = sp->sparse_count;
    while (lo < hi) {
      uint64_t mid = lo + (hi - lo) / 2;
      uint32_t k = packed_index(sp->sparse_idx, sp->sparse_ict, mid);
      if (k == i) return sp->sparse_val + mid * sp->elem;
      if (k < i) lo = mid + 1;
      else hi = mid;
    }
  }
  return sp->base ? sp->base + i * sp->stride : NULL;
}

float pb_span_f(const pb_span *sp, uint64_t i, int c) {
  const uint8_t *p = element(sp, i);
  if (!p) return 0.0f;
  p += (uint64_t)c * pb_component_size(sp->ct);
  switch (sp->ct) {
  case PB_CT_FLOAT: { float f; memcpy(&f, p, 4); return f; }
  case PB_CT_UBYTE: return sp->normalized ? (float)p[0] / 255.0f : (float)p[0];
  case PB_CT_BYTE: { int8_t x = (int8_t)p[0]; return sp->normalized ? fmaxf((float)x / 127.0f, -1.0f) : (float)x; }
  case PB_CT_USHORT: { uint16_t x; memcpy(&x, p, 2); return sp->normalized ? (float)x / 65535.0f : (float)x; }
  case PB_CT_SHORT: { int16_t x; memcpy(&x, p, 2); return sp->normalized ? fmaxf((float)x / 32767.0f, -1.0f) : (float)x; }
  case PB_CT_UINT: { uint32_t x; memcpy(&x, p, 4); return (float)x; }
  default: return 0.0f;
  }
}

uint32_t pb_span_u(const pb_span *sp, uint64_t i, int c) {
  const uint8_t *p = element(sp, i);
  if (!p) return 0;
  p += (uint64_t)c * pb_component_size(sp->ct);
  switch (sp->ct) {
  case PB_CT_UBYTE: return p[0];
  case PB_CT_USHORT: { uint16_t x; memcpy(&x, p, 2); return x; }
  default: { uint32_t x; memcpy(&x, p, 4); return x; }
  }
}
