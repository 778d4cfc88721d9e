/* Vulkan instance, device selection, the compute queue, command recording,
 * submission and timestamps (see gpu.h). */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "gpu/gpu_internal.h"

const char *pb_vk_result_name(VkResult vr) {
  switch (vr) {
#define C(x) case x: return #x;
    C(VK_SUCCESS) C(VK_NOT_READY) C(VK_TIMEOUT) C(VK_INCOMPLETE)
    C(VK_ERROR_OUT_OF_HOST_MEMORY) C(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    C(VK_ERROR_INITIALIZATION_FAILED) C(VK_ERROR_DEVICE_LOST)
    C(VK_ERROR_MEMORY_MAP_FAILED) C(VK_ERROR_LAYER_NOT_PRESENT)
    C(VK_ERROR_EXTENSION_NOT_PRESENT) C(VK_ERROR_FEATURE_NOT_PRESENT)
    C(VK_ERROR_INCOMPATIBLE_DRIVER) C(VK_ERROR_TOO_MANY_OBJECTS)
    C(VK_ERROR_FORMAT_NOT_SUPPORTED) C(VK_ERROR_FRAGMENTED_POOL)
    C(VK_ERROR_OUT_OF_POOL_MEMORY) C(VK_ERROR_INVALID_SHADER_NV)
    C(VK_ERROR_UNKNOWN)
#undef C
  default: return "VK_ERROR_(unknown)";
  }
}

pb_result pb_vk_fail(VkResult vr, const char *what) {
  if (vr == VK_ERROR_DEVICE_LOST)
    return pb_fail(PB_ERR_DEVICE_LOST,
                   "%s: the Vulkan device was lost (driver reset or GPU hang); "
                   "no output was written; rerun, or pick another device with --device",
                   what);
  if (vr == VK_ERROR_OUT_OF_DEVICE_MEMORY || vr == VK_ERROR_OUT_OF_HOST_MEMORY)
    return pb_fail(PB_ERR_NOMEM, "%s: %s (render a smaller image or scene)", what,
                   pb_vk_result_name(vr));
  return pb_fail(PB_ERR_VULKAN, "%s: %s", what, pb_vk_result_name(vr));
}

/* ---- instance ------------------------------------------------------------ */

static uint32_t validation_total;
uint32_t pb_gpu_validation_total(void) { return __atomic_load_n(&validation_total, __ATOMIC_RELAXED); }

static VKAPI_ATTR VkBool32 VKAPI_CALL on_debug(VkDebugUtilsMessageSeverityFlagBitsEXT sev,
                                               VkDebugUtilsMessageTypeFlagsEXT type,
                                               const VkDebugUtilsMessengerCallbackDataEXT *data,
                                               void *user) {
  (void)type;
  pb_gpu *g = user;
  if (sev < VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) return VK_FALSE;
  const char *msg = data && data->pMessage ? data->pMessage : "(no message)";
  __atomic_fetch_add(&validation_total, 1u, __ATOMIC_RELAXED);
  if (!g) {
    fprintf(stderr, "photonbridge: Vulkan validation: %s\n", msg);
    return VK_FALSE;
  }
  g->validation_errors++;
  if (!g->validation_first[0])
    snprintf(g->validation_first, sizeof g->validation_first, "%s", msg);
  fprintf(stderr, "photonbridge: Vulkan validation: %s\n", msg);
  return VK_FALSE;
}

static int env_flag(const char *name) {
  const char *v = getenv(name);
  return v && v[0] && strcmp(v, "0") != 0;
}

/* PB_VK_VALIDATION=1, or PB_SYNC_VALIDATION=1 (which implies it). */
static int env_validation(void) { return env_flag("PB_VK_VALIDATION") || env_flag("PB_SYNC_VALIDATION"); }

static int has_layer(const char *name) {
  uint32_t n = 0;
  if (vkEnumerateInstanceLayerProperties(&n, NULL) != VK_SUCCESS || !n) return 0;
  VkLayerProperties *p = calloc(n, sizeof *p);
  if (!p) return 0;
  int found = 0;
  if (vkEnumerateInstanceLayerProperties(&n, p) == VK_SUCCESS)
    for (uint32_t i = 0; i < n; ++i)
      if (strcmp(p[i].layerName, name) == 0) found = 1;
  free(p);
  return found;
}

static const char *const no_driver_advice =
    "install a Vulkan driver (a GPU vendor driver, or the CPU fallback: "
    "apt install mesa-vulkan-drivers) and the loader (libvulkan1)";

/* Creates an instance; with validation, the layer and a messenger whose
 * callback counts messages into g (g may be NULL when listing). */
static pb_result create_instance(int validation, pb_gpu *g, const char *const *extra, uint32_t extra_count,
                                 VkInstance *out, VkDebugUtilsMessengerEXT *messenger) {
  *out = VK_NULL_HANDLE;
  if (messenger) *messenger = VK_NULL_HANDLE;
  uint32_t version = 0;
  if (vkEnumerateInstanceVersion(&version) != VK_SUCCESS || version < VK_API_VERSION_1_1)
    return pb_fail(PB_ERR_NO_DEVICE, "Vulkan 1.1 loader not found: %s", no_driver_advice);
  const char *layers[1] = {"VK_LAYER_KHRONOS_validation"};
  const char *exts[18] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME};
  int sync = validation && env_flag("PB_SYNC_VALIDATION");
  uint32_t ext_count = validation ? (sync ? 2u : 1u) : 0u;
  if (extra_count > 16) return pb_fail(PB_ERR_USAGE, "gpu: %u instance extensions (at most 16)", extra_count);
  for (uint32_t i = 0; i < extra_count; ++i) exts[ext_count++] = extra[i];
  if (validation && !has_layer(layers[0]))
    return pb_fail(PB_ERR_NOT_AVAILABLE,
                   "validation requested (PB_VK_VALIDATION) but VK_LAYER_KHRONOS_validation "
                   "is not installed: apt install vulkan-validationlayers");
  VkApplicationInfo app = {
      .sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
      .pApplicationName = "photonbridge",
      .apiVersion = VK_API_VERSION_1_1,
  };
  VkDebugUtilsMessengerCreateInfoEXT dbg = {
      .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
      .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
      .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
      .pfnUserCallback = on_debug,
      .pUserData = g,
  };
  int use_dbg = validation && g;
  /* PB_SYNC_VALIDATION=1: the layer's synchronization validation as well
   * (hazards between submissions in flight and the host's writes). */
  VkValidationFeatureEnableEXT sync_enable = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
  VkValidationFeaturesEXT vf = {
      .sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT,
      .pNext = use_dbg ? &dbg : NULL,
      .enabledValidationFeatureCount = 1,
      .pEnabledValidationFeatures = &sync_enable,
  };
  VkInstanceCreateInfo ci = {
      .sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
      .pNext = sync ? (void *)&vf : use_dbg ? (void *)&dbg : NULL,
      .pApplicationInfo = &app,
      .enabledLayerCount = validation ? 1u : 0u,
      .ppEnabledLayerNames = layers,
      .enabledExtensionCount = ext_count,
      .ppEnabledExtensionNames = exts,
  };
  VkResult vr = vkCreateInstance(&ci, NULL, out);
  if (vr == VK_ERROR_INCOMPATIBLE_DRIVER || vr == VK_ERROR_INITIALIZATION_FAILED)
    return pb_fail(PB_ERR_NO_DEVICE, "no Vulkan driver (%s): %s", pb_vk_result_name(vr),
                   no_driver_advice);
  if (vr != VK_SUCCESS) return pb_vk_fail(vr, "vkCreateInstance");
  if (use_dbg && messenger) {
    PFN_vkCreateDebugUtilsMessengerEXT create =
        (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(*out, "vkCreateDebugUtilsMessengerEXT");
    if (!create) {
      vkDestroyInstance(*out, NULL);
      *out = VK_NULL_HANDLE;
      return pb_fail(PB_ERR_NOT_AVAILABLE, "VK_EXT_debug_utils is missing from the validation layer");
    }
    vr = create(*out, &dbg, NULL, messenger);
    if (vr != VK_SUCCESS) {
      vkDestroyInstance(*out, NULL);
      *out = VK_NULL_HANDLE;
      return pb_vk_fail(vr, "vkCreateDebugUtilsMessengerEXT");
    }
  }
  return PB_OK;
}

static const char *type_name(VkPhysicalDeviceType t) {
  switch (t) {
  case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
  case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
  case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
  case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
  default: return "other";
  }
}

/* Lower is better: discrete, integrated, virtual, other, cpu (lavapipe). */
static int type_rank(VkPhysicalDeviceType t) {
  switch (t) {
  case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
  case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
  case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
  case VK_PHYSICAL_DEVICE_TYPE_CPU: return 4;
  default: return 3;
  }
}

/* The compute queue family (prefer a compute-only one), or UINT32_MAX. */
static uint32_t compute_family(VkPhysicalDevice pd, uint32_t *ts_bits) {
  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, NULL);
  VkQueueFamilyProperties q[32];
  if (n > 32) n = 32;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, q);
  uint32_t best = UINT32_MAX;
  for (uint32_t i = 0; i < n; ++i) {
    if (!(q[i].queueFlags & VK_QUEUE_COMPUTE_BIT) || q[i].queueCount == 0) continue;
    if (best == UINT32_MAX || !(q[i].queueFlags & VK_QUEUE_GRAPHICS_BIT)) best = i;
  }
  if (ts_bits) *ts_bits = best == UINT32_MAX ? 0 : q[best].timestampValidBits;
  return best;
}

/* ---- requirements and the PB_GPU_MASK_FEATURES test hook ------------------ */

enum {
  PB_FEAT_VULKAN11 = 1u << 0,
  PB_FEAT_COMPUTE = 1u << 1,
  PB_FEAT_WORKGROUP = 1u << 2,
  PB_FEAT_STORAGE_BUFFERS = 1u << 3,
  PB_FEAT_TIMESTAMPS = 1u << 4,
  PB_FEAT_RAY_QUERY = 1u << 5,
};
static const struct {
  const char *name;
  unsigned bit;
} feature_names[] = {
    {"vulkan-1.1", PB_FEAT_VULKAN11},   {"compute", PB_FEAT_COMPUTE},
    {"workgroup-64", PB_FEAT_WORKGROUP}, {"storage-buffers", PB_FEAT_STORAGE_BUFFERS},
    {"timestamps", PB_FEAT_TIMESTAMPS}, {"ray-query", PB_FEAT_RAY_QUERY},
};

/* The features PB_GPU_MASK_FEATURES hides; PB_ERR_USAGE for an unknown name. */
static pb_result masked_features(unsigned *mask) {
  *mask = 0;
  const char *v = getenv("PB_GPU_MASK_FEATURES");
  if (!v) return PB_OK;
  const char *p = v;
  while (*p) {
    size_t len = strcspn(p, ", ");
    if (len) {
      unsigned bit = 0;
      for (size_t i = 0; i < sizeof feature_names / sizeof *feature_names; ++i)
        if (strlen(feature_names[i].name) == len && strncmp(feature_names[i].name, p, len) == 0)
          bit = feature_names[i].bit;
      if (!bit)
        return pb_fail(PB_ERR_USAGE,
                       "PB_GPU_MASK_FEATURES: unknown feature '%.*s' (known: vulkan-1.1, compute, "
                       "workgroup-64, storage-buffers, timestamps, ray-query)",
                       (int)len, p);
      *mask |= bit;
    }
    p += len;
    while (*p == ',' || *p == ' ') ++p;
  }
  return PB_OK;
}

static void add_missing(pb_gpu_device_info *d, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void add_missing(pb_gpu_device_info *d, const char *fmt, ...) {
  size_t k = strlen(d->missing);
  if (k + 3 >= sizeof d->missing) return;
  if (k) {
    memcpy(d->missing + k, ", ", 3);
    k += 2;
  }
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(d->missing + k, sizeof d->missing - k, fmt, ap);
  va_end(ap);
}

/* The device extensions the ray-query path enables: the two it uses and
 * those they require on a Vulkan 1.1 instance (the instance asks for 1.1, so
 * the promoted ones are enabled as extensions even on a 1.2+ driver). */
static const char *const ray_query_exts[] = {
    VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME, VK_KHR_RAY_QUERY_EXTENSION_NAME,
    VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME, VK_KHR_BUFFER_DEVICE_ADDRESS_EXTENSION_NAME,
    VK_EXT_DESCRIPTOR_INDEXING_EXTENSION_NAME, VK_KHR_SPIRV_1_4_EXTENSION_NAME,
    VK_KHR_SHADER_FLOAT_CONTROLS_EXTENSION_NAME,
};
enum { RAY_QUERY_EXT_COUNT = sizeof ray_query_exts / sizeof *ray_query_exts };

/* Sets ext[i] to whether the device offers names[i]. */
static void device_exts(VkPhysicalDevice pd, const char *const *names, uint32_t count, int *has) {
  for (uint32_t i = 0; i < count; ++i) has[i] = 0;
  uint32_t ne = 0;
  VkExtensionProperties *ep = NULL;
  if (vkEnumerateDeviceExtensionProperties(pd, NULL, &ne, NULL) == VK_SUCCESS && ne &&
      (ep = calloc(ne, sizeof *ep)) && vkEnumerateDeviceExtensionProperties(pd, NULL, &ne, ep) == VK_SUCCESS)
    for (uint32_t e = 0; e < ne; ++e)
      for (uint32_t i = 0; i < count; ++i)
        if (strcmp(ep[e].extensionName, names[i]) == 0) has[i] = 1;
  free(ep);
}

/* Whether the ray-query path can run on pd (gpu.h pb_gpu_device_info
 * .ray_query); *accel: VK_KHR_acceleration_structure alone. */
static int ray_query_support(VkPhysicalDevice pd, uint32_t api_version, int *accel) {
  int has[RAY_QUERY_EXT_COUNT];
  device_exts(pd, ray_query_exts, RAY_QUERY_EXT_COUNT, has);
  *accel = has[0];
  for (uint32_t i = 0; i < RAY_QUERY_EXT_COUNT; ++i)
    if (!has[i]) return 0;
  if (api_version < VK_API_VERSION_1_1) return 0;
  VkPhysicalDeviceRayQueryFeaturesKHR rq = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR as = {
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR, .pNext = &rq};
  VkPhysicalDeviceBufferDeviceAddressFeatures bda = {
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES, .pNext = &as};
  VkPhysicalDeviceFeatures2 f2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, .pNext = &bda};
  vkGetPhysicalDeviceFeatures2(pd, &f2);
  return bda.bufferDeviceAddress && as.accelerationStructure && rq.rayQuery;
}

static void describe(VkPhysicalDevice pd, pb_gpu_device_info *d, unsigned mask) {
  memset(d, 0, sizeof *d);
  VkPhysicalDeviceSubgroupProperties sg = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceDriverProperties drv = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES,
                                          .pNext = &sg};
  VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  VkPhysicalDeviceProperties p;
  vkGetPhysicalDeviceProperties(pd, &p);
  int v12 = p.apiVersion >= VK_API_VERSION_1_2;
  p2.pNext = v12 ? (void *)&drv : (void *)&sg;
  if (p.apiVersion >= VK_API_VERSION_1_1) vkGetPhysicalDeviceProperties2(pd, &p2);
  snprintf(d->name, sizeof d->name, "%s", p.deviceName);
  d->type = type_name(p.deviceType);
  d->vendor_id = p.vendorID;
  d->device_id = p.deviceID;
  d->api_version = p.apiVersion;
  if (v12) {
    d->driver_id = (uint32_t)drv.driverID;
    size_t k = strnlen(drv.driverName, sizeof drv.driverName);
    memcpy(d->driver, drv.driverName, k < sizeof d->driver ? k : sizeof d->driver - 1);
    d->driver[k < sizeof d->driver ? k : sizeof d->driver - 1] = 0;
    k = strnlen(drv.driverInfo, sizeof drv.driverInfo);
    memcpy(d->driver_info, drv.driverInfo, k < sizeof d->driver_info ? k : sizeof d->driver_info - 1);
    d->driver_info[k < sizeof d->driver_info ? k : sizeof d->driver_info - 1] = 0;
  }
  d->ray_query = ray_query_support(pd, p.apiVersion, &d->acceleration_structure) && !(mask & PB_FEAT_RAY_QUERY);
  if (mask & PB_FEAT_RAY_QUERY) d->acceleration_structure = 0;
  d->max_storage_buffer_range = p.limits.maxStorageBufferRange;
  d->subgroup_size = p.apiVersion >= VK_API_VERSION_1_1 ? sg.subgroupSize : 0;
  d->subgroup_ops = p.apiVersion >= VK_API_VERSION_1_1 && (sg.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT)
                        ? sg.supportedOperations
                        : 0;
  VkPhysicalDeviceMemoryProperties mp;
  vkGetPhysicalDeviceMemoryProperties(pd, &mp);
  for (uint32_t i = 0; i < mp.memoryHeapCount; ++i)
    if (mp.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      d->device_local_bytes += mp.memoryHeaps[i].size;
  uint32_t ts = 0;
  uint32_t fam = compute_family(pd, &ts);
  d->timestamps = ts > 0 && p.limits.timestampPeriod > 0 && !(mask & PB_FEAT_TIMESTAMPS);
  /* What the pipeline needs (gpu.h); a masked feature counts as absent. */
  static const char masked[] = " (masked by PB_GPU_MASK_FEATURES)";
  if (mask & PB_FEAT_VULKAN11)
    add_missing(d, "vulkan-1.1%s", masked);
  else if (p.apiVersion < VK_API_VERSION_1_1)
    add_missing(d, "vulkan-1.1 (the driver offers Vulkan %u.%u)", VK_API_VERSION_MAJOR(p.apiVersion),
                VK_API_VERSION_MINOR(p.apiVersion));
  if (mask & PB_FEAT_COMPUTE)
    add_missing(d, "compute%s", masked);
  else if (fam == UINT32_MAX)
    add_missing(d, "compute (no queue family with compute)");
  uint32_t wg = p.limits.maxComputeWorkGroupSize[0] < p.limits.maxComputeWorkGroupInvocations
                    ? p.limits.maxComputeWorkGroupSize[0]
                    : p.limits.maxComputeWorkGroupInvocations;
  if (mask & PB_FEAT_WORKGROUP)
    add_missing(d, "workgroup-64%s", masked);
  else if (wg < PB_GPU_WORKGROUP)
    add_missing(d, "workgroup-64 (workgroups of at most %u invocations, needs %u)", wg,
                (unsigned)PB_GPU_WORKGROUP);
  uint32_t sb = p.limits.maxPerStageDescriptorStorageBuffers < p.limits.maxDescriptorSetStorageBuffers
                    ? p.limits.maxPerStageDescriptorStorageBuffers
                    : p.limits.maxDescriptorSetStorageBuffers;
  if (mask & PB_FEAT_STORAGE_BUFFERS)
    add_missing(d, "storage-buffers%s", masked);
  else if (sb < PB_GPU_REQUIRED_STORAGE_BUFFERS)
    add_missing(d, "storage-buffers (%u storage buffers per shader stage, needs %u)", sb,
                (unsigned)PB_GPU_REQUIRED_STORAGE_BUFFERS);
  d->usable = d->missing[0] == 0;
}

static pb_result enumerate(VkInstance inst, VkPhysicalDevice **out, uint32_t *count) {
  *out = NULL;
  *count = 0;
  uint32_t n = 0;
  VkResult vr = vkEnumeratePhysicalDevices(inst, &n, NULL);
  if (vr != VK_SUCCESS) return pb_vk_fail(vr, "vkEnumeratePhysicalDevices");
  if (n == 0)
    return pb_fail(PB_ERR_NO_DEVICE, "no Vulkan device found: %s", no_driver_advice);
  VkPhysicalDevice *pd = calloc(n, sizeof *pd);
  if (!pd) return pb_fail(PB_ERR_NOMEM, "out of memory listing Vulkan devices");
  vr = vkEnumeratePhysicalDevices(inst, &n, pd);
  if (vr != VK_SUCCESS && vr != VK_INCOMPLETE) {
    free(pd);
    return pb_vk_fail(vr, "vkEnumeratePhysicalDevices");
  }
  *out = pd;
  *count = n;
  return PB_OK;
}

/* Index of the preferred usable device, or UINT32_MAX. */
static uint32_t pick(const pb_gpu_device_info *d, const VkPhysicalDevice *pd, uint32_t n) {
  uint32_t best = UINT32_MAX;
  int best_rank = 99;
  for (uint32_t i = 0; i < n; ++i) {
    if (!d[i].usable) continue;
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(pd[i], &p);
    int r = type_rank(p.deviceType);
    if (r < best_rank) {
      best_rank = r;
      best = i;
    }
  }
  return best;
}

pb_result pb_gpu_list_devices(pb_gpu_device_info **out, uint32_t *count) {
  *out = NULL;
  *count = 0;
  VkInstance inst;
  unsigned mask;
  pb_result r = masked_features(&mask);
  if (r != PB_OK) return r;
  r = create_instance(0, NULL, NULL, 0, &inst, NULL);
  if (r != PB_OK) return r;
  VkPhysicalDevice *pd = NULL;
  uint32_t n = 0;
  r = enumerate(inst, &pd, &n);
  if (r != PB_OK) goto done;
  pb_gpu_device_info *d = calloc(n, sizeof *d);
  if (!d) {
    r = pb_fail(PB_ERR_NOMEM, "out of memory listing Vulkan devices");
    goto done;
  }
  for (uint32_t i = 0; i < n; ++i) describe(pd[i], &d[i], mask);
  uint32_t best = pick(d, pd, n);
  if (best != UINT32_MAX) d[best].preferred = 1;
  *out = d;
  *count = n;
done:
  free(pd);
  vkDestroyInstance(inst, NULL);
  return r;
}

/* ---- context ------------------------------------------------------------- */

void pb_gpu_set_name(pb_gpu *g, VkObjectType type, uint64_t handle, const char *name) {
  if (!g || !g->set_name || !handle || !name) return;
  VkDebugUtilsObjectNameInfoEXT ni = {
      .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT,
      .objectType = type,
      .objectHandle = handle,
      .pObjectName = name,
  };
  g->set_name(g->device, &ni);
}

void pb_gpu_destroy(pb_gpu *g) {
  if (!g) return;
  if (g->device) {
    vkDeviceWaitIdle(g->device);
    for (uint32_t i = 0; i < PB_GPU_FRAMES; ++i) {
      if (g->subs[i].queries) vkDestroyQueryPool(g->device, g->subs[i].queries, NULL);
      if (g->subs[i].fence) vkDestroyFence(g->device, g->subs[i].fence, NULL);
    }
    if (g->pool) vkDestroyCommandPool(g->device, g->pool, NULL);
    pb_gpu_pipe_cache_destroy(g);
    vkDestroyDevice(g->device, NULL);
  }
  if (g->messenger) {
    PFN_vkDestroyDebugUtilsMessengerEXT destroy =
        (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(g->instance, "vkDestroyDebugUtilsMessengerEXT");
    if (destroy) destroy(g->instance, g->messenger, NULL);
  }
  if (g->instance) vkDestroyInstance(g->instance, NULL);
  for (uint32_t i = 0; i < g->deferred_count; ++i) free(g->deferred[i].data);
  free(g->deferred);
  free(g);
}

/* The buffer-memory cap: the desc's, else PB_GPU_MEMORY_LIMIT in MiB. */
static pb_result memory_limit_from(const pb_gpu_desc *d, uint64_t *limit) {
  *limit = d->memory_limit;
  const char *v = getenv("PB_GPU_MEMORY_LIMIT");
  if (*limit || !v || !v[0]) return PB_OK;
  char *end = NULL;
  double mib = strtod(v, &end);
  if (end == v || *end || !(mib > 0) || !(mib < 1e12))
    return pb_fail(PB_ERR_USAGE, "PB_GPU_MEMORY_LIMIT: '%s' is not a positive number of MiB", v);
  *limit = (uint64_t)(mib * 1048576.0);
  if (*limit == 0) *limit = 1;
  return PB_OK;
}

pb_result pb_gpu_create(const pb_gpu_desc *desc_in, pb_gpu **out) {
  *out = NULL;
  pb_gpu_desc desc = {0};
  if (desc_in) desc = *desc_in;
  if (desc.max_timestamps == 0) desc.max_timestamps = 256;
  if (desc.max_timestamps > 4096)
    return pb_fail(PB_ERR_USAGE, "gpu: %u timestamp slots requested (at most 4096)", desc.max_timestamps);

  pb_gpu *g = calloc(1, sizeof *g);
  if (!g) return pb_fail(PB_ERR_NOMEM, "out of memory for the GPU context");
  VkPhysicalDevice *pd = NULL;
  pb_gpu_device_info *info = NULL;
  uint32_t n = 0;
  g->validation = desc.validation || env_validation();
  unsigned mask;
  pb_result r = masked_features(&mask);
  if (r != PB_OK) goto fail;
  r = memory_limit_from(&desc, &g->memory_limit);
  if (r != PB_OK) goto fail;
  r = create_instance(g->validation, g, desc.instance_extensions, desc.instance_extension_count, &g->instance,
                      &g->messenger);
  if (r != PB_OK) goto fail;
  r = enumerate(g->instance, &pd, &n);
  if (r != PB_OK) goto fail;
  info = calloc(n, sizeof *info);
  if (!info) {
    r = pb_fail(PB_ERR_NOMEM, "out of memory listing Vulkan devices");
    goto fail;
  }
  for (uint32_t i = 0; i < n; ++i) describe(pd[i], &info[i], mask);
  uint32_t idx;
  if (desc.device_set) {
    if (desc.device >= n) {
      r = pb_fail(PB_ERR_NO_DEVICE, "--device %u: only %u Vulkan device%s (see 'photonbridge info --devices')",
                  desc.device, n, n == 1 ? "" : "s");
      goto fail;
    }
    idx = desc.device;
    if (!info[idx].usable) {
      r = pb_fail(PB_ERR_NO_DEVICE, "--device %u (%s) lacks %s; pick another with --device "
                  "(see 'photonbridge info --devices')", idx, info[idx].name, info[idx].missing);
      goto fail;
    }
  } else {
    idx = pick(info, pd, n);
    if (idx == UINT32_MAX) {
      /* Name the first device and what it lacks; the others are in info --devices. */
      r = pb_fail(PB_ERR_NO_DEVICE,
                  "no usable Vulkan device: %s lacks %s%s; use a GPU with a Vulkan 1.1 driver, or the CPU "
                  "fallback (apt install mesa-vulkan-drivers)", info[0].name, info[0].missing,
                  n > 1 ? " (and the others too, see 'photonbridge info --devices')" : "");
      goto fail;
    }
  }
  g->phys = pd[idx];
  snprintf(g->name, sizeof g->name, "%s", info[idx].name);
  VkPhysicalDeviceProperties p;
  vkGetPhysicalDeviceProperties(g->phys, &p);
  g->type = type_name(p.deviceType);
  vkGetPhysicalDeviceMemoryProperties(g->phys, &g->mem);
  VkPhysicalDeviceMaintenance3Properties m3 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
  VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &m3};
  vkGetPhysicalDeviceProperties2(g->phys, &p2);
  uint32_t ts_bits = 0;
  g->family = compute_family(g->phys, &ts_bits);
  int swapchain = 0;
  if (desc.can_present) { /* a family that computes, blits and presents, and the extension */
    uint32_t ne = 0;
    VkExtensionProperties *ep = NULL;
    if (vkEnumerateDeviceExtensionProperties(g->phys, NULL, &ne, NULL) == VK_SUCCESS && ne &&
        (ep = calloc(ne, sizeof *ep)) && vkEnumerateDeviceExtensionProperties(g->phys, NULL, &ne, ep) == VK_SUCCESS)
      for (uint32_t i = 0; i < ne; ++i)
        if (strcmp(ep[i].extensionName, VK_KHR_SWAPCHAIN_EXTENSION_NAME) == 0) swapchain = 1;
    free(ep);
    uint32_t nq = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(g->phys, &nq, NULL);
    VkQueueFamilyProperties q[32];
    if (nq > 32) nq = 32;
    vkGetPhysicalDeviceQueueFamilyProperties(g->phys, &nq, q);
    uint32_t fam = UINT32_MAX;
    for (uint32_t i = 0; i < nq && fam == UINT32_MAX; ++i) {
      VkQueueFlags need = VK_QUEUE_COMPUTE_BIT | VK_QUEUE_GRAPHICS_BIT;
      if ((q[i].queueFlags & need) == need && q[i].queueCount &&
          desc.can_present(desc.present_user, g->instance, g->phys, i))
        fam = i;
    }
    if (!swapchain) {
      g->present_reason = "the render device has no VK_KHR_swapchain";
    } else if (fam == UINT32_MAX) {
      g->present_reason = "no queue family of the render device computes, blits and presents to this window";
      swapchain = 0;
    } else {
      g->family = fam;
      ts_bits = q[fam].timestampValidBits;
      g->can_present = 1;
    }
  }
  g->limits.max_storage_buffer_range = p.limits.maxStorageBufferRange;
  g->limits.max_allocation = m3.maxMemoryAllocationSize ? m3.maxMemoryAllocationSize : UINT64_MAX;
  g->limits.max_workgroup_count_x = p.limits.maxComputeWorkGroupCount[0];
  g->limits.max_workgroup_count_y = p.limits.maxComputeWorkGroupCount[1];
  g->limits.subgroup_size = info[idx].subgroup_size;
  g->limits.subgroup_ops = info[idx].subgroup_ops;
  g->limits.cpu = p.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
  g->limits.driver_id = info[idx].driver_id;
  g->limits.timestamps = info[idx].timestamps && ts_bits > 0; /* the queue family chosen */
  g->limits.timestamp_period_ns = p.limits.timestampPeriod;
  g->ts_mask = ts_bits >= 64 ? UINT64_MAX : ((1ull << ts_bits) - 1);

  float prio = 1.0f;
  VkDeviceQueueCreateInfo qci = {
      .sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
      .queueFamilyIndex = g->family,
      .queueCount = 1,
      .pQueuePriorities = &prio,
  };
  const char *dext[1 + RAY_QUERY_EXT_COUNT];
  uint32_t dext_count = 0;
  if (g->can_present) dext[dext_count++] = VK_KHR_SWAPCHAIN_EXTENSION_NAME;
  /* The ray-query path's extensions and features only where the device has
   * them all (describe); a device without keeps the plain 1.1 device. */
  VkPhysicalDeviceRayQueryFeaturesKHR rq = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR,
                                            .rayQuery = VK_TRUE};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR as = {
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR, .pNext = &rq,
      .accelerationStructure = VK_TRUE};
  VkPhysicalDeviceBufferDeviceAddressFeatures bda = {
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES, .pNext = &as,
      .bufferDeviceAddress = VK_TRUE};
  /* auto: ray queries on a GPU that has them (its ray-tracing units); not on
   * a CPU device, where they are software like our BVH and measured no
   * faster (lavapipe 25: 0.56-1.13x per pass, docs/traversal.md). */
  /* PB_GPU_TRAVERSAL=ray-query|bvh (a test hook, as PB_GPU_MASK_FEATURES):
   * what auto means for every device this process makes, so a whole test
   * suite can run on one traversal. */
  const char *te = getenv("PB_GPU_TRAVERSAL");
  if (desc.traversal == PB_GPU_TRAVERSAL_AUTO && te && *te) {
    if (strcmp(te, "ray-query") == 0) desc.traversal = PB_GPU_TRAVERSAL_RAY_QUERY;
    else if (strcmp(te, "bvh") == 0) desc.traversal = PB_GPU_TRAVERSAL_BVH;
    else if (strcmp(te, "auto") != 0) {
      r = pb_fail(PB_ERR_USAGE, "PB_GPU_TRAVERSAL: '%s' is not auto, bvh or ray-query", te);
      goto fail;
    }
  }
  g->limits.ray_query = info[idx].ray_query && (desc.traversal == PB_GPU_TRAVERSAL_RAY_QUERY ||
                                                (desc.traversal == PB_GPU_TRAVERSAL_AUTO && !g->limits.cpu));
  if (desc.traversal == PB_GPU_TRAVERSAL_RAY_QUERY && !g->limits.ray_query) {
    r = pb_fail(PB_ERR_NO_DEVICE,
                "--traversal ray-query: %s has no ray queries (VK_KHR_acceleration_structure, VK_KHR_ray_query); "
                "see 'photonbridge info --devices'",
                p.deviceName);
    goto fail;
  }
  if (g->limits.ray_query)
    for (uint32_t i = 0; i < RAY_QUERY_EXT_COUNT; ++i) dext[dext_count++] = ray_query_exts[i];
  VkDeviceCreateInfo dci = {
      .sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
      .pNext = g->limits.ray_query ? (void *)&bda : NULL,
      .queueCreateInfoCount = 1,
      .pQueueCreateInfos = &qci,
      .enabledExtensionCount = dext_count,
      .ppEnabledExtensionNames = dext,
  };
  VkResult vr = vkCreateDevice(g->phys, &dci, NULL, &g->device);
  if (vr != VK_SUCCESS) {
    g->device = VK_NULL_HANDLE;
    r = pb_vk_fail(vr, "vkCreateDevice");
    goto fail;
  }
  vkGetDeviceQueue(g->device, g->family, 0, &g->queue);
  if (g->validation)
    g->set_name = (PFN_vkSetDebugUtilsObjectNameEXT)vkGetDeviceProcAddr(g->device, "vkSetDebugUtilsObjectNameEXT");
  if (!g->set_name && g->validation)
    g->set_name = (PFN_vkSetDebugUtilsObjectNameEXT)vkGetInstanceProcAddr(g->instance, "vkSetDebugUtilsObjectNameEXT");

  VkCommandPoolCreateInfo pci = {
      .sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
      .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
      .queueFamilyIndex = g->family,
  };
  vr = vkCreateCommandPool(g->device, &pci, NULL, &g->pool);
  if (vr != VK_SUCCESS) {
    r = pb_vk_fail(vr, "vkCreateCommandPool");
    goto fail;
  }
  VkCommandBufferAllocateInfo cai = {
      .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
      .commandPool = g->pool,
      .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
      .commandBufferCount = 1,
  };
  pb_gpu_set_name(g, VK_OBJECT_TYPE_COMMAND_POOL, (uint64_t)g->pool, "pb.command_pool");
  for (uint32_t i = 0; i < PB_GPU_FRAMES; ++i) { /* the submission ring (gpu.h PB_GPU_FRAMES) */
    struct pb_gpu_sub *c = &g->subs[i];
    vr = vkAllocateCommandBuffers(g->device, &cai, &c->cmd);
    if (vr != VK_SUCCESS) {
      r = pb_vk_fail(vr, "vkAllocateCommandBuffers");
      goto fail;
    }
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    vr = vkCreateFence(g->device, &fci, NULL, &c->fence);
    if (vr != VK_SUCCESS) {
      r = pb_vk_fail(vr, "vkCreateFence");
      goto fail;
    }
    if (g->limits.timestamps) {
      VkQueryPoolCreateInfo qpi = {
          .sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
          .queryType = VK_QUERY_TYPE_TIMESTAMP,
          .queryCount = desc.max_timestamps,
      };
      vr = vkCreateQueryPool(g->device, &qpi, NULL, &c->queries);
      if (vr != VK_SUCCESS) {
        r = pb_vk_fail(vr, "vkCreateQueryPool");
        goto fail;
      }
      g->query_count = desc.max_timestamps;
    }
    char nm[48];
    snprintf(nm, sizeof nm, "pb.commands[%u]", i);
    pb_gpu_set_name(g, VK_OBJECT_TYPE_COMMAND_BUFFER, (uint64_t)(uintptr_t)c->cmd, nm);
    snprintf(nm, sizeof nm, "pb.fence[%u]", i);
    pb_gpu_set_name(g, VK_OBJECT_TYPE_FENCE, (uint64_t)c->fence, nm);
    snprintf(nm, sizeof nm, "pb.timestamps[%u]", i);
    pb_gpu_set_name(g, VK_OBJECT_TYPE_QUERY_POOL, (uint64_t)c->queries, nm);
  }
  g->cur = g->read_sub = 0;
  g->cmd = g->subs[0].cmd;
  g->queries = g->subs[0].queries;
  pb_log_verbose("gpu: %s (%s), subgroup %u, maxStorageBufferRange %llu MiB%s", g->name,
                 info[idx].type, g->limits.subgroup_size,
                 (unsigned long long)(g->limits.max_storage_buffer_range >> 20),
                 g->validation ? ", validation on" : "");
  free(pd);
  free(info);
  *out = g;
  return PB_OK;
fail:
  free(pd);
  free(info);
  pb_gpu_destroy(g);
  return r;
}

const pb_gpu_limits *pb_gpu_get_limits(const pb_gpu *g) { return &g->limits; }
const char *pb_gpu_device_name(const pb_gpu *g) { return g->name; }
const char *pb_gpu_device_type(const pb_gpu *g) { return g->type ? g->type : "other"; }
const char *pb_gpu_traversal(const pb_gpu *g) { return g->limits.ray_query ? "ray-query" : "bvh"; }
VkDevice pb_gpu_vk_device(const pb_gpu *g) { return g->device; }
uint32_t pb_gpu_validation_errors(const pb_gpu *g) { return g->validation_errors; }
uint64_t pb_gpu_memory_in_use(const pb_gpu *g) { return g->memory_live; }
uint64_t pb_gpu_memory_peak(const pb_gpu *g) { return g->memory_peak; }

void pb_gpu_restart(pb_gpu *g) {
  (void)pb_gpu_settle(g);
  g->memory_peak = g->memory_live;
  g->validation_errors = 0;
  g->validation_first[0] = 0;
}
uint64_t pb_gpu_memory_limit(const pb_gpu *g) { return g->memory_limit; }
int pb_gpu_validation_enabled(const pb_gpu *g) { return g->validation; }

/* ---- recording ------------------------------------------------------------ */

/* Waits for context i's submission, in slices, so that a lost device is
 * reported rather than hanging forever. */
static pb_result wait_sub(pb_gpu *g, uint32_t i) {
  struct pb_gpu_sub *c = &g->subs[i];
  if (!c->pending) return PB_OK;
  VkResult vr;
  for (;;) {
    vr = vkWaitForFences(g->device, 1, &c->fence, VK_TRUE, 1000000000ull);
    if (vr != VK_TIMEOUT) break;
  }
  c->pending = 0;
  if (vr != VK_SUCCESS) return pb_vk_fail(vr, "vkWaitForFences");
  if (g->validation_errors)
    return pb_fail(PB_ERR_VULKAN, "Vulkan validation reported %u message%s; first: %s",
                   g->validation_errors, g->validation_errors == 1 ? "" : "s", g->validation_first);
  return PB_OK;
}

/* The context for the next submission: after the last one, the first that
 * is neither pending nor held; else the first not held (waiting for it);
 * else the oldest held one (its timestamps are lost). */
static uint32_t next_sub(pb_gpu *g) {
  uint32_t best = UINT32_MAX;
  for (uint32_t k = 1; k <= PB_GPU_FRAMES && best == UINT32_MAX; ++k) {
    uint32_t i = (g->cur + k) % PB_GPU_FRAMES;
    if (!g->subs[i].pending && !g->subs[i].held) best = i;
  }
  for (uint32_t k = 1; k <= PB_GPU_FRAMES && best == UINT32_MAX; ++k) {
    uint32_t i = (g->cur + k) % PB_GPU_FRAMES;
    if (!g->subs[i].held) best = i;
  }
  if (best == UINT32_MAX) {
    best = 0;
    for (uint32_t i = 1; i < PB_GPU_FRAMES; ++i)
      if (g->subs[i].serial < g->subs[best].serial) best = i;
    g->ring.held_stolen++;
  }
  return best;
}

/* Records the deferred host writes (pb_gpu_defer_write) into the recording
 * command buffer, after its leading barrier, and a barrier after them. */
static void record_deferred(pb_gpu *g) {
  g->cmd_deferred = g->deferred_count > 0;
  if (!g->deferred_count) return;
  for (uint32_t i = 0; i < g->deferred_count; ++i) {
    struct pb_gpu_deferred *d = &g->deferred[i];
    if (!d->data) { /* pb_gpu_buffer_fill_zero: the whole buffer */
      vkCmdFillBuffer(g->cmd, d->buffer, 0, VK_WHOLE_SIZE, 0);
    } else {
      vkCmdUpdateBuffer(g->cmd, d->buffer, d->offset, d->size, d->data);
      free(d->data);
    }
  }
  g->deferred_count = 0;
  pb_gpu_barrier(g);
}

pb_result pb_gpu_begin(pb_gpu *g) {
  if (g->recording) return pb_fail(PB_ERR_INTERNAL, "gpu: pb_gpu_begin while recording");
  uint32_t i = next_sub(g);
  struct pb_gpu_sub *c = &g->subs[i];
  if (c->pending) g->ring.begin_waits++;
  pb_result r = wait_sub(g, i); /* only this context's command buffer and queries are reused */
  c->held = 0;
  if (r != PB_OK) return r;
  if (g->read_sub == i) g->read_sub = UINT32_MAX; /* its timestamps are about to go */
  g->cur = i;
  g->cmd = c->cmd;
  g->queries = c->queries;
  VkResult vr = vkResetCommandBuffer(g->cmd, 0);
  if (vr != VK_SUCCESS) return pb_vk_fail(vr, "vkResetCommandBuffer");
  VkCommandBufferBeginInfo bi = {
      .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
      .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT,
  };
  vr = vkBeginCommandBuffer(g->cmd, &bi);
  if (vr != VK_SUCCESS) return pb_vk_fail(vr, "vkBeginCommandBuffer");
  if (g->queries) vkCmdResetQueryPool(g->cmd, g->queries, 0, g->query_count);
  /* Queue order (gpu.h PB_GPU_FRAMES): everything this submission does comes
   * after everything the earlier ones did, as with one context that waited.
   * The first scope of a pipeline barrier includes the commands of earlier
   * submissions to the queue. */
  VkMemoryBarrier mb = {
      .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
      .srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT,
      .dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT,
  };
  vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1, &mb, 0,
                       NULL, 0, NULL);
  g->recording = 1;
  record_deferred(g);
  return PB_OK;
}

int pb_gpu_can_defer(const pb_gpu *g) { return g && !g->recording && pb_gpu_pending(g); }

void pb_gpu_note_host_write(pb_gpu *g) {
  if (!g->recording || !g->cmd_deferred) return;
  if (!g->ring.late_writes) pb_log_verbose("gpu: a host write while recording a command buffer with deferred writes");
  g->ring.late_writes++;
}

pb_result pb_gpu_defer_write(pb_gpu *g, const pb_gpu_buffer *b, uint64_t offset, const void *data, uint64_t size) {
  if (g->deferred_count == g->deferred_cap) {
    uint32_t cap = g->deferred_cap ? 2 * g->deferred_cap : 16;
    struct pb_gpu_deferred *d = realloc(g->deferred, cap * sizeof *d);
    if (!d) return pb_fail(PB_ERR_NOMEM, "gpu: out of memory for a deferred write");
    g->deferred = d, g->deferred_cap = cap;
  }
  void *copy = NULL;
  if (data) {
    if (!(copy = malloc(size))) return pb_fail(PB_ERR_NOMEM, "gpu: out of memory for a deferred write");
    memcpy(copy, data, size);
  }
  g->deferred[g->deferred_count++] = (struct pb_gpu_deferred){
      .buffer = b->buffer, .mapped = b->mapped, .offset = offset, .size = size, .data = copy};
  g->ring.deferred_writes++;
  g->ring.deferred_bytes += size;
  return PB_OK;
}

static void bind(pb_gpu *g, const pb_gpu_pipeline *p, const void *push) {
  vkCmdBindPipeline(g->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->pipeline);
  vkCmdBindDescriptorSets(g->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->layout, 0, 1, &p->set, 0, NULL);
  if (p->push_bytes && push)
    vkCmdPushConstants(g->cmd, p->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, p->push_bytes, push);
}

pb_result pb_gpu_dispatch(pb_gpu *g, const pb_gpu_pipeline *p, const void *push,
                          uint64_t invocations) {
  if (invocations == 0) return PB_OK;
  uint64_t groups = (invocations + PB_GPU_WORKGROUP - 1) / PB_GPU_WORKGROUP;
  uint64_t gx = groups, gy = 1;
  uint64_t maxx = g->limits.max_workgroup_count_x;
  if (gx > maxx) {
    gx = maxx;
    gy = (groups + gx - 1) / gx;
  }
  if (gy > g->limits.max_workgroup_count_y)
    return pb_fail(PB_ERR_LIMIT, "gpu: %s: %llu work items exceed the device's dispatch limits",
                   "dispatch", (unsigned long long)invocations);
  bind(g, p, push);
  vkCmdDispatch(g->cmd, (uint32_t)gx, (uint32_t)gy, 1);
  return PB_OK;
}

pb_result pb_gpu_dispatch_indirect(pb_gpu *g, const pb_gpu_pipeline *p, const void *push,
                                   const pb_gpu_buffer *args, uint64_t offset) {
  if (!args || !args->buffer || offset % 4 || offset + 12 > args->size)
    return pb_fail(PB_ERR_INTERNAL, "gpu: indirect dispatch arguments at %llu outside their buffer",
                   (unsigned long long)offset);
  bind(g, p, push);
  vkCmdDispatchIndirect(g->cmd, args->buffer, offset);
  return PB_OK;
}

void pb_gpu_barrier(pb_gpu *g) {
  VkMemoryBarrier mb = {
      .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
      .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
      .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                       VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                       VK_ACCESS_INDIRECT_COMMAND_READ_BIT, /* pb_gpu_dispatch_indirect's counts */
  };
  vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                           VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                       0, 1, &mb, 0, NULL, 0, NULL);
}

void pb_gpu_timestamp(pb_gpu *g, uint32_t slot) {
  if (!g->queries || slot >= g->query_count) return;
  vkCmdWriteTimestamp(g->cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, g->queries, slot);
}

void pb_gpu_copy(pb_gpu *g, const pb_gpu_buffer *src, uint64_t src_offset, const pb_gpu_buffer *dst,
                 uint64_t dst_offset, uint64_t size) {
  if (!size) return;
  VkBufferCopy c = {.srcOffset = src_offset, .dstOffset = dst_offset, .size = size};
  vkCmdCopyBuffer(g->cmd, src->buffer, dst->buffer, 1, &c);
}

static pb_result submit(pb_gpu *g, int wait);

pb_result pb_gpu_submit(pb_gpu *g) { return submit(g, 1); }

pb_result pb_gpu_submit_async(pb_gpu *g) { return submit(g, 0); }

int pb_gpu_pending(const pb_gpu *g) {
  for (uint32_t i = 0; i < PB_GPU_FRAMES; ++i)
    if (g->subs[i].pending) return 1;
  return 0;
}

uint64_t pb_gpu_last_submission(const pb_gpu *g) { return g->serial; }

pb_gpu_ring_stats pb_gpu_ring_stats_get(const pb_gpu *g) { return g->ring; }

static uint32_t find_sub(const pb_gpu *g, uint64_t sub) {
  for (uint32_t i = 0; sub && i < PB_GPU_FRAMES; ++i)
    if (g->subs[i].serial == sub) return i;
  return UINT32_MAX;
}

int pb_gpu_outstanding(const pb_gpu *g, uint64_t sub) {
  uint32_t i = find_sub(g, sub);
  return i != UINT32_MAX && g->subs[i].pending;
}

int pb_gpu_busy(pb_gpu *g, uint64_t sub) {
  uint32_t i = find_sub(g, sub);
  if (i == UINT32_MAX || !g->subs[i].pending) return 0;
  return vkGetFenceStatus(g->device, g->subs[i].fence) == VK_NOT_READY;
}

int pb_gpu_timestamps_of(pb_gpu *g, uint64_t sub) {
  g->read_sub = sub ? find_sub(g, sub) : find_sub(g, g->serial);
  return g->read_sub != UINT32_MAX;
}

void pb_gpu_release(pb_gpu *g, uint64_t sub) {
  uint32_t i = find_sub(g, sub);
  if (i != UINT32_MAX) g->subs[i].held = 0;
}

/* Waits for every pending submission, oldest first, then makes the
 * deferred host writes: on the host where the buffer is mapped (nothing
 * runs now), else in a submission of their own. */
pb_result pb_gpu_wait(pb_gpu *g) {
  pb_result r = PB_OK;
  for (;;) {
    uint32_t oldest = UINT32_MAX;
    for (uint32_t i = 0; i < PB_GPU_FRAMES; ++i)
      if (g->subs[i].pending && (oldest == UINT32_MAX || g->subs[i].serial < g->subs[oldest].serial)) oldest = i;
    if (oldest == UINT32_MAX) break;
    pb_result ri = wait_sub(g, oldest);
    if (r == PB_OK) r = ri;
  }
  if (r != PB_OK || !g->deferred_count || g->recording) return r;
  int all_mapped = 1;
  for (uint32_t i = 0; i < g->deferred_count; ++i)
    if (!g->deferred[i].mapped) all_mapped = 0;
  if (!all_mapped) { /* recorded by pb_gpu_begin */
    if ((r = pb_gpu_begin(g)) != PB_OK) return r;
    return submit(g, 1);
  }
  for (uint32_t i = 0; i < g->deferred_count; ++i) {
    struct pb_gpu_deferred *d = &g->deferred[i];
    if (d->data) memcpy((char *)d->mapped + d->offset, d->data, d->size);
    else memset((char *)d->mapped + d->offset, 0, d->size);
    free(d->data);
  }
  g->deferred_count = 0;
  return PB_OK;
}

pb_result pb_gpu_settle(pb_gpu *g) { return g && (pb_gpu_pending(g) || g->deferred_count) ? pb_gpu_wait(g) : PB_OK; }

static pb_result submit(pb_gpu *g, int wait) {
  if (!g->recording) return pb_fail(PB_ERR_INTERNAL, "gpu: submit without begin");
  g->recording = 0;
  struct pb_gpu_sub *c = &g->subs[g->cur];
  VkResult vr = vkEndCommandBuffer(g->cmd);
  if (vr != VK_SUCCESS) return pb_vk_fail(vr, "vkEndCommandBuffer");
  VkSubmitInfo si = {
      .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
      .commandBufferCount = 1,
      .pCommandBuffers = &g->cmd,
  };
  vr = vkResetFences(g->device, 1, &c->fence);
  if (vr != VK_SUCCESS) return pb_vk_fail(vr, "vkResetFences");
  vr = vkQueueSubmit(g->queue, 1, &si, c->fence);
  if (vr != VK_SUCCESS) return pb_vk_fail(vr, "vkQueueSubmit");
  c->serial = ++g->serial;
  c->pending = 1;
  g->read_sub = g->cur;
  g->ring.submissions++;
  if (!wait) {
    c->held = 1;
    g->ring.async_submissions++;
    return PB_OK;
  }
  return wait_sub(g, g->cur);
}

double pb_gpu_elapsed_ms(pb_gpu *g, uint32_t a, uint32_t b) {
  uint32_t i = g->read_sub;
  if (i == UINT32_MAX || wait_sub(g, i) != PB_OK) return -1.0;
  VkQueryPool q = g->subs[i].queries;
  if (!q || a >= g->query_count || b >= g->query_count) return -1.0;
  uint64_t ta, tb;
  /* Without WAIT, a slot not written in that submission is NOT_READY. */
  if (vkGetQueryPoolResults(g->device, q, a, 1, sizeof ta, &ta, sizeof ta, VK_QUERY_RESULT_64_BIT) != VK_SUCCESS ||
      vkGetQueryPoolResults(g->device, q, b, 1, sizeof tb, &tb, sizeof tb, VK_QUERY_RESULT_64_BIT) != VK_SUCCESS)
    return -1.0;
  uint64_t d = (tb - ta) & g->ts_mask;
  return (double)d * g->limits.timestamp_period_ns * 1e-6;
}

void pb_gpu_vk_handles(const pb_gpu *g, pb_gpu_vk *out) {
  out->instance = g->instance;
  out->phys = g->phys;
  out->device = g->device;
  out->queue = g->queue;
  out->family = g->family;
  out->can_present = g->can_present;
  out->present_reason = g->can_present ? NULL : g->present_reason ? g->present_reason : "the renderer was made without a window";
}
