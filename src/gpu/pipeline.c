/* Compute pipelines from embedded SPIR-V (see gpu.h): one descriptor set of
 * storage buffers (and acceleration structures on a device with ray
 * queries), an optional push-constant block, and specialization
 * constants so that a scene's pipeline holds only the features it uses. */
#include <stdio.h>
#include <string.h>

#include "core/log.h"
#include "gpu/gpu_internal.h"

void pb_gpu_pipeline_destroy(pb_gpu *g, pb_gpu_pipeline *p) {
  if (!p) return;
  if (p->pipeline) (void)pb_gpu_settle(g); /* a pending submission may use it */
  if (g && g->device) {
    if (p->pipeline) vkDestroyPipeline(g->device, p->pipeline, NULL);
    if (p->layout) vkDestroyPipelineLayout(g->device, p->layout, NULL);
    if (p->pool) vkDestroyDescriptorPool(g->device, p->pool, NULL);
    if (p->set_layout) vkDestroyDescriptorSetLayout(g->device, p->set_layout, NULL);
    if (p->module) vkDestroyShaderModule(g->device, p->module, NULL);
  }
  memset(p, 0, sizeof *p);
}

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

  VkShaderModuleCreateInfo smi = {
      .sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
      .codeSize = d->spirv_bytes,
      .pCode = d->spirv,
  };
  vr = vkCreateShaderModule(g->device, &smi, NULL, &p->module);
  if (vr != VK_SUCCESS) {
    p->module = VK_NULL_HANDLE;
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
  vr = vkCreateDescriptorSetLayout(g->device, &dli, NULL, &p->set_layout);
  if (vr != VK_SUCCESS) {
    p->set_layout = VK_NULL_HANDLE;
    snprintf(label, sizeof label, "%s: vkCreateDescriptorSetLayout", name);
    r = pb_vk_fail(vr, label);
    goto fail;
  }
  VkPushConstantRange pcr = {.stageFlags = VK_SHADER_STAGE_COMPUTE_BIT, .size = d->push_bytes};
  VkPipelineLayoutCreateInfo pli = {
      .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
      .setLayoutCount = 1,
      .pSetLayouts = &p->set_layout,
      .pushConstantRangeCount = d->push_bytes ? 1u : 0u,
      .pPushConstantRanges = &pcr,
  };
  vr = vkCreatePipelineLayout(g->device, &pli, NULL, &p->layout);
  if (vr != VK_SUCCESS) {
    p->layout = VK_NULL_HANDLE;
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
              .module = p->module,
              .pName = "main",
              .pSpecializationInfo = d->spec_count ? &spec : NULL,
          },
      .layout = p->layout,
  };
  double t0 = pb_time_now();
  vr = vkCreateComputePipelines(g->device, VK_NULL_HANDLE, 1, &cpi, NULL, &p->pipeline);
  /* -v: what each scene pays for creating its pipelines. lavapipe compiles a
   * kernel at its first dispatch instead (seconds per large kernel with a
   * cold Mesa shader cache: the first pass timings of a run show it). */
  pb_log_verbose("gpu: pipeline %s: %.1f ms", name, (pb_time_now() - t0) * 1e3);
  if (vr != VK_SUCCESS) {
    p->pipeline = VK_NULL_HANDLE;
    snprintf(label, sizeof label, "%s: vkCreateComputePipelines", name);
    r = pb_vk_fail(vr, label);
    goto fail;
  }
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
  p->binding_count = d->binding_count;
  p->accel_bindings = d->accel_bindings;
  p->push_bytes = d->push_bytes;
  pb_gpu_set_name(g, VK_OBJECT_TYPE_SHADER_MODULE, (uint64_t)p->module, name);
  pb_gpu_set_name(g, VK_OBJECT_TYPE_PIPELINE, (uint64_t)p->pipeline, name);
  pb_gpu_set_name(g, VK_OBJECT_TYPE_PIPELINE_LAYOUT, (uint64_t)p->layout, name);
  pb_gpu_set_name(g, VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, (uint64_t)p->set_layout, name);
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
