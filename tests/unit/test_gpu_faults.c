/* GPU faults at the API: the buffer-memory cap sums live
 * allocations (exact boundary, release, peak, the error names buffer, size and
 * cap), PB_GPU_MASK_FEATURES makes pb_gpu_create and pb_gpu_list_devices
 * treat a required feature as absent (PB_ERR_NO_DEVICE naming device and
 * feature) and an optional one (timestamps) as merely off, and validation
 * catches a deliberately invalid call. Exit 77 without a usable device. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>

#include "gpu/gpu.h"
#include "pbtest.h"

static void test_memory_cap(void) {
  pb_gpu_desc gd = {.memory_limit = 1u << 20};
  pb_gpu *g = NULL;
  CHECK_EQ_INT(pb_gpu_create(&gd, &g), PB_OK);
  if (!g) return;
  CHECK_EQ_INT(pb_gpu_memory_limit(g), 1u << 20);
  pb_gpu_buffer a, b, c;
  pb_gpu_buffer_desc half = {.name = "test.half", .size = 512u << 10};
  CHECK_EQ_INT(pb_gpu_buffer_create(g, &half, &a), PB_OK);
  CHECK_EQ_INT(pb_gpu_memory_in_use(g), 512u << 10);
  /* Exactly at the cap is allowed. */
  CHECK_EQ_INT(pb_gpu_buffer_create(g, &half, &b), PB_OK);
  CHECK_EQ_INT(pb_gpu_memory_in_use(g), 1u << 20);
  /* One byte more is not, and nothing is allocated. */
  pb_error_clear();
  pb_gpu_buffer_desc one = {.name = "test.one_more", .size = 4};
  CHECK_EQ_INT(pb_gpu_buffer_create(g, &one, &c), PB_ERR_NOMEM);
  CHECK(c.buffer == VK_NULL_HANDLE && c.memory == VK_NULL_HANDLE);
  const char *m = pb_error_message();
  CHECK(strstr(m, "test.one_more") != NULL);
  CHECK(strstr(m, "cap of 1.0 MiB") != NULL);
  CHECK(strchr(m, '\n') == NULL);
  CHECK_EQ_INT(pb_gpu_memory_in_use(g), 1u << 20);
  /* Releasing one makes room again; the peak stays. */
  pb_gpu_buffer_destroy(g, &a);
  CHECK_EQ_INT(pb_gpu_memory_in_use(g), 512u << 10);
  pb_error_clear();
  CHECK_EQ_INT(pb_gpu_buffer_create(g, &one, &c), PB_OK);
  CHECK_EQ_INT(pb_gpu_memory_in_use(g), (512u << 10) + 4);
  CHECK_EQ_INT(pb_gpu_memory_peak(g), 1u << 20);
  /* A single buffer over the cap: refused before the driver is asked. */
  pb_gpu_buffer_desc big = {.name = "test.big", .size = 3u << 20};
  pb_gpu_buffer d;
  pb_error_clear();
  CHECK_EQ_INT(pb_gpu_buffer_create(g, &big, &d), PB_ERR_NOMEM);
  CHECK(strstr(pb_error_message(), "GPU buffer of 3.0 MiB") != NULL);
  pb_gpu_buffer_destroy(g, &b);
  pb_gpu_buffer_destroy(g, &c);
  CHECK_EQ_INT(pb_gpu_memory_in_use(g), 0);
  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  pb_gpu_destroy(g);

  /* The environment's cap (MiB) applies when the desc has none. */
  setenv("PB_GPU_MEMORY_LIMIT", "0.25", 1);
  g = NULL;
  CHECK_EQ_INT(pb_gpu_create(NULL, &g), PB_OK);
  if (g) {
    CHECK_EQ_INT(pb_gpu_memory_limit(g), 256u << 10);
    pb_error_clear();
    CHECK_EQ_INT(pb_gpu_buffer_create(g, &half, &a), PB_ERR_NOMEM);
    pb_gpu_destroy(g);
  }
  setenv("PB_GPU_MEMORY_LIMIT", "-3", 1);
  pb_error_clear();
  CHECK_EQ_INT(pb_gpu_create(NULL, &g), PB_ERR_USAGE);
  CHECK(g == NULL);
  unsetenv("PB_GPU_MEMORY_LIMIT");
}

static void test_feature_mask(void) {
  static const char *const required[] = {"vulkan-1.1", "compute", "workgroup-64", "storage-buffers"};
  for (size_t i = 0; i < sizeof required / sizeof *required; ++i) {
    setenv("PB_GPU_MASK_FEATURES", required[i], 1);
    pb_gpu *g = NULL;
    pb_error_clear();
    CHECK_EQ_INT(pb_gpu_create(NULL, &g), PB_ERR_NO_DEVICE);
    CHECK(g == NULL);
    const char *m = pb_error_message();
    CHECK(strstr(m, "no usable Vulkan device: ") != NULL);
    CHECK(strstr(m, required[i]) != NULL);
    pb_gpu_device_info *d = NULL;
    uint32_t n = 0;
    CHECK_EQ_INT(pb_gpu_list_devices(&d, &n), PB_OK);
    for (uint32_t k = 0; k < n; ++k) {
      CHECK(!d[k].usable && !d[k].preferred);
      CHECK(strstr(d[k].missing, required[i]) != NULL);
      CHECK(strstr(m, d[0].name) != NULL);
    }
    free(d);
  }
  /* Two at once: both named. */
  setenv("PB_GPU_MASK_FEATURES", "compute, storage-buffers", 1);
  pb_gpu *g = NULL;
  pb_error_clear();
  CHECK_EQ_INT(pb_gpu_create(NULL, &g), PB_ERR_NO_DEVICE);
  CHECK(strstr(pb_error_message(), "compute") && strstr(pb_error_message(), "storage-buffers"));
  /* Optional: timestamps off, the device still usable. */
  setenv("PB_GPU_MASK_FEATURES", "timestamps", 1);
  g = NULL;
  CHECK_EQ_INT(pb_gpu_create(NULL, &g), PB_OK);
  if (g) {
    CHECK_EQ_INT(pb_gpu_get_limits(g)->timestamps, 0);
    pb_gpu_destroy(g);
  }
  setenv("PB_GPU_MASK_FEATURES", "ray-tracing", 1);
  g = NULL;
  pb_error_clear();
  CHECK_EQ_INT(pb_gpu_create(NULL, &g), PB_ERR_USAGE);
  CHECK(strstr(pb_error_message(), "'ray-tracing'") != NULL);
  unsetenv("PB_GPU_MASK_FEATURES");
  /* Unmasked, every listed device that is usable has an empty reason. */
  pb_gpu_device_info *d = NULL;
  uint32_t n = 0;
  CHECK_EQ_INT(pb_gpu_list_devices(&d, &n), PB_OK);
  int usable = 0;
  for (uint32_t k = 0; k < n; ++k) {
    CHECK_EQ_INT(d[k].usable, d[k].missing[0] == 0);
    usable += d[k].usable;
  }
  CHECK(usable > 0);
  free(d);
}

/* Validation is live: a deliberately invalid call (a zero-sized VkBuffer,
 * VUID-VkBufferCreateInfo-size-00912) is counted per context and per process,
 * and the next submission fails with PB_ERR_VULKAN quoting it. */
static void test_validation_catches(void) {
  pb_gpu_desc gd = {.validation = 1};
  pb_gpu *g = NULL;
  pb_result r = pb_gpu_create(&gd, &g);
  if (r == PB_ERR_NOT_AVAILABLE) {
    printf("note: no validation layer, validation check skipped\n");
    return;
  }
  CHECK_EQ_INT(r, PB_OK);
  if (!g) return;
  uint32_t total0 = pb_gpu_validation_total();
  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  VkBufferCreateInfo bci = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                            .size = 0,
                            .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                            .sharingMode = VK_SHARING_MODE_EXCLUSIVE};
  VkBuffer b = VK_NULL_HANDLE;
  fprintf(stderr, "(a validation message about a zero-sized buffer is expected next)\n");
  VkResult vr = vkCreateBuffer(pb_gpu_vk_device(g), &bci, NULL, &b);
  if (vr == VK_SUCCESS && b) vkDestroyBuffer(pb_gpu_vk_device(g), b, NULL);
  CHECK(pb_gpu_validation_errors(g) >= 1);
  CHECK(pb_gpu_validation_total() >= total0 + 1);
  CHECK_EQ_INT(pb_gpu_begin(g), PB_OK);
  pb_error_clear();
  CHECK_EQ_INT(pb_gpu_submit(g), PB_ERR_VULKAN);
  CHECK(strstr(pb_error_message(), "Vulkan validation reported") != NULL);
  pb_gpu_destroy(g);
}

int main(void) {
  unsetenv("PB_GPU_MASK_FEATURES");
  unsetenv("PB_GPU_MEMORY_LIMIT");
  pb_gpu *g = NULL;
  if (pb_gpu_create(NULL, &g) != PB_OK) {
    printf("skip: no usable Vulkan device: %s\n", pb_error_message());
    return 77;
  }
  pb_gpu_destroy(g);
  test_memory_cap();
  test_feature_mask();
  test_validation_catches();
  return pbt_done();
}
