/* Compute pipelines from embedded SPIR-V (see gpu.h): one descriptor set of
 * storage buffers (and acceleration structures on a device with ray
 * queries), an optional push-constant block, and specialization
 * constants so that a scene's pipeline holds only the features it uses. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "gpu/gpu_internal.h"

static pb_result validate(const pb_gpu_pipeline_desc *d) {
  const char *n = d->name ? d->name : "pipeline";
  if (!d->spirv || d->spirv_bytes < 20 || d->spirv_bytes % 4 || d->spirv[0] != 0x07230203u)
    return pb_fail(PB_ERR_INTERNAL, "gpu: %s: embedded SPIR-V is missing or malformed", n);
  if (d->binding_count == 0 || d->binding_count > PB_GPU_MAX_BINDINGS)
    return pb_fail(PB_ERR_INTERNAL, "gpu: %s: %u bindings (1..%d)", n, d->binding_count,
                   PB_GPU_MAX_BINDINGS);
  if (d->binding_count < 32 && d->accel_bindings >> d->binding_count)
    return pb_fail(PB_ERR_INTERNAL, "gpu: %s: acceleration structure beyond its %u bindings", n, d->binding_count);
  if (d->push_bytes % 4 || d->push_bytes > 128)
    return pb_fail(PB_ERR_INTERNAL, "gpu: %s: push constants of %u bytes", n, d->push_bytes);
  if (d->spec_count > PB_GPU_MAX_SPEC || (d->spec_count && !d->spec))
    return pb_fail(PB_ERR_INTERNAL, "gpu: %s: bad specialization constants", n);
  return PB_OK;
}

/* The device's pipeline cache. Creating a compute pipeline compiles its
 * kernel: seconds for the large shading kernels on lavapipe (SPIR-V to NIR
 * and its optimisation are paid at every creation: Mesa 22.3 keeps only the
 * LLVM code on disk), a noticeable pause on GPU drivers. A pass made again
 * for the same SPIR-V, bindings, push block and specialization (the next
 * frame context of `view` or `serve` after a reload or a new size, the next
 * job of `photonbridge batch`) takes the compiled pipeline from here; each
 * pb_gpu_pipeline keeps its own descriptor pool and set. Entries no
 * pipeline uses stay, up to PIPE_KEEP, the least recently used dropped
 * first. */
enum { PIPE_KEEP = 160 };

struct pb_gpu_pipe_entry {
  struct pb_gpu_pipe_entry *next;
  const uint32_t *spirv;
  size_t spirv_bytes;
  uint32_t binding_count, accel_bindings, push_bytes, spec_count;
  uint32_t spec[PB_GPU_MAX_SPEC];
  VkShaderModule module;
  VkDescriptorSetLayout set_layout;
  VkPipelineLayout layout;
  VkPipeline pipeline;
  uint32_t users; /* pb_gpu_pipelines holding it */
};

static void entry_free(pb_gpu *g, struct pb_gpu_pipe_entry *e) {
  if (g && g->device) {
    if (e->pipeline) vkDestroyPipeline(g->device, e->pipeline, NULL);
    if (e->layout) vkDestroyPipelineLayout(g->device, e->layout, NULL);
    if (e->set_layout) vkDestroyDescriptorSetLayout(g->device, e->set_layout, NULL);
    if (e->module) vkDestroyShaderModule(g->device, e->module, NULL);
  }
  free(e);
}

void pb_gpu_pipe_cache_destroy(pb_gpu *g) {
  while (g->pipes) {
    struct pb_gpu_pipe_entry *e = g->pipes;
    g->pipes = e->next;
    entry_free(g, e);
  }
  g->pipe_stats.cached = 0;
}

pb_gpu_pipeline_stats pb_gpu_pipeline_stats_get(const pb_gpu *g) { return g->pipe_stats; }

/* Drops the least recently used entries nothing holds beyond PIPE_KEEP
 * (the list is in order of use, most recent first). */
static void cache_trim(pb_gpu *g) {
  uint32_t idle = 0;
  for (struct pb_gpu_pipe_entry *e = g->pipes; e; e = e->next) idle += e->users == 0;
  if (idle <= PIPE_KEEP) return;
  (void)pb_gpu_settle(g); /* a pending submission may still use an idle pipeline */
  struct pb_gpu_pipe_entry **link = &g->pipes;
  uint32_t seen = 0;
  while (*link) {
    struct pb_gpu_pipe_entry *e = *link;
    if (e->users == 0 && ++seen > PIPE_KEEP) {
      *link = e->next;
      entry_free(g, e);
      g->pipe_stats.evicted++, g->pipe_stats.cached--;
      continue;
    }
    link = &e->next;
  }
}

void pb_gpu_pipeline_destroy(pb_gpu *g, pb_gpu_pipeline *p) {
  if (!p) return;
  if (p->pool) (void)pb_gpu_settle(g); /* a pending submission may use its set */
  if (g && g->device && p->pool) vkDestroyDescriptorPool(g->device, p->pool, NULL);
  if (p->entry && p->entry->users) p->entry->users--;
  memset(p, 0, sizeof *p);
  if (g) cache_trim(g);
}

/* The cached entry for d, found (moved to the front) or made. */
static pb_result entry_get(pb_gpu *g, const pb_gpu_pipeline_desc *d, const char *name,
                           struct pb_gpu_pipe_entry **out) {
  struct pb_gpu_pipe_entry **link = &g->pipes;
  for (; *link; link = &(*link)->next) {
    struct pb_gpu_pipe_entry *e = *link;
    if (e->spirv == d->spirv && e->spirv_bytes == d->spirv_bytes && e->binding_count == d->binding_count &&
        e->accel_bindings == d->accel_bindings && e->push_bytes == d->push_bytes &&
        e->spec_count == d->spec_count && (!d->spec_count || memcmp(e->spec, d->spec, 4u * d->spec_count) == 0)) {
      *link = e->next;
      e->next = g->pipes, g->pipes = e;
      g->pipe_stats.reused++;
      pb_log_verbose("gpu: pipeline %s: from the cache", name);
      *out = e;
      return PB_OK;
    }
  }
  struct pb_gpu_pipe_entry *e = calloc(1, sizeof *e);
  if (!e) return pb_fail(PB_ERR_NOMEM, "gpu: %s: out of memory", name);
  e->spirv = d->spirv, e->spirv_bytes = d->spirv_bytes, e->binding_count = d->binding_count;
  e->accel_bindings = d->accel_bindings, e->push_bytes = d->push_bytes, e->spec_count = d->spec_count;
  if (d->spec_count) memcpy(e->spec, d->spec, 4u * d->spec_count);
  char label[128];
  VkResult vr;
  pb_result r = PB_OK;
  VkShaderModuleCreateInfo smi = {
      .sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
      .codeSize = d->spirv_bytes,
      .pCode = d->spirv,
  };
  vr = vkCreateShaderModule(g->device, &smi, NULL, &e->module);
  if (vr != VK_SUCCESS) {
    e->module = VK_NULL_HANDLE;
    snprintf(label, sizeof label, "%s: vkCreateShaderModule", name);
    r = pb_vk_fail(vr, label);
    goto fail;
  }
  VkDescriptorSetLayoutBinding b[PB_GPU_MAX_BINDINGS];
  for (uint32_t i = 0; i < d->binding_count; ++i)
    b[i] = (VkDescriptorSetLayoutBinding){
        .binding = i,
        .descriptorType = (d->accel_bindings >> i & 1u) ? VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR
                                                         : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
        .descriptorCount = 1,
        .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT,
    };
  VkDescriptorSetLayoutCreateInfo dli = {
      .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
      .bindingCount = d->binding_count,
      .pBindings = b,
  };
  vr = vkCreateDescriptorSetLayout(g->device, &dli, NULL, &e->set_layout);
  if (vr != VK_SUCCESS) {
    e->set_layout = VK_NULL_HANDLE;
    snprintf(label, sizeof label, "%s: vkCreateDescriptorSetLayout", name);
    r = pb_vk_fail(vr, label);
    goto fail;
  }
  VkPushConstantRange pcr = {.stageFlags = VK_SHADER_STAGE_COMPUTE_BIT, .size = d->push_bytes};
  VkPipelineLayoutCreateInfo pli = {
      .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
      .setLayoutCount = 1,
      .pSetLayouts = &e->set_layout,
      .pushConstantRangeCount = d->push_bytes ? 1u : 0u,
      .pPushConstantRanges = &pcr,
  };
  vr = vkCreatePipelineLayout(g->device, &pli, NULL, &e->layout);
  if (vr != VK_SUCCESS) {
    e->layout = VK_NULL_HANDLE;
    snprintf(label, sizeof label, "%s: vkCreatePipelineLayout", name);
    r = pb_vk_fail(vr, label);
    goto fail;
  }
  VkSpecializationMapEntry map[PB_GPU_MAX_SPEC];
  for (uint32_t i = 0; i < d->spec_count; ++i)
    map[i] = (VkSpecializationMapEntry){.constantID = i, .offset = 4 * i, .size = 4};
  VkSpecializationInfo spec = {
      .mapEntryCount = d->spec_count,
      .pMapEntries = map,
      .dataSize = 4u * d->spec_count,
      .pData = d->spec,
  };
  VkComputePipelineCreateInfo cpi = {
      .sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
      .stage =
          {
              .sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
              .stage = VK_SHADER_STAGE_COMPUTE_BIT,
              .module = e->module,
              .pName = "main",
              .pSpecializationInfo = d->spec_count ? &spec : NULL,
          },
      .layout = e->layout,
  };
  double t0 = pb_time_now();
  vr = vkCreateComputePipelines(g->device, VK_NULL_HANDLE, 1, &cpi, NULL, &e->pipeline);
  /* -v: what each pipeline costs to make (lavapipe 22.3 compiles here;
   * Mesa 25's lavapipe at the first dispatch, where the first pass timings
   * of a run show it). */
  double ms = (pb_time_now() - t0) * 1e3;
  pb_log_verbose("gpu: pipeline %s: %.1f ms", name, ms);
  if (vr != VK_SUCCESS) {
    e->pipeline = VK_NULL_HANDLE;
    snprintf(label, sizeof label, "%s: vkCreateComputePipelines", name);
    r = pb_vk_fail(vr, label);
    goto fail;
  }
  g->pipe_stats.created++, g->pipe_stats.cached++;
  g->pipe_stats.create_ms += ms;
  pb_gpu_set_name(g, VK_OBJECT_TYPE_SHADER_MODULE, (uint64_t)e->module, name);
  pb_gpu_set_name(g, VK_OBJECT_TYPE_PIPELINE, (uint64_t)e->pipeline, name);
  pb_gpu_set_name(g, VK_OBJECT_TYPE_PIPELINE_LAYOUT, (uint64_t)e->layout, name);
  pb_gpu_set_name(g, VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, (uint64_t)e->set_layout, name);
  e->next = g->pipes, g->pipes = e;
  *out = e;
  return PB_OK;
fail:
  entry_free(g, e);
  return r;
}

pb_result pb_gpu_pipeline_create(pb_gpu *g, const pb_gpu_pipeline_desc *d, pb_gpu_pipeline *p) {
  memset(p, 0, sizeof *p);
  pb_result r = validate(d);
  if (r != PB_OK) return r;
  const char *name = d->name ? d->name : "pipeline";
  if (d->accel_bindings && !g->limits.ray_query)
    return pb_fail(PB_ERR_NOT_AVAILABLE, "%s: binds an acceleration structure; %s has no ray queries", name, g->name);
  uint32_t accel_count = 0;
  for (uint32_t i = 0; i < d->binding_count; ++i) accel_count += d->accel_bindings >> i & 1u;
  char label[128];
  VkResult vr;
  struct pb_gpu_pipe_entry *e = NULL;
  if ((r = entry_get(g, d, name, &e)) != PB_OK) return r;
  e->users++;
  p->entry = e;
  p->module = e->module, p->set_layout = e->set_layout, p->layout = e->layout, p->pipeline = e->pipeline;
  p->binding_count = d->binding_count;
  p->accel_bindings = d->accel_bindings;
  p->push_bytes = d->push_bytes;
  VkDescriptorPoolSize ps[2] = {
      {.type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .descriptorCount = d->binding_count - accel_count},
      {.type = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, .descriptorCount = accel_count},
  };
  VkDescriptorPoolCreateInfo dpi = {
      .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
      .maxSets = 1,
      .poolSizeCount = accel_count == 0 ? 1u : accel_count == d->binding_count ? 1u : 2u,
      .pPoolSizes = accel_count == d->binding_count ? &ps[1] : ps,
  };
  vr = vkCreateDescriptorPool(g->device, &dpi, NULL, &p->pool);
  if (vr != VK_SUCCESS) {
    p->pool = VK_NULL_HANDLE;
    snprintf(label, sizeof label, "%s: vkCreateDescriptorPool", name);
    r = pb_vk_fail(vr, label);
    goto fail;
  }
  VkDescriptorSetAllocateInfo dai = {
      .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
      .descriptorPool = p->pool,
      .descriptorSetCount = 1,
      .pSetLayouts = &p->set_layout,
  };
  vr = vkAllocateDescriptorSets(g->device, &dai, &p->set);
  if (vr != VK_SUCCESS) {
    snprintf(label, sizeof label, "%s: vkAllocateDescriptorSets", name);
    r = pb_vk_fail(vr, label);
    goto fail;
  }
  pb_gpu_set_name(g, VK_OBJECT_TYPE_DESCRIPTOR_SET, (uint64_t)p->set, name);
  return PB_OK;
fail:
  pb_gpu_pipeline_destroy(g, p);
  return r;
}

pb_result pb_gpu_pipeline_bind(pb_gpu *g, pb_gpu_pipeline *p, const pb_gpu_buffer *const *buffers,
                               uint32_t count) {
  if (count != p->binding_count)
    return pb_fail(PB_ERR_INTERNAL, "gpu: %u buffers bound to a pipeline of %u bindings", count,
                   p->binding_count);
  int same = 1;
  for (uint32_t i = 0; i < count; ++i)
    if (!(p->accel_bindings >> i & 1u) &&
        (!buffers[i] || !buffers[i]->buffer || !buffers[i]->id || buffers[i]->id != p->bound[i]))
      same = 0;
  if (same) { /* what the set holds: a pending submission may use it as it is */
    g->ring.bind_skips++;
    return PB_OK;
  }
  pb_result r = pb_gpu_settle(g); /* the set may be in use by a pending submission */
  if (r != PB_OK) return r;
  VkDescriptorBufferInfo bi[PB_GPU_MAX_BINDINGS];
  VkWriteDescriptorSet w[PB_GPU_MAX_BINDINGS];
  uint32_t nw = 0;
  for (uint32_t i = 0; i < count; ++i) {
    if (p->accel_bindings >> i & 1u) continue;
    if (!buffers[i] || !buffers[i]->buffer)
      return pb_fail(PB_ERR_INTERNAL, "gpu: binding %u has no buffer", i);
    bi[nw] = (VkDescriptorBufferInfo){.buffer = buffers[i]->buffer, .offset = 0, .range = VK_WHOLE_SIZE};
    w[nw] = (VkWriteDescriptorSet){
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
        .dstSet = p->set,
        .dstBinding = i,
        .descriptorCount = 1,
        .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
        .pBufferInfo = &bi[nw],
    };
    ++nw;
  }
  vkUpdateDescriptorSets(g->device, nw, w, 0, NULL);
  for (uint32_t i = 0; i < count; ++i)
    if (!(p->accel_bindings >> i & 1u)) p->bound[i] = buffers[i]->id;
  return PB_OK;
}

pb_result pb_gpu_pipeline_bind_accel(pb_gpu *g, pb_gpu_pipeline *p, uint32_t binding, const pb_gpu_accel *a) {
  if (binding >= p->binding_count || !(p->accel_bindings >> binding & 1u))
    return pb_fail(PB_ERR_INTERNAL, "gpu: binding %u is not an acceleration structure", binding);
  if (!a || !a->tlas) return pb_fail(PB_ERR_INTERNAL, "gpu: binding %u has no acceleration structure", binding);
  pb_result r = pb_gpu_settle(g); /* the set may be in use by a pending submission */
  if (r != PB_OK) return r;
  VkWriteDescriptorSetAccelerationStructureKHR as = {
      .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR,
      .accelerationStructureCount = 1,
      .pAccelerationStructures = &a->tlas,
  };
  VkWriteDescriptorSet w = {
      .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
      .pNext = &as,
      .dstSet = p->set,
      .dstBinding = binding,
      .descriptorCount = 1,
      .descriptorType = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR,
  };
  vkUpdateDescriptorSets(g->device, 1, &w, 0, NULL);
  return PB_OK;
}
