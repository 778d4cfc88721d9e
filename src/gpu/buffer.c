/* Storage buffers and their memory (see gpu.h). One allocation per buffer:
 * the renderer makes a dozen, far from any allocation-count limit. Memory is
 * device-local when possible and mapped persistently when that memory is also
 * host-visible and coherent (integrated GPUs, lavapipe); otherwise transfers
 * go through a temporary staging buffer. */
#include <stdlib.h>
#include <string.h>

#include "gpu/gpu_internal.h"

static uint32_t find_type(const pb_gpu *g, uint32_t bits, VkMemoryPropertyFlags want) {
  for (uint32_t i = 0; i < g->mem.memoryTypeCount; ++i)
    if ((bits >> i & 1) && (g->mem.memoryTypes[i].propertyFlags & want) == want) return i;
  return UINT32_MAX;
}

void pb_gpu_buffer_destroy(pb_gpu *g, pb_gpu_buffer *b) {
  if (!b) return;
  if (b->buffer) (void)pb_gpu_settle(g); /* a pending submission may use it */
  if (g && b->memory && b->size) g->memory_live -= b->size <= g->memory_live ? b->size : g->memory_live;
  if (g && g->device) {
    if (b->mapped) vkUnmapMemory(g->device, b->memory);
    if (b->buffer) vkDestroyBuffer(g->device, b->buffer, NULL);
    if (b->memory) vkFreeMemory(g->device, b->memory, NULL);
  }
  memset(b, 0, sizeof *b);
}

pb_result pb_gpu_buffer_create(pb_gpu *g, const pb_gpu_buffer_desc *d, pb_gpu_buffer *out) {
  memset(out, 0, sizeof *out);
  const char *name = d->name ? d->name : "buffer";
  if (d->size == 0) return pb_fail(PB_ERR_INTERNAL, "gpu: buffer '%s' of size 0", name);
  if (d->size > g->limits.max_storage_buffer_range)
    return pb_fail(PB_ERR_LIMIT,
                   "%s: %.1f MiB in one storage buffer exceeds %s's maxStorageBufferRange "
                   "(%.1f MiB); render a smaller image or scene, or use a device with a larger limit",
                   name, (double)d->size / 1048576.0, g->name,
                   (double)g->limits.max_storage_buffer_range / 1048576.0);
  if (d->size > g->limits.max_allocation)
    return pb_fail(PB_ERR_LIMIT, "%s: %.1f MiB exceeds %s's maxMemoryAllocationSize (%.1f MiB)", name,
                   (double)d->size / 1048576.0, g->name, (double)g->limits.max_allocation / 1048576.0);
  /* The memory cap (--gpu-memory-limit, PB_GPU_MEMORY_LIMIT): live
   * allocations summed, checked before the driver is asked. */
  if (g->memory_limit && (d->size > g->memory_limit || g->memory_live > g->memory_limit - d->size))
    return pb_fail(PB_ERR_NOMEM,
                   "%s: GPU buffer of %.1f MiB would bring GPU memory in use to %.1f MiB, over the cap of "
                   "%.1f MiB (--gpu-memory-limit / PB_GPU_MEMORY_LIMIT); render a smaller image, fewer "
                   "photons, or raise the cap",
                   name, (double)d->size / 1048576.0, (double)(g->memory_live + d->size) / 1048576.0,
                   (double)g->memory_limit / 1048576.0);
  if (d->device_address && !g->limits.ray_query)
    return pb_fail(PB_ERR_NOT_AVAILABLE, "%s: a buffer with a device address needs a device with ray queries "
                   "(VK_KHR_acceleration_structure, VK_KHR_ray_query); %s has none", name, g->name);
  VkBufferCreateInfo bci = {
      .sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
      .size = d->size,
      .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
               VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
               (d->device_address ? VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
                                        VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR |
                                        VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR
                                  : 0),
      .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
  };
  pb_result r;
  VkResult vr = vkCreateBuffer(g->device, &bci, NULL, &out->buffer);
  if (vr != VK_SUCCESS) {
    out->buffer = VK_NULL_HANDLE;
    return pb_vk_fail(vr, name);
  }
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(g->device, out->buffer, &req);
  const VkMemoryPropertyFlags hv = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  uint32_t type = d->readback ? find_type(g, req.memoryTypeBits, hv | VK_MEMORY_PROPERTY_HOST_CACHED_BIT) : UINT32_MAX;
  if (type == UINT32_MAX) type = find_type(g, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | hv);
  if (type == UINT32_MAX)
    type = d->host_visible ? find_type(g, req.memoryTypeBits, hv)
                           : find_type(g, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  if (type == UINT32_MAX) type = find_type(g, req.memoryTypeBits, 0);
  if (type == UINT32_MAX) {
    r = pb_fail(PB_ERR_VULKAN, "%s: no memory type fits the buffer", name);
    goto fail;
  }
  VkMemoryAllocateFlagsInfo maf = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO,
                                   .flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT};
  VkMemoryAllocateInfo mai = {
      .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
      .pNext = d->device_address ? &maf : NULL,
      .allocationSize = req.size,
      .memoryTypeIndex = type,
  };
  vr = vkAllocateMemory(g->device, &mai, NULL, &out->memory);
  if (vr != VK_SUCCESS) {
    out->memory = VK_NULL_HANDLE;
    if (vr == VK_ERROR_OUT_OF_DEVICE_MEMORY || vr == VK_ERROR_OUT_OF_HOST_MEMORY)
      r = pb_fail(PB_ERR_NOMEM,
                  "%s: %s allocating a GPU buffer of %.1f MiB (%.1f MiB already in use) on %s; render a "
                  "smaller image, fewer photons, or use a device with more memory",
                  name, pb_vk_result_name(vr), (double)req.size / 1048576.0,
                  (double)g->memory_live / 1048576.0, g->name);
    else
      r = pb_vk_fail(vr, name);
    goto fail;
  }
  vr = vkBindBufferMemory(g->device, out->buffer, out->memory, 0);
  if (vr != VK_SUCCESS) {
    r = pb_vk_fail(vr, name);
    goto fail;
  }
  if ((g->mem.memoryTypes[type].propertyFlags & hv) == hv) {
    vr = vkMapMemory(g->device, out->memory, 0, VK_WHOLE_SIZE, 0, &out->mapped);
    if (vr != VK_SUCCESS) {
      out->mapped = NULL;
      r = pb_vk_fail(vr, name);
      goto fail;
    }
    out->cached = (g->mem.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_CACHED_BIT) != 0;
  }
  out->size = d->size;
  out->id = ++g->next_buffer_id;
  g->memory_live += d->size;
  if (g->memory_live > g->memory_peak) g->memory_peak = g->memory_live;
  pb_gpu_set_name(g, VK_OBJECT_TYPE_BUFFER, (uint64_t)out->buffer, name);
  pb_gpu_set_name(g, VK_OBJECT_TYPE_DEVICE_MEMORY, (uint64_t)out->memory, name);
  return PB_OK;
fail:
  pb_gpu_buffer_destroy(g, out);
  return r;
}

/* Copies between a device buffer and a temporary host-visible one. */
static pb_result staged(pb_gpu *g, const pb_gpu_buffer *b, uint64_t offset, void *host,
                        uint64_t size, int upload) {
  pb_gpu_buffer st;
  pb_gpu_buffer_desc sd = {.name = "pb.staging", .size = size, .host_visible = 1, .readback = !upload};
  pb_result r = pb_gpu_buffer_create(g, &sd, &st);
  if (r != PB_OK) return r;
  if (!st.mapped) {
    pb_gpu_buffer_destroy(g, &st);
    return pb_fail(PB_ERR_VULKAN, "gpu: staging memory is not mappable");
  }
  if (upload) memcpy(st.mapped, host, size);
  uint32_t keep_ts = g->read_sub; /* a staged copy has no timestamps: the last pass's stay readable */
  r = pb_gpu_begin(g);
  if (r != PB_OK) goto done;
  VkBufferCopy c = {.srcOffset = upload ? 0 : offset, .dstOffset = upload ? offset : 0, .size = size};
  vkCmdCopyBuffer(g->cmd, upload ? st.buffer : b->buffer, upload ? b->buffer : st.buffer, 1, &c);
  r = pb_gpu_submit(g);
  if (keep_ts != UINT32_MAX && g->subs[keep_ts].serial && keep_ts != g->cur) g->read_sub = keep_ts;
  if (r == PB_OK && !upload) memcpy(host, st.mapped, size);
done:
  pb_gpu_buffer_destroy(g, &st);
  return r;
}

static pb_result check_range(const pb_gpu_buffer *b, uint64_t offset, uint64_t size) {
  if (offset > b->size || size > b->size - offset)
    return pb_fail(PB_ERR_INTERNAL, "gpu: transfer of %llu bytes at %llu past a %llu-byte buffer",
                   (unsigned long long)size, (unsigned long long)offset, (unsigned long long)b->size);
  return PB_OK;
}

pb_result pb_gpu_buffer_upload(pb_gpu *g, pb_gpu_buffer *b, uint64_t offset, const void *data,
                               uint64_t size) {
  pb_result r = check_range(b, offset, size);
  if (r != PB_OK || size == 0) return r;
  /* Frames in flight (gpu.h pb_gpu_submit_async): the GPU may still read b.
   * A small write goes into the next command buffer, after that; a larger
   * one waits. */
  if (pb_gpu_can_defer(g) && size <= 65536 && offset % 4 == 0 && size % 4 == 0) {
    g->transfers.upload_bytes += size, g->transfers.uploads++;
    return pb_gpu_defer_write(g, b, offset, data, size);
  }
  pb_gpu_note_host_write(g);
  if ((r = pb_gpu_settle(g)) != PB_OK) return r;
  g->transfers.upload_bytes += size, g->transfers.uploads++;
  if (b->mapped) {
    memcpy((char *)b->mapped + offset, data, size);
    return PB_OK;
  }
  return staged(g, b, offset, (void *)(uintptr_t)data, size, 1);
}

pb_result pb_gpu_buffer_download(pb_gpu *g, const pb_gpu_buffer *b, uint64_t offset, void *data,
                                 uint64_t size) {
  pb_result r = check_range(b, offset, size);
  if (r != PB_OK || size == 0) return r;
  if ((r = pb_gpu_settle(g)) != PB_OK) return r; /* frames in flight: the GPU may use b */
  g->transfers.download_bytes += size, g->transfers.downloads++;
  if (b->mapped && b->cached) {
    memcpy(data, (const char *)b->mapped + offset, size);
    return PB_OK;
  }
  return staged(g, b, offset, data, size, 0); /* GPU copy into cached memory, then read */
}

pb_gpu_transfers pb_gpu_transfers_get(const pb_gpu *g) { return g->transfers; }

void pb_gpu_note_read_back(pb_gpu *g, uint64_t size) { g->transfers.readback_bytes += size; }

pb_result pb_gpu_buffer_read_back(pb_gpu *g, const pb_gpu_buffer *b, uint64_t offset, void *data, uint64_t size) {
  pb_gpu_transfers keep = g->transfers;
  pb_result r = pb_gpu_buffer_download(g, b, offset, data, size);
  g->transfers = keep;
  if (r == PB_OK) g->transfers.readback_bytes += size;
  return r;
}

pb_result pb_gpu_buffer_fill_zero(pb_gpu *g, pb_gpu_buffer *b) {
  if (pb_gpu_can_defer(g)) return pb_gpu_defer_write(g, b, 0, NULL, b->size); /* as an upload (above) */
  pb_gpu_note_host_write(g);
  pb_result rs = pb_gpu_settle(g);
  if (rs != PB_OK) return rs;
  if (b->mapped) {
    memset(b->mapped, 0, b->size);
    return PB_OK;
  }
  pb_result r = pb_gpu_begin(g);
  if (r != PB_OK) return r;
  vkCmdFillBuffer(g->cmd, b->buffer, 0, VK_WHOLE_SIZE, 0);
  return pb_gpu_submit(g);
}
