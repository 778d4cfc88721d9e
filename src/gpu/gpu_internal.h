/* The GPU context fields, shared by the files of src/gpu only. */
#ifndef PB_GPU_INTERNAL_H
#define PB_GPU_INTERNAL_H

#include "gpu/gpu.h"
#include "shared/pb_gpu.h"

struct pb_gpu {
  VkInstance instance;
  VkDebugUtilsMessengerEXT messenger;
  VkPhysicalDevice phys;
  VkDevice device;
  VkQueue queue;
  uint32_t family;
  VkCommandPool pool;
  VkCommandBuffer cmd;
  VkFence fence;
  VkQueryPool queries;
  uint32_t query_count;
  uint64_t ts_mask;
  int recording;
  int pending;       /* a pb_gpu_submit_async submission not yet waited for */
  VkPhysicalDeviceMemoryProperties mem;
  pb_gpu_limits limits;
  char name[VK_MAX_PHYSICAL_DEVICE_NAME_SIZE];
  int validation;
  uint32_t validation_errors;
  char validation_first[512];
  PFN_vkSetDebugUtilsObjectNameEXT set_name;
  uint64_t memory_limit, memory_live, memory_peak; /* bytes; limit 0: none */
  pb_gpu_transfers transfers; /* pb_gpu_buffer_upload / _download totals */
  int can_present;            /* pb_gpu_vk */
  const char *present_reason;
};

/* Waits for a pending asynchronous submission (pb_gpu_wait); every host
 * access to GPU objects through this API calls it first. */
pb_result pb_gpu_settle(pb_gpu *g);

#endif
