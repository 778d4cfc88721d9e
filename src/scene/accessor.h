/* glTF accessors, checked before they are read (internal to src/scene).
 *
 * pb_accessor_check validates an accessor against the shape its user needs
 * (components, allowed component types) and against its bufferView and
 * buffer, so that reading any element i < count is in bounds; sparse
 * accessors (glTF 2.0 3.6.2.3) are validated the same way (indices strictly
 * increasing and in range, both bufferViews large enough) and read through
 * the same calls, without expanding them: an element listed in the sparse
 * indices reads its sparse value, every other element the base bufferView
 * (or zero when the accessor has none). Errors are one line
 * "FILE: accessors[i]...: why" (pb_fail). */
#ifndef PB_SCENE_ACCESSOR_H
#define PB_SCENE_ACCESSOR_H

#include <stdint.h>

#include "core/result.h"
#include "scene/gltf_doc.h"

enum {
  PB_CT_BYTE = 5120,
  PB_CT_UBYTE = 5121,
  PB_CT_SHORT = 5122,
  PB_CT_USHORT = 5123,
  PB_CT_UINT = 5125,
  PB_CT_FLOAT = 5126,
};

/* Bytes of one component of type ct; 0 for an unknown type. */
uint32_t pb_component_size(int32_t ct);

/* A checked view of an accessor's elements. */
typedef struct pb_span {
  const uint8_t *base; /* NULL: no bufferView, the base elements are zero */
  uint64_t count;
  uint32_t stride, elem;
  int32_t ct;
  int normalized;
  /* Sparse substitution: sparse_count strictly increasing element indices
   * (component type sparse_ict, packed) and as many packed values. */
  uint64_t sparse_count;
  const uint8_t *sparse_idx, *sparse_val;
  int32_t sparse_ict;
} pb_span;

/* Element i's data: whether the span has bytes for it (a sparse value or
 * the base bufferView); an element with none reads as zero. */
static inline int pb_span_has_data(const pb_span *sp) { return sp->base || sp->sparse_count; }

/* Checks doc->accessors[idx], used at `where` (a JSON path), against
 * `components` per element and the 0-terminated list of allowed component
 * types, then its bufferViews and buffers. */
pb_result pb_accessor_check(const char *path, const pb_gltf_doc *doc, int32_t idx, const char *where, int components,
                            const int32_t *types, pb_span *out);

/* Component c of element i as a float, normalized integers mapped per the
 * glTF spec (3.11: unsigned c / (2^n - 1), signed max(c / (2^(n-1) - 1), -1)). */
float pb_span_f(const pb_span *sp, uint64_t i, int c);

/* Element i of an index or joint accessor (UBYTE, USHORT, UINT scalars or
 * one component of a vector), as an integer. */
uint32_t pb_span_u(const pb_span *sp, uint64_t i, int c);

#endif
