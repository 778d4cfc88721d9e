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
  /* The submission ring (gpu.h PB_GPU_FRAMES): each submission records into
   * its own command buffer with its own fence and timestamp queries, so the
   * host records submission k + 1 while submission k runs. cmd and queries
   * are the recording (or last submitted) context's. */
  struct pb_gpu_sub {
    VkCommandBuffer cmd;
    VkFence fence;
    VkQueryPool queries;
    uint64_t serial;  /* the submission it holds (0: none yet) */
    int pending;      /* submitted, its fence not yet waited for */
    int held;         /* an asynchronous submission whose timestamps are still to
                         be read (pb_gpu_release): not reused while others are free */
  } subs[PB_GPU_FRAMES];
  uint32_t cur;       /* the context recording, else the last submitted */
  uint32_t read_sub;  /* the context pb_gpu_elapsed_ms reads (pb_gpu_timestamps_of) */
  uint64_t serial;    /* submissions so far */
  VkCommandBuffer cmd;
  VkQueryPool queries;
  uint32_t query_count;
  uint64_t ts_mask;
  int recording;
  pb_gpu_ring_stats ring;
  /* Host writes made while a submission is pending (gpu.h "frames in
   * flight"): recorded at the start of the next command buffer, after the
   * barrier that orders it after every earlier submission. */
  struct pb_gpu_deferred {
    VkBuffer buffer;
    void *mapped;     /* the buffer's mapping, for the host path of pb_gpu_settle */
    uint64_t offset, size;
    void *data;       /* NULL: zeros */
  } *deferred;
  uint32_t deferred_count, deferred_cap;
  int cmd_deferred; /* the recording command buffer holds deferred writes */
  VkPhysicalDeviceMemoryProperties mem;
  pb_gpu_limits limits;
  char name[VK_MAX_PHYSICAL_DEVICE_NAME_SIZE];
  const char *type; /* VkPhysicalDeviceType as a word (pb_gpu_device_type) */
  int validation;
  uint32_t validation_errors;
  char validation_first[512];
  PFN_vkSetDebugUtilsObjectNameEXT set_name;
  uint64_t next_buffer_id;
  uint64_t memory_limit, memory_live, memory_peak; /* bytes; limit 0: none */
  pb_gpu_transfers transfers; /* pb_gpu_buffer_upload / _download totals */
  /* The pipeline cache (pipeline.c): every entry, most recently used first. */
  struct pb_gpu_pipe_entry *pipes;
  pb_gpu_pipeline_stats pipe_stats;
  int can_present;            /* pb_gpu_vk */
  const char *present_reason;
};

/* Destroys every cached pipeline (pb_gpu_destroy, the device idle). */
void pb_gpu_pipe_cache_destroy(pb_gpu *g);

/* Waits for every pending submission (pb_gpu_wait) and makes the deferred
 * host writes; every host access to GPU objects through this API that
 * cannot be deferred calls it first. */
pb_result pb_gpu_settle(pb_gpu *g);
/* 1 when a host write to a buffer now may be recorded for later instead
 * (a submission pending, nothing recording); pb_gpu_defer_write queues it
 * (data copied; NULL: zeros). PB_ERR_NOMEM when it cannot. */
int pb_gpu_can_defer(const pb_gpu *g);
pb_result pb_gpu_defer_write(pb_gpu *g, const pb_gpu_buffer *b, uint64_t offset, const void *data, uint64_t size);
/* Counts a host write made while recording after deferred writes
 * (pb_gpu_ring_stats.late_writes). */
void pb_gpu_note_host_write(pb_gpu *g);

#endif
