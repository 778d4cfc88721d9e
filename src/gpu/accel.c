/* Acceleration structures for VK_KHR_ray_query (see gpu.h): one bottom-level
 * structure over a triangle list and one top-level structure holding it,
 * built on the GPU from buffers with device addresses. Only on a device
 * created with the ray-query extensions (pb_gpu_limits.ray_query); the GLSL
 * BVH (bvh.c, shaders/common/bvh.glsl) serves every other device.
 *
 * The instance is the identity, mask 0xff, custom index 0, face culling off
 * (back faces count, as in the GLSL BVH and Embree); the geometry is opaque,
 * so no any-hit work reaches the shader and a ray query's primitive index is
 * the triangle's index in the desc. */
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
  pb_gpu_buffer_destroy(g, &a->tlas_buffer);
  pb_gpu_buffer_destroy(g, &a->blas_buffer);
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

/* Sizes a structure of `type` from `geom`, makes its storage and the
 * handle; *scratch_bytes: what its build needs. */
static pb_result make_structure(pb_gpu *g, const accel_fns *f, const char *name, VkAccelerationStructureTypeKHR type,
                                const VkAccelerationStructureGeometryKHR *geom, uint32_t primitives,
                                pb_gpu_buffer *storage, VkAccelerationStructureKHR *as, uint64_t *scratch_bytes) {
  VkAccelerationStructureBuildGeometryInfoKHR bi = {
      .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR,
      .type = type,
      .flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR,
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
  return PB_OK;
}

pb_result pb_gpu_accel_create(pb_gpu *g, const pb_gpu_accel_desc *d, pb_gpu_accel *a) {
  memset(a, 0, sizeof *a);
  const char *name = d->name ? d->name : "accel";
  if (!g->limits.ray_query)
    return pb_fail(PB_ERR_NOT_AVAILABLE, "%s: acceleration structures need a device with ray queries "
                   "(VK_KHR_acceleration_structure, VK_KHR_ray_query); %s has none", name, g->name);
  if (d->triangle_count == 0 || d->vertex_count == 0 || !d->positions || !d->indices)
    return pb_fail(PB_ERR_USAGE, "%s: no triangles", name);
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

  pb_gpu_buffer vtx = {0}, idx = {0}, inst = {0}, scratch = {0};
  pb_result r = make_buffer(g, name, "vertices", 12ull * d->vertex_count, d->positions, &vtx);
  if (r == PB_OK) r = make_buffer(g, name, "indices", 12ull * d->triangle_count, d->indices, &idx);
  if (r != PB_OK) goto fail;

  VkAccelerationStructureGeometryKHR tri = {
      .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR,
      .geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR,
      .geometry.triangles =
          {
              .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR,
              .vertexFormat = VK_FORMAT_R32G32B32_SFLOAT,
              .vertexData.deviceAddress = buffer_address(&f, g, &vtx),
              .vertexStride = 12,
              .maxVertex = d->vertex_count - 1,
              .indexType = VK_INDEX_TYPE_UINT32,
              .indexData.deviceAddress = buffer_address(&f, g, &idx),
          },
      .flags = VK_GEOMETRY_OPAQUE_BIT_KHR,
  };
  uint64_t blas_scratch = 0, tlas_scratch = 0;
  r = make_structure(g, &f, name, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, &tri, d->triangle_count,
                     &a->blas_buffer, &a->blas, &blas_scratch);
  if (r != PB_OK) goto fail;
  VkAccelerationStructureDeviceAddressInfoKHR ai = {
      .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR, .accelerationStructure = a->blas};
  VkAccelerationStructureInstanceKHR instance = {
      .transform.matrix = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}},
      .instanceCustomIndex = 0,
      .mask = 0xff,
      .instanceShaderBindingTableRecordOffset = 0,
      .flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR,
      .accelerationStructureReference = f.as_address(g->device, &ai),
  };
  r = make_buffer(g, name, "instances", sizeof instance, &instance, &inst);
  if (r != PB_OK) goto fail;
  VkAccelerationStructureGeometryKHR ins = {
      .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR,
      .geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR,
      .geometry.instances =
          {
              .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR,
              .arrayOfPointers = VK_FALSE,
              .data.deviceAddress = buffer_address(&f, g, &inst),
          },
      .flags = VK_GEOMETRY_OPAQUE_BIT_KHR,
  };
  r = make_structure(g, &f, name, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, &ins, 1, &a->tlas_buffer, &a->tlas,
                     &tlas_scratch);
  if (r != PB_OK) goto fail;
  /* One scratch buffer for both builds (a barrier between them), its
   * address rounded up to the device's scratch alignment. */
  uint64_t scratch_bytes = (blas_scratch > tlas_scratch ? blas_scratch : tlas_scratch) + align;
  r = make_buffer(g, name, "scratch", scratch_bytes, NULL, &scratch);
  if (r != PB_OK) goto fail;
  VkDeviceAddress sa = (buffer_address(&f, g, &scratch) + align - 1) / align * align;

  VkAccelerationStructureBuildGeometryInfoKHR bb = {
      .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR,
      .type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR,
      .flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR,
      .mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR,
      .dstAccelerationStructure = a->blas,
      .geometryCount = 1,
      .pGeometries = &tri,
      .scratchData.deviceAddress = sa,
  };
  VkAccelerationStructureBuildGeometryInfoKHR tb = bb;
  tb.type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR;
  tb.dstAccelerationStructure = a->tlas;
  tb.pGeometries = &ins;
  VkAccelerationStructureBuildRangeInfoKHR br = {.primitiveCount = d->triangle_count};
  VkAccelerationStructureBuildRangeInfoKHR tr = {.primitiveCount = 1};
  const VkAccelerationStructureBuildRangeInfoKHR *brp = &br, *trp = &tr;
  /* Between the builds: the bottom level written before the top level
   * reads it, and the scratch memory reused. After: the top level written
   * before compute shaders trace it (the next submission starts with a full
   * barrier too, gpu.h pb_gpu_begin). */
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
  r = pb_gpu_begin(g);
  if (r != PB_OK) goto fail;
  f.cmd_build(g->cmd, 1, &bb, &brp);
  vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                       VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, 0, 1, &between, 0, NULL, 0, NULL);
  f.cmd_build(g->cmd, 1, &tb, &trp);
  vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &after, 0, NULL, 0, NULL);
  double t0 = pb_time_now();
  r = pb_gpu_submit(g);
  a->build_ms = (pb_time_now() - t0) * 1e3;
  if (r != PB_OK) goto fail;
  a->bytes = a->blas_buffer.size + a->tlas_buffer.size;
  pb_log_verbose("gpu: %s: %u triangles, acceleration structures %.1f KiB, built in %.1f ms", name, d->triangle_count,
                 (double)a->bytes / 1024.0, a->build_ms);
  pb_gpu_buffer_destroy(g, &scratch);
  pb_gpu_buffer_destroy(g, &inst);
  pb_gpu_buffer_destroy(g, &idx);
  pb_gpu_buffer_destroy(g, &vtx);
  return PB_OK;
fail:
  pb_gpu_buffer_destroy(g, &scratch);
  pb_gpu_buffer_destroy(g, &inst);
  pb_gpu_buffer_destroy(g, &idx);
  pb_gpu_buffer_destroy(g, &vtx);
  pb_gpu_accel_destroy(g, a);
  return r;
}
