/* photonbridge info --devices: the Vulkan devices in the order --device N
 * counts, with the limits the renderer checks. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/cli.h"
#include "app/commands.h"
#include "core/json.h"
#include "gpu/gpu.h"

pb_result pb_info_devices(const pb_core_opts *c) {
  pb_gpu_device_info *d;
  uint32_t n;
  pb_result r = pb_gpu_list_devices(&d, &n);
  if (r != PB_OK) return r;
  if (c->json) {
    pb_json j;
    char *tmp;
    r = pb_json_open(&j, c->json, &tmp);
    if (r == PB_OK) {
      pb_json_begin_object(&j, NULL);
      pb_json_begin_array(&j, "devices");
      for (uint32_t i = 0; i < n; ++i) {
        pb_json_begin_object(&j, NULL);
        pb_json_int(&j, "index", i);
        pb_json_string(&j, "name", d[i].name);
        pb_json_string(&j, "type", d[i].type);
        pb_json_string(&j, "driver", d[i].driver);
        pb_json_string(&j, "driver_info", d[i].driver_info);
        char api[32];
        snprintf(api, sizeof api, "%u.%u.%u", VK_API_VERSION_MAJOR(d[i].api_version),
                 VK_API_VERSION_MINOR(d[i].api_version), VK_API_VERSION_PATCH(d[i].api_version));
        pb_json_string(&j, "api", api);
        pb_json_int(&j, "max_storage_buffer_range", (int64_t)d[i].max_storage_buffer_range);
        pb_json_int(&j, "device_local_bytes", (int64_t)d[i].device_local_bytes);
        pb_json_int(&j, "subgroup_size", d[i].subgroup_size);
        pb_json_bool(&j, "timestamps", d[i].timestamps);
        pb_json_bool(&j, "acceleration_structure", d[i].acceleration_structure);
        pb_json_bool(&j, "ray_query", d[i].ray_query);
        pb_json_bool(&j, "usable", d[i].usable);
        if (!d[i].usable) pb_json_string(&j, "missing", d[i].missing);
        pb_json_bool(&j, "default", d[i].preferred);
        pb_json_end_object(&j);
      }
      pb_json_end_array(&j);
      pb_json_end_object(&j);
      r = pb_json_close(&j, c->json, tmp);
    }
    if (r != PB_OK || strcmp(c->json, "-") == 0) {
      free(d);
      return r;
    }
  }
  if (!c->quiet) {
    printf("Vulkan devices (--device N):\n");
    for (uint32_t i = 0; i < n; ++i)
      printf("  %u%s %-36s %-10s Vulkan %u.%u  %s%s%s%s  storage buffer max %llu MiB, subgroup %u, timestamps %s, "
             "acceleration structures %s, ray queries %s%s%s%s\n",
             i, d[i].preferred ? "*" : " ", d[i].name, d[i].type, VK_API_VERSION_MAJOR(d[i].api_version),
             VK_API_VERSION_MINOR(d[i].api_version), d[i].driver[0] ? d[i].driver : "-",
             d[i].driver_info[0] ? " (" : "", d[i].driver_info, d[i].driver_info[0] ? ")" : "",
             (unsigned long long)(d[i].max_storage_buffer_range >> 20), d[i].subgroup_size,
             d[i].timestamps ? "yes" : "no", d[i].acceleration_structure ? "yes" : "no", d[i].ray_query ? "yes" : "no",
             d[i].usable ? "" : "  (unusable, lacks ", d[i].missing, d[i].usable ? "" : ")");
    printf("* = used by default (discrete GPU first, CPU implementations last)\n");
  }
  free(d);
  return PB_OK;
}
