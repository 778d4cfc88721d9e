/* Headless Vulkan compute runtime: instance and device selection, one compute
 * queue, buffers, pipelines from embedded SPIR-V with specialization
 * constants, and timestamp queries. No window system, no ray-tracing
 * extensions (rays are traced by our own BVH in compute shaders).
 *
 * Errors the world can cause (no driver, no device, out of memory, device
 * lost, a limit exceeded) are pb_results with a one-line message saying what
 * to install or do; every VkResult is checked. Validation layers: on when
 * pb_gpu_desc.validation is set or the environment has PB_VK_VALIDATION=1;
 * PB_SYNC_VALIDATION=1 turns them on with synchronization validation too
 * (VK_EXT_validation_features: hazards between submissions, the host's
 * writes and the GPU's reads). Any validation message then makes the next
 * pb_gpu_submit fail with PB_ERR_VULKAN (tests treat them as fatal). */
#ifndef PB_GPU_H
#define PB_GPU_H

#include <stddef.h>
#include <stdint.h>

#include <vulkan/vulkan.h>

#include "core/result.h"
#include "shared/pb_contract.h"

/* What `photonbridge info --devices` lists, one per physical device, in the
 * order --device N counts. */
typedef struct pb_gpu_device_info {
  char name[VK_MAX_PHYSICAL_DEVICE_NAME_SIZE];
  const char *type;            /* "discrete", "integrated", "virtual", "cpu", "other" */
  uint32_t vendor_id, device_id;
  uint32_t api_version;        /* VK_MAKE_API_VERSION */
  char driver[VK_MAX_DRIVER_NAME_SIZE]; /* VkPhysicalDeviceDriverProperties.driverName
                                           ("llvmpipe"), "" if unknown (Vulkan 1.1) */
  char driver_info[VK_MAX_DRIVER_INFO_SIZE]; /* its driverInfo, the driver's version
                                           ("Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)"), "" if unknown */
  uint64_t max_storage_buffer_range; /* bytes */
  uint64_t device_local_bytes;
  uint32_t subgroup_size;      /* 0 if the device cannot say */
  uint32_t subgroup_ops;       /* VkSubgroupFeatureFlags of the compute stage (0: none) */
  uint32_t driver_id;          /* VkDriverId (Vulkan 1.2 drivers), 0 if unknown */
  int timestamps;              /* compute queue has timestamps */
  int acceleration_structure;  /* VK_KHR_acceleration_structure offered */
  int ray_query;               /* the ray-query path can run: VK_KHR_acceleration_structure
                                  and VK_KHR_ray_query with their features accelerationStructure,
                                  rayQuery and bufferDeviceAddress (and their required
                                  extensions); optional, masked by "ray-query" */
  int usable;                  /* has everything the pipeline needs (missing[0] == 0) */
  int preferred;               /* the device that --device auto picks */
  char missing[200];           /* what an unusable device lacks, "" if usable, e.g.
                                  "storage-buffers (8 storage buffers per shader stage, needs 19)" */
} pb_gpu_device_info;

/* What the pipeline needs from a device, each with the name that
 * PB_GPU_MASK_FEATURES uses:
 *   vulkan-1.1       Vulkan 1.1 (subgroup properties, maintenance3)
 *   compute          a queue family with compute
 *   workgroup-64     compute workgroups of PB_GPU_WORKGROUP (64) invocations
 *   storage-buffers  PB_GPU_REQUIRED_STORAGE_BUFFERS storage buffers per stage
 *                    and per set: the most any kernel binds (the gather's 20,
 *                    PB_GATHER_BIND_COUNT of shaders/shared/pb_contract.h)
 * Optional: timestamps (per-pass GPU times; without them the times are null);
 * ray-query (VK_KHR_ray_query on acceleration structures: pb_gpu_device_info
 * .ray_query; the device is then created with those extensions and features,
 * pb_gpu_limits.ray_query, and without them the GLSL BVH serves every ray).
 * Nothing else is required: no subgroup operations, no 64-bit integers or
 * float atomics (shared-memory and 32-bit buffer atomics are core).
 *
 * Test hook: the environment variable PB_GPU_MASK_FEATURES, a comma-separated
 * list of the names above (and "timestamps", "ray-query"), makes device selection treat
 * those features as absent on every device, so that the "device lacks a
 * feature" paths can be tested on any machine. An unknown name is a usage
 * error (PB_ERR_USAGE). */
enum { PB_GPU_REQUIRED_STORAGE_BUFFERS = PB_GATHER_BIND_COUNT };
_Static_assert(PB_BIND_COUNT <= PB_GPU_REQUIRED_STORAGE_BUFFERS && PB_PHOTON_BIND_COUNT <= PB_GPU_REQUIRED_STORAGE_BUFFERS &&
                   PB_RSM_BIND_COUNT <= PB_GPU_REQUIRED_STORAGE_BUFFERS && PB_LBVH_BIND_COUNT <= PB_GPU_REQUIRED_STORAGE_BUFFERS &&
                   PB_SORT_BIND_COUNT <= PB_GPU_REQUIRED_STORAGE_BUFFERS &&
                   PB_RESOLVE_BIND_COUNT <= PB_GPU_REQUIRED_STORAGE_BUFFERS,
               "a kernel binds more storage buffers than devices are required to have");

/* Lists the Vulkan devices. *out is malloc'd (free()). Errors:
 * PB_ERR_NO_DEVICE (no loader, no driver, no device) with the fix in the
 * message. */
pb_result pb_gpu_list_devices(pb_gpu_device_info **out, uint32_t *count);

/* Zero means default for every field. */
typedef struct pb_gpu_desc {
  int device_set;      /* 1: use device `device` (index into the listing) */
  uint32_t device;
  int validation;      /* 1: enable the Khronos validation layer (also
                          PB_VK_VALIDATION=1 in the environment) */
  uint32_t max_timestamps; /* timestamp query slots; 0: 256 */
  uint64_t memory_limit;   /* bytes of buffer memory live at once; 0: the
                              environment's PB_GPU_MEMORY_LIMIT (MiB), else none.
                              A buffer that would pass it fails with
                              PB_ERR_NOMEM naming the buffer, size and cap. */
  /* Presentation (photonbridge view): instance extensions to enable as well
   * (the window system's surface ones), and a test of whether a queue
   * family of a physical device can present to the window. With them the
   * device's queue is one of a family with compute, graphics (the
   * presenter's blit) and presentation, and VK_KHR_swapchain is enabled,
   * when the chosen device has such a family and the extension; otherwise
   * the compute family as without (pb_gpu_vk.present_reason says why). */
  const char *const *instance_extensions;
  uint32_t instance_extension_count;
  /* How rays find surfaces (PB_GPU_TRAVERSAL_*): auto takes ray queries on
   * a GPU that has them (pb_gpu_limits.ray_query) and the BVH on a CPU
   * device (software either way, ray queries no faster there), bvh never
   * creates the device with them, ray_query takes them on any device that
   * has them and fails with PB_ERR_NO_DEVICE on one without. */
  int traversal;
  int (*can_present)(void *user, VkInstance instance, VkPhysicalDevice phys, uint32_t family);
  void *present_user;
} pb_gpu_desc;

typedef struct pb_gpu pb_gpu;

enum { PB_GPU_TRAVERSAL_AUTO = 0, PB_GPU_TRAVERSAL_BVH = 1, PB_GPU_TRAVERSAL_RAY_QUERY = 2 };

/* Device selection: `device` when set; otherwise the first usable discrete
 * GPU, then integrated, virtual, and last a CPU implementation (lavapipe). */
pb_result pb_gpu_create(const pb_gpu_desc *desc, pb_gpu **out);
void pb_gpu_destroy(pb_gpu *g);
/* A device kept for another render (`photonbridge batch`): its per-render
 * readings start again (the buffer-memory peak from what is live now, the
 * validation messages counted for pb_gpu_submit's check); its pipeline
 * cache and totals stay. */
void pb_gpu_restart(pb_gpu *g);

/* The Vulkan objects behind g, for a presenter sharing the render device
 * (view/present.h): one VkDevice, one queue, used from one thread. */
typedef struct pb_gpu_vk {
  VkInstance instance;
  VkPhysicalDevice phys;
  VkDevice device;
  VkQueue queue;
  uint32_t family;
  int can_present;            /* the family presents, has graphics, and
                                 VK_KHR_swapchain is enabled */
  const char *present_reason; /* why not (static text), else NULL */
} pb_gpu_vk;
void pb_gpu_vk_handles(const pb_gpu *g, pb_gpu_vk *out);

/* Properties the renderer checks. */
typedef struct pb_gpu_limits {
  uint64_t max_storage_buffer_range;
  uint64_t max_allocation;
  uint32_t max_workgroup_count_x, max_workgroup_count_y;
  uint32_t subgroup_size;
  uint32_t subgroup_ops;       /* VkSubgroupFeatureFlags usable in compute shaders
                                  (0 when the compute stage has none); kernels that
                                  use them have a portable twin for devices without */
  int cpu;                     /* a CPU implementation (lavapipe, SwiftShader): kernels
                                  may pick variants for its cost model */
  uint32_t driver_id;          /* VkDriverId, 0 if unknown (kernels may work around
                                  a driver's known bugs) */
  int timestamps;
  double timestamp_period_ns;
  int ray_query;               /* the device was created with VK_KHR_acceleration_structure,
                                  VK_KHR_ray_query, bufferDeviceAddress (pb_gpu_device_info
                                  .ray_query) */
} pb_gpu_limits;
const pb_gpu_limits *pb_gpu_get_limits(const pb_gpu *g);
const char *pb_gpu_device_name(const pb_gpu *g);
/* The device's VkPhysicalDeviceType as a word: "discrete", "integrated",
 * "virtual", "cpu" (lavapipe, SwiftShader) or "other". */
const char *pb_gpu_device_type(const pb_gpu *g);
/* How the device's passes find surfaces: "ray-query" (pb_gpu_limits
 * .ray_query) or "bvh" (the shaders' own BVH). */
const char *pb_gpu_traversal(const pb_gpu *g);
VkDevice pb_gpu_vk_device(const pb_gpu *g);
/* Validation messages seen so far (0 without validation). */
uint32_t pb_gpu_validation_errors(const pb_gpu *g);
int pb_gpu_validation_enabled(const pb_gpu *g);
/* Validation messages seen by every context of this process, including those
 * reported while a context was destroyed (object leaks); main() turns a
 * non-zero count into exit PB_ERR_VULKAN. */
uint32_t pb_gpu_validation_total(void);
/* Buffer memory (bytes requested by pb_gpu_buffer_create) live now and at
 * most so far, and the cap (0: none). */
uint64_t pb_gpu_memory_in_use(const pb_gpu *g);
uint64_t pb_gpu_memory_peak(const pb_gpu *g);
uint64_t pb_gpu_memory_limit(const pb_gpu *g);

/* Names a Vulkan object for debuggers and validation messages (no-op
 * without VK_EXT_debug_utils). */
void pb_gpu_set_name(pb_gpu *g, VkObjectType type, uint64_t handle, const char *name);

/* ---- buffers ------------------------------------------------------------ */

typedef struct pb_gpu_buffer {
  VkBuffer buffer;
  VkDeviceMemory memory;
  uint64_t size;
  uint64_t id;        /* unique per context, never reused (pipeline binds compare it) */
  void *mapped;       /* non-NULL when the memory is host-visible and coherent */
  int cached;         /* mapped memory is also HOST_CACHED: the host reads it at
                         memory speed (device-local host-visible memory, as a
                         discrete GPU's resizable BAR, is write-combined: reads
                         from it crawl, so downloads go through a cached
                         staging copy instead) */
} pb_gpu_buffer;

typedef struct pb_gpu_buffer_desc {
  const char *name;   /* object name, and the subject of limit errors */
  uint64_t size;      /* bytes, > 0 */
  int host_visible;   /* 1: must be mappable (readback of large results) */
  int readback;       /* 1: the host reads it: HOST_CACHED memory first */
  int device_address; /* 1: it has a device address and may hold or feed
                         acceleration structures (accel.c); only on a device
                         with pb_gpu_limits.ray_query (PB_ERR_NOT_AVAILABLE) */
} pb_gpu_buffer_desc;

/* A storage buffer (also a transfer source and destination). Sizes over
 * maxStorageBufferRange or the allocation limit fail with PB_ERR_LIMIT naming
 * the buffer and the limit: never truncated. */
pb_result pb_gpu_buffer_create(pb_gpu *g, const pb_gpu_buffer_desc *desc,
                               pb_gpu_buffer *out);
void pb_gpu_buffer_destroy(pb_gpu *g, pb_gpu_buffer *b);
/* Copies host data to/from a buffer (through a staging buffer when the memory
 * is not mappable). Waits for completion. */
pb_result pb_gpu_buffer_upload(pb_gpu *g, pb_gpu_buffer *b, uint64_t offset,
                               const void *data, uint64_t size);
pb_result pb_gpu_buffer_download(pb_gpu *g, const pb_gpu_buffer *b, uint64_t offset,
                                 void *data, uint64_t size);
pb_result pb_gpu_buffer_fill_zero(pb_gpu *g, pb_gpu_buffer *b);
/* Bytes moved by pb_gpu_buffer_upload and pb_gpu_buffer_download since the
 * context was made (mapped copies included: they are host <-> device
 * traffic on a discrete GPU). A frame's share is the difference of two
 * readings (render.h pb_render_stats.upload_bytes, --json "transfers"). */
typedef struct pb_gpu_transfers {
  uint64_t upload_bytes, download_bytes;
  uint64_t readback_bytes;     /* pb_gpu_buffer_read_back's, not in download_bytes */
  uint32_t uploads, downloads; /* calls */
} pb_gpu_transfers;
pb_gpu_transfers pb_gpu_transfers_get(const pb_gpu *g);
/* pb_gpu_buffer_download for the readback module (render/frame/readback.h), the
 * one place a frame's pixels come to the host: counted apart. */
pb_result pb_gpu_buffer_read_back(pb_gpu *g, const pb_gpu_buffer *b, uint64_t offset, void *data, uint64_t size);
/* Counts `size` bytes the readback read through a buffer's cached mapping. */
void pb_gpu_note_read_back(pb_gpu *g, uint64_t size);

/* ---- pipelines ---------------------------------------------------------- */

enum { PB_GPU_MAX_BINDINGS = 24, PB_GPU_MAX_SPEC = 16 };

typedef struct pb_gpu_pipeline_desc {
  const char *name;
  const uint32_t *spirv;     /* embedded SPIR-V words */
  size_t spirv_bytes;
  uint32_t binding_count;    /* storage buffers at bindings 0 .. count-1 of set 0 */
  uint32_t accel_bindings;   /* bit i: binding i is an acceleration structure
                                instead (pb_gpu_pipeline_bind_accel; a device
                                with pb_gpu_limits.ray_query) */
  uint32_t push_bytes;       /* push-constant block size, multiple of 4; 0: none */
  const uint32_t *spec;      /* specialization constants: constant_id i = spec[i] */
  uint32_t spec_count;
} pb_gpu_pipeline_desc;

/* A pipeline: the compiled module and layouts come from the device's own
 * cache (pipeline.c, shared with every pipeline made from the same SPIR-V,
 * bindings, push block and specialization); the descriptor pool and set are
 * its own. */
struct pb_gpu_pipe_entry;
typedef struct pb_gpu_pipeline {
  struct pb_gpu_pipe_entry *entry; /* the device's cached objects below */
  VkShaderModule module;
  VkDescriptorSetLayout set_layout;
  VkPipelineLayout layout;
  VkPipeline pipeline;
  VkDescriptorPool pool;
  VkDescriptorSet set;
  uint32_t binding_count, push_bytes;
  uint32_t accel_bindings;
  uint64_t bound[PB_GPU_MAX_BINDINGS]; /* the buffers' ids the set holds (0: unset) */
} pb_gpu_pipeline;

pb_result pb_gpu_pipeline_create(pb_gpu *g, const pb_gpu_pipeline_desc *desc,
                                 pb_gpu_pipeline *out);
void pb_gpu_pipeline_destroy(pb_gpu *g, pb_gpu_pipeline *p);
/* The device's pipeline cache since it was made: pipelines created (a
 * driver compile: seconds for a large kernel on lavapipe) and taken from
 * the cache (the next frame context of a session after a reload or resize,
 * the next job of `photonbridge batch`), the creations' wall time. */
typedef struct pb_gpu_pipeline_stats {
  uint64_t created, reused, evicted;
  double create_ms;
  uint32_t cached; /* entries held now */
} pb_gpu_pipeline_stats;
pb_gpu_pipeline_stats pb_gpu_pipeline_stats_get(const pb_gpu *g);
/* Points bindings 0 .. count-1 at whole buffers; count == binding_count.
 * The acceleration-structure bindings (accel_bindings) take NULL here and
 * are set by pb_gpu_pipeline_bind_accel. */
pb_result pb_gpu_pipeline_bind(pb_gpu *g, pb_gpu_pipeline *p,
                               const pb_gpu_buffer *const *buffers, uint32_t count);

/* ---- acceleration structures (devices with pb_gpu_limits.ray_query) ------ */

/* Triangles for an acceleration structure: positions float[3 * vertex_count],
 * indices uint[3 * triangle_count], each below vertex_count. */
typedef struct pb_gpu_accel_desc {
  const char *name;
  const float *positions;
  uint32_t vertex_count;
  const uint32_t *indices;
  uint32_t triangle_count;     /* 0: an empty structure (every query misses) */
  int updatable;               /* 1: built to be refitted (VK's update mode;
                                  ALLOW_UPDATE may cost some trace speed) */
} pb_gpu_accel_desc;

/* One bottom-level structure over the triangles (one opaque geometry, so a
 * ray query's primitive index is the triangle's index in desc.indices) and a
 * top-level one holding it once, untransformed, without face culling: what
 * a shader's accelerationStructureEXT binds. */
typedef struct pb_gpu_accel {
  VkAccelerationStructureKHR blas, tlas;
  pb_gpu_buffer blas_buffer, tlas_buffer;
  uint64_t bytes;             /* both structures' storage */
  double build_ms;            /* wall time of the last build's submission */
  uint32_t vertex_count, triangle_count;
  int updatable;
  /* Kept for pb_gpu_accel_update. */
  pb_gpu_buffer vertices, indices, instances, scratch;
  uint64_t scratch_address;   /* aligned for the builds */
} pb_gpu_accel;

/* Builds both on the GPU and waits. PB_ERR_NOT_AVAILABLE without
 * pb_gpu_limits.ray_query, PB_ERR_USAGE for an index out
 * of range. */
pb_result pb_gpu_accel_create(pb_gpu *g, const pb_gpu_accel_desc *desc, pb_gpu_accel *out);
/* New positions (vertex_count of them, the same triangles): built again in
 * place, or with refit on a structure made updatable, refitted (the
 * driver's update: faster, traversal degrades as triangles move far); waits. The handles stay, so pipelines bound to it need no new binding. */
pb_result pb_gpu_accel_update(pb_gpu *g, pb_gpu_accel *a, const float *positions, int refit);
void pb_gpu_accel_destroy(pb_gpu *g, pb_gpu_accel *a);
/* Points acceleration-structure binding `binding` of p at a's top level. */
pb_result pb_gpu_pipeline_bind_accel(pb_gpu *g, pb_gpu_pipeline *p, uint32_t binding, const pb_gpu_accel *a);

/* ---- recording and submission ------------------------------------------ */

/* The submission ring: PB_GPU_FRAMES contexts of {command buffer, fence,
 * timestamp query pool}. pb_gpu_begin takes the next free context and waits
 * only for that context's own earlier submission (when every context is
 * pending), so the host records submission k + 1 while the GPU runs k.
 * Queue order is kept: every command buffer starts with a full execution and
 * memory dependency on all earlier submissions to the queue (a pipeline
 * barrier's first scope includes them), so a submission never overlaps the
 * one before it on the GPU, only the host's work. Three: a frame in flight,
 * the next frame's, and the one recording (render/frame/frame.c). */
enum { PB_GPU_FRAMES = 3 };

/* Begin, record dispatches, barriers and timestamps, then submit (and wait,
 * or not: pb_gpu_submit_async). */
pb_result pb_gpu_begin(pb_gpu *g);
/* Dispatches `invocations` 1-D work items in workgroups of PB_GPU_WORKGROUP,
 * folded into a 2-D grid when the count exceeds the x limit; kernels compute
 * gid = x + y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP and skip gid >= count. */
pb_result pb_gpu_dispatch(pb_gpu *g, const pb_gpu_pipeline *p, const void *push,
                          uint64_t invocations);
/* Dispatches the workgroup counts (VkDispatchIndirectCommand: x, y, z) that an
 * earlier pass wrote at byte `offset` of `args`, so that a pass is sized on the
 * GPU without the host reading anything back. Whoever writes the counts folds
 * them into x <= maxComputeWorkGroupCount[0] and y, as pb_gpu_dispatch does;
 * a barrier (pb_gpu_barrier) must separate the write from this call. */
pb_result pb_gpu_dispatch_indirect(pb_gpu *g, const pb_gpu_pipeline *p, const void *push,
                                   const pb_gpu_buffer *args, uint64_t offset);
/* Compute-to-compute (and transfer, and compute-to-indirect-arguments) memory barrier. */
void pb_gpu_barrier(pb_gpu *g);
/* Writes timestamp slot `slot` after all previous work (ignored when the queue
 * has none). */
void pb_gpu_timestamp(pb_gpu *g, uint32_t slot);
/* Ends, submits, waits. PB_ERR_DEVICE_LOST / PB_ERR_VULKAN with a message;
 * PB_ERR_VULKAN too when validation reported anything. */
pb_result pb_gpu_submit(pb_gpu *g);
/* Ends and submits without waiting (frames in flight: a frame's last
 * submission runs while the host goes on with the next). Until pb_gpu_wait,
 * nothing may touch what that submission reads or writes but through this
 * API, which keeps the GPU's order:
 *   - pb_gpu_begin records the next submission into another context; the
 *     queue runs it after this one (see PB_GPU_FRAMES).
 *   - pb_gpu_buffer_fill_zero, and pb_gpu_buffer_upload of at most 64 KiB
 *     (offset and size multiples of 4), made while nothing records, are
 *     deferred: recorded at the start of the next command buffer
 *     (vkCmdFillBuffer, vkCmdUpdateBuffer), after the pending submission on
 *     the GPU, never over memory it still reads. A host read of the buffer
 *     through this API first makes them (pb_gpu_settle).
 *   - pb_gpu_pipeline_bind of the buffers a pipeline's set already holds
 *     changes nothing and does not wait; other binds wait.
 *   - everything else (downloads, larger uploads, uploads while recording,
 *     destruction) waits for every pending submission first.
 * Reads of a buffer's `mapped` pointer do not wait: only for buffers the
 * pending submission does not write (render/frame/readback.h's ring).
 * The submission's timestamps stay readable (pb_gpu_timestamps_of) until
 * pb_gpu_release: its context is reused only when no other is free. */
pb_result pb_gpu_submit_async(pb_gpu *g);
/* Waits for every pending submission; their errors (device lost,
 * validation messages) as pb_gpu_submit's. */
pb_result pb_gpu_wait(pb_gpu *g);
/* 1 while an asynchronous submission has not been waited for. */
int pb_gpu_pending(const pb_gpu *g);
/* The last submission's number (1, 2, ...; 0 before any). */
uint64_t pb_gpu_last_submission(const pb_gpu *g);
/* 1 while the host has not waited for submission `sub` (it may still run). */
int pb_gpu_outstanding(const pb_gpu *g, uint64_t sub);
/* 1 while submission `sub` still runs on the GPU (its fence unsignalled;
 * does not wait). */
int pb_gpu_busy(pb_gpu *g, uint64_t sub);
/* pb_gpu_elapsed_ms reads submission `sub`'s timestamps from now on (0: the
 * last submission's, as after every submit). Returns 0, and makes
 * pb_gpu_elapsed_ms negative, when that submission's context was reused. */
int pb_gpu_timestamps_of(pb_gpu *g, uint64_t sub);
/* The asynchronous submission `sub`'s timestamps are read: its context may
 * be reused. */
void pb_gpu_release(pb_gpu *g, uint64_t sub);
/* What the ring did since the context was made. */
typedef struct pb_gpu_ring_stats {
  uint64_t submissions, async_submissions;
  uint64_t begin_waits;   /* pb_gpu_begin found its context pending and waited for it */
  uint64_t held_stolen;   /* a held context reused before pb_gpu_release (timestamps lost) */
  uint64_t deferred_writes, deferred_bytes; /* host writes recorded instead of waiting */
  uint64_t bind_skips;    /* pipeline binds that changed nothing */
  uint64_t late_writes;   /* host writes while recording a command buffer that
                             holds deferred writes: made on the host now, before
                             those (an older value may land last; 0 expected) */
} pb_gpu_ring_stats;
pb_gpu_ring_stats pb_gpu_ring_stats_get(const pb_gpu *g);
/* Copies `size` bytes between buffers in the recording command buffer
 * (transfer; a pb_gpu_barrier orders it with the passes around it). */
void pb_gpu_copy(pb_gpu *g, const pb_gpu_buffer *src, uint64_t src_offset, const pb_gpu_buffer *dst,
                 uint64_t dst_offset, uint64_t size);
/* Milliseconds between two timestamp slots of the last submission (or of
 * pb_gpu_timestamps_of's), waiting for it; negative when timestamps are
 * unavailable. */
double pb_gpu_elapsed_ms(pb_gpu *g, uint32_t from_slot, uint32_t to_slot);

/* Turns a VkResult into a pb_result with "what: VK_ERROR_..." (device lost
 * and out-of-memory get their own codes and advice). */
pb_result pb_vk_fail(VkResult vr, const char *what);
const char *pb_vk_result_name(VkResult vr);

#endif
