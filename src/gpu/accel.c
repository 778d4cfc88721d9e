/* Acceleration structures for VK_KHR_ray_query (see gpu.h): one bottom-level
 * structure over a triangle list and one top-level structure holding it,
 * built on the GPU from buffers with device addresses. Only on a device
 * created with the ray-query extensions (pb_gpu_limits.ray_query); the GLSL
 * BVH (bvh.c, shaders/common/bvh.glsl) serves every other device.
 *
 * The instance is the identity, mask 0xff, custom index 0, face culling off
 * (back faces count, as in the GLSL BVH and Embree); the geometry is opaque,
 * so no any-hit work reaches the shader and a ray query's primitive index is
 * the triangle's index in the desc. A structure keeps its vertex, index,
 * instance and scratch buffers, and pb_gpu_accel_update builds it again
 * (or, made updatable, refits it) in place over new positions, so that the
 * pipelines bound to it stay valid; an animated scene does this where the GLSL BVH is
 * refitted or rebuilt (render/scene/scene_gpu.c). No triangles: an empty top level
 * (every query misses). */
#include <stdio.h>
#include <string.h>

#include "core/log.h"
#include "gpu/gpu_internal.h"

/* The extension's entry points (the loader exports none of them). */
typedef struct accel_fns {
  PFN_vkGetBufferDeviceAddressKHR buffer_address;
  PFN_vkGetAccelerationStructureBuildSizesKHR build_sizes;
  PFN_vkCreateAccelerationStructureKHR create;
  PFN_vkDestroyAccelerationStructureKHR destroy;
  PFN_vkCmdBuildAccelerationStructuresKHR cmd_build;
  PFN_vkGetAccelerationStructureDeviceAddressKHR as_address;
} accel_fns;

static int load_fns(const pb_gpu *g, accel_fns *f) {
  f->buffer_address = (PFN_vkGetBufferDeviceAddressKHR)vkGetDeviceProcAddr(g->device, "vkGetBufferDeviceAddressKHR");
  f->build_sizes = (PFN_vkGetAccelerationStructureBuildSizesKHR)vkGetDeviceProcAddr(
      g->device, "vkGetAccelerationStructureBuildSizesKHR");
  f->create =
      (PFN_vkCreateAccelerationStructureKHR)vkGetDeviceProcAddr(g->device, "vkCreateAccelerationStructureKHR");
  f->destroy =
      (PFN_vkDestroyAccelerationStructureKHR)vkGetDeviceProcAddr(g->device, "vkDestroyAccelerationStructureKHR");
  f->cmd_build =
      (PFN_vkCmdBuildAccelerationStructuresKHR)vkGetDeviceProcAddr(g->device, "vkCmdBuildAccelerationStructuresKHR");
  f->as_address = (PFN_vkGetAccelerationStructureDeviceAddressKHR)vkGetDeviceProcAddr(
      g->device, "vkGetAccelerationStructureDeviceAddressKHR");
  return f->buffer_address && f->build_sizes && f->create && f->destroy && f->cmd_build && f->as_address;
}

static VkDeviceAddress buffer_address(const accel_fns *f, const pb_gpu *g, const pb_gpu_buffer *b) {
  VkBufferDeviceAddressInfo i = {.sType = VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO, .buffer = b->buffer};
  return f->buffer_address(g->device, &i);
}

void pb_gpu_accel_destroy(pb_gpu *g, pb_gpu_accel *a) {
  if (!a) return;
  if (g && g->device && (a->blas || a->tlas)) {
    (void)pb_gpu_settle(g); /* a pending submission may trace it */
    PFN_vkDestroyAccelerationStructureKHR destroy =
        (PFN_vkDestroyAccelerationStructureKHR)vkGetDeviceProcAddr(g->device, "vkDestroyAccelerationStructureKHR");
    if (destroy) {
      if (a->tlas) destroy(g->device, a->tlas, NULL);
      if (a->blas) destroy(g->device, a->blas, NULL);
    }
  }
  pb_gpu_buffer *b[] = {&a->tlas_buffer, &a->blas_buffer, &a->vertices, &a->indices, &a->instances, &a->scratch};
  for (size_t i = 0; i < sizeof b / sizeof *b; ++i) pb_gpu_buffer_destroy(g, b[i]);
  memset(a, 0, sizeof *a);
}

/* A device-address buffer named "<name>.<what>" of `size` bytes, filled
 * from data when data is not NULL. */
static pb_result make_buffer(pb_gpu *g, const char *name, const char *what, uint64_t size, const void *data,
                             pb_gpu_buffer *out) {
  char nm[96];
  snprintf(nm, sizeof nm, "%s.%s", name, what);
  pb_gpu_buffer_desc d = {.name = nm, .size = size ? size : 4, .device_address = 1};
  pb_result r = pb_gpu_buffer_create(g, &d, out);
  if (r == PB_OK && data) r = pb_gpu_buffer_upload(g, out, 0, data, size);
  return r;
}

/* The two geometries of a's structures: its triangles, and its instance. */
static void geometries(const accel_fns *f, const pb_gpu *g, const pb_gpu_accel *a,
                       VkAccelerationStructureGeometryKHR *tri, VkAccelerationStructureGeometryKHR *ins) {
  *tri = (VkAccelerationStructureGeometryKHR){
      .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR,
      .geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR,
      .geometry.triangles =
          {
              .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR,
              .vertexFormat = VK_FORMAT_R32G32B32_SFLOAT,
              .vertexData.deviceAddress = a->triangle_count ? buffer_address(f, g, &a->vertices) : 0,
              .vertexStride = 12,
              .maxVertex = a->vertex_count ? a->vertex_count - 1 : 0,
              .indexType = VK_INDEX_TYPE_UINT32,
              .indexData.deviceAddress = a->triangle_count ? buffer_address(f, g, &a->indices) : 0,
          },
      .flags = VK_GEOMETRY_OPAQUE_BIT_KHR,
  };
  *ins = (VkAccelerationStructureGeometryKHR){
      .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR,
      .geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR,
      .geometry.instances =
          {
              .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR,
              .arrayOfPointers = VK_FALSE,
              .data.deviceAddress = buffer_address(f, g, &a->instances),
          },
      .flags = VK_GEOMETRY_OPAQUE_BIT_KHR,
  };
}

static VkBuildAccelerationStructureFlagsKHR build_flags(const pb_gpu_accel *a) {
  return VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR |
         (a->updatable ? VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_UPDATE_BIT_KHR : 0);
}

/* Sizes a structure of `type` from `geom`, makes its storage and the
 * handle; *scratch_bytes: what its build (and, updatable, its update)
 * needs. */
static pb_result make_structure(pb_gpu *g, const accel_fns *f, const pb_gpu_accel *a, const char *name,
                                VkAccelerationStructureTypeKHR type, const VkAccelerationStructureGeometryKHR *geom,
                                uint32_t primitives, pb_gpu_buffer *storage, VkAccelerationStructureKHR *as,
                                uint64_t *scratch_bytes) {
  VkAccelerationStructureBuildGeometryInfoKHR bi = {
      .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR,
      .type = type,
      .flags = build_flags(a),
      .mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR,
      .geometryCount = 1,
      .pGeometries = geom,
  };
  VkAccelerationStructureBuildSizesInfoKHR sz = {.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
  f->build_sizes(g->device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &bi, &primitives, &sz);
  const char *what = type == VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR ? "blas" : "tlas";
  pb_result r = make_buffer(g, name, what, sz.accelerationStructureSize, NULL, storage);
  if (r != PB_OK) return r;
  VkAccelerationStructureCreateInfoKHR ci = {
      .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR,
      .buffer = storage->buffer,
      .size = sz.accelerationStructureSize,
      .type = type,
  };
  VkResult vr = f->create(g->device, &ci, NULL, as);
  if (vr != VK_SUCCESS) {
    *as = VK_NULL_HANDLE;
    char label[96];
    snprintf(label, sizeof label, "%s: vkCreateAccelerationStructureKHR (%s)", name, what);
    return pb_vk_fail(vr, label);
  }
  char nm[96];
  snprintf(nm, sizeof nm, "%s.%s", name, what);
  pb_gpu_set_name(g, VK_OBJECT_TYPE_ACCELERATION_STRUCTURE_KHR, (uint64_t)*as, nm);
  *scratch_bytes = sz.buildScratchSize;
  if (a->updatable && sz.updateScratchSize > *scratch_bytes) *scratch_bytes = sz.updateScratchSize;
  return PB_OK;
}

/* Records and runs the builds of both levels (refit: VK's update mode, the
 * structures their own source) and waits. */
static pb_result run_builds(pb_gpu *g, const accel_fns *f, pb_gpu_accel *a, int refit) {
  VkAccelerationStructureGeometryKHR tri, ins;
  geometries(f, g, a, &tri, &ins);
  VkBuildAccelerationStructureModeKHR mode =
      refit ? VK_BUILD_ACCELERATION_STRUCTURE_MODE_UPDATE_KHR : VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
  VkAccelerationStructureBuildGeometryInfoKHR bb = {
      .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR,
      .type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR,
      .flags = build_flags(a),
      .mode = mode,
      .srcAccelerationStructure = refit ? a->blas : VK_NULL_HANDLE,
      .dstAccelerationStructure = a->blas,
      .geometryCount = 1,
      .pGeometries = &tri,
      .scratchData.deviceAddress = a->scratch_address,
  };
  VkAccelerationStructureBuildGeometryInfoKHR tb = bb;
  tb.type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR;
  tb.srcAccelerationStructure = refit ? a->tlas : VK_NULL_HANDLE;
  tb.dstAccelerationStructure = a->tlas;
  tb.pGeometries = &ins;
  VkAccelerationStructureBuildRangeInfoKHR br = {.primitiveCount = a->triangle_count};
  VkAccelerationStructureBuildRangeInfoKHR tr = {.primitiveCount = a->triangle_count ? 1u : 0u};
  const VkAccelerationStructureBuildRangeInfoKHR *brp = &br, *trp = &tr;
  /* Before: the host's uploads (vertices) visible to the build. Between the
   * builds: the bottom level written before the top level reads it, and
   * the scratch memory reused. After: the top level written before compute
   * shaders trace it (the next submission starts with a full barrier too,
   * gpu.h pb_gpu_begin). */
  VkMemoryBarrier before = {
      .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
      .srcAccessMask = VK_ACCESS_HOST_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT,
      .dstAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR | VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
  };
  VkMemoryBarrier between = {
      .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
      .srcAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
      .dstAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR | VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
  };
  VkMemoryBarrier after = {
      .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
      .srcAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
      .dstAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR,
  };
  pb_result r = pb_gpu_begin(g);
  if (r != PB_OK) return r;
  vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                                   VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, 0, 1, &before, 0, NULL, 0, NULL);
  if (a->triangle_count) {
    f->cmd_build(g->cmd, 1, &bb, &brp);
    vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                         VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, 0, 1, &between, 0, NULL, 0, NULL);
  }
  f->cmd_build(g->cmd, 1, &tb, &trp);
  vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &after, 0, NULL, 0, NULL);
  double t0 = pb_time_now();
  r = pb_gpu_submit(g);
  a->build_ms = (pb_time_now() - t0) * 1e3;
  return r;
}

pb_result pb_gpu_accel_create(pb_gpu *g, const pb_gpu_accel_desc *d, pb_gpu_accel *a) {
  memset(a, 0, sizeof *a);
  const char *name = d->name ? d->name : "accel";
  if (!g->limits.ray_query)
    return pb_fail(PB_ERR_NOT_AVAILABLE, "%s: acceleration structures need a device with ray queries "
                   "(VK_KHR_acceleration_structure, VK_KHR_ray_query); %s has none", name, g->name);
  if (d->triangle_count && (d->vertex_count == 0 || !d->positions || !d->indices))
    return pb_fail(PB_ERR_USAGE, "%s: triangles without vertices", name);
  for (uint64_t i = 0; i < 3ull * d->triangle_count; ++i)
    if (d->indices[i] >= d->vertex_count)
      return pb_fail(PB_ERR_USAGE, "%s: triangle %llu names vertex %u of %u", name, (unsigned long long)(i / 3),
                     d->indices[i], d->vertex_count);
  accel_fns f;
  if (!load_fns(g, &f)) return pb_fail(PB_ERR_NOT_AVAILABLE, "%s: the driver lacks the acceleration-structure "
                                       "entry points", name);
  VkPhysicalDeviceAccelerationStructurePropertiesKHR asp = {
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR};
  VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &asp};
  vkGetPhysicalDeviceProperties2(g->phys, &p2);
  uint64_t align = asp.minAccelerationStructureScratchOffsetAlignment ? asp.minAccelerationStructureScratchOffsetAlignment : 1;
  a->vertex_count = d->triangle_count ? d->vertex_count : 0;
  a->triangle_count = d->triangle_count;
  a->updatable = d->updatable && d->triangle_count;

  pb_result r = PB_OK;
  VkAccelerationStructureInstanceKHR instance = {
      .transform.matrix = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}},
      .instanceCustomIndex = 0,
      .mask = 0xff,
      .instanceShaderBindingTableRecordOffset = 0,
      .flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR,
  };
  VkAccelerationStructureGeometryKHR tri, ins;
  uint64_t blas_scratch = 0, tlas_scratch = 0;
  if (a->triangle_count) {
    if ((r = make_buffer(g, name, "vertices", 12ull * d->vertex_count, d->positions, &a->vertices)) != PB_OK ||
        (r = make_buffer(g, name, "indices", 12ull * d->triangle_count, d->indices, &a->indices)) != PB_OK)
      goto fail;
    if ((r = make_buffer(g, name, "instances", sizeof instance, NULL, &a->instances)) != PB_OK) goto fail;
    geometries(&f, g, a, &tri, &ins);
    r = make_structure(g, &f, a, name, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, &tri, d->triangle_count,
                       &a->blas_buffer, &a->blas, &blas_scratch);
    if (r != PB_OK) goto fail;
    VkAccelerationStructureDeviceAddressInfoKHR ai = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR, .accelerationStructure = a->blas};
    instance.accelerationStructureReference = f.as_address(g->device, &ai);
    if ((r = pb_gpu_buffer_upload(g, &a->instances, 0, &instance, sizeof instance)) != PB_OK) goto fail;
  } else if ((r = make_buffer(g, name, "instances", sizeof instance, NULL, &a->instances)) != PB_OK) {
    goto fail;
  }
  geometries(&f, g, a, &tri, &ins);
  r = make_structure(g, &f, a, name, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, &ins, a->triangle_count ? 1 : 0,
                     &a->tlas_buffer, &a->tlas, &tlas_scratch);
  if (r != PB_OK) goto fail;
  /* One scratch buffer for both builds (a barrier between them), its
   * address rounded up to the device's scratch alignment. */
  uint64_t scratch_bytes = (blas_scratch > tlas_scratch ? blas_scratch : tlas_scratch) + align;
  if ((r = make_buffer(g, name, "scratch", scratch_bytes, NULL, &a->scratch)) != PB_OK) goto fail;
  a->scratch_address = (buffer_address(&f, g, &a->scratch) + align - 1) / align * align;
  if ((r = run_builds(g, &f, a, 0)) != PB_OK) goto fail;
  a->bytes = a->blas_buffer.size + a->tlas_buffer.size;
  pb_log_verbose("gpu: %s: %u triangles, acceleration structures %.1f KiB, built in %.1f ms", name, d->triangle_count,
                 (double)a->bytes / 1024.0, a->build_ms);
  return PB_OK;
fail:
  pb_gpu_accel_destroy(g, a);
  return r;
}

pb_result pb_gpu_accel_update(pb_gpu *g, pb_gpu_accel *a, const float *positions, int refit) {
  if (!a->tlas) return pb_fail(PB_ERR_INTERNAL, "gpu: update of an acceleration structure never built");
  if (!a->triangle_count) return PB_OK;
  accel_fns f;
  if (!load_fns(g, &f)) return pb_fail(PB_ERR_NOT_AVAILABLE, "gpu: the driver lacks the acceleration-structure "
                                       "entry points");
  pb_result r = pb_gpu_buffer_upload(g, &a->vertices, 0, positions, 12ull * a->vertex_count);
  if (r != PB_OK) return r;
  return run_builds(g, &f, a, refit && a->updatable);
}
