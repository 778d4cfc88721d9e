/* Swapchain presentation (present.h). One frame in flight: the renderer
 * blocks for each frame anyway, so a second would only add latency. */
#include "view/present.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "gpu/gpu.h"

struct pb_present {
  GLFWwindow *window;
  VkInstance instance;
  VkDebugUtilsMessengerEXT messenger;
  VkSurfaceKHR surface;
  VkPhysicalDevice phys;
  VkDevice device;
  uint32_t queue_family;
  VkQueue queue;
  VkCommandPool pool;
  VkCommandBuffer cmd;
  VkFence fence;
  VkSemaphore acquired;
  VkSemaphore *done; /* one per swapchain image: a present may still wait on the last one */
  VkSwapchainKHR swapchain;
  VkFormat format;
  VkExtent2D extent;
  uint32_t image_count;
  VkImage *images;
  /* The frame: staging buffer and image, made for one size. */
  uint32_t fw, fh;
  VkBuffer staging;
  VkDeviceMemory staging_mem;
  void *staging_map;
  VkImage frame;
  VkDeviceMemory frame_mem;
  int frame_fresh; /* the frame image has never been written (layout UNDEFINED) */
  uint32_t validation_messages, recreations;
  int borrowed; /* instance and device are the renderer's (pb_gpu_vk) */
};

static pb_result vk_fail(VkResult vr, const char *what) {
  if (vr == VK_ERROR_DEVICE_LOST)
    return pb_fail(PB_ERR_DEVICE_LOST, "view: the presentation device was lost (%s); the window closes", what);
  if (vr == VK_ERROR_OUT_OF_HOST_MEMORY || vr == VK_ERROR_OUT_OF_DEVICE_MEMORY)
    return pb_fail(PB_ERR_NOMEM, "view: out of memory in %s", what);
  return pb_fail(PB_ERR_VULKAN, "view: %s failed (VkResult %d)", what, (int)vr);
}
#define VK(call, what)                         \
  do {                                         \
    VkResult vr_ = (call);                     \
    if (vr_ != VK_SUCCESS) {                   \
      r = vk_fail(vr_, what);                  \
      goto fail;                               \
    }                                          \
  } while (0)

static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT sev,
                                                 VkDebugUtilsMessageTypeFlagsEXT type,
                                                 const VkDebugUtilsMessengerCallbackDataEXT *data, void *user) {
  (void)type;
  if (sev < VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) return VK_FALSE;
  pb_present *p = user;
  p->validation_messages++;
  fprintf(stderr, "photonbridge view: Vulkan validation (presenter): %s\n", data->pMessage);
  return VK_FALSE;
}

static int has_layer(const char *name) {
  uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, NULL);
  VkLayerProperties *l = calloc(n ? n : 1, sizeof *l);
  int found = 0;
  if (l && vkEnumerateInstanceLayerProperties(&n, l) == VK_SUCCESS)
    for (uint32_t i = 0; i < n; ++i) found |= strcmp(l[i].layerName, name) == 0;
  free(l);
  return found;
}

static int find_memory(VkPhysicalDevice phys, uint32_t bits, VkMemoryPropertyFlags want, uint32_t *out) {
  VkPhysicalDeviceMemoryProperties mp;
  vkGetPhysicalDeviceMemoryProperties(phys, &mp);
  for (uint32_t i = 0; i < mp.memoryTypeCount; ++i)
    if ((bits & (1u << i)) && (mp.memoryTypes[i].propertyFlags & want) == want) {
      *out = i;
      return 1;
    }
  return 0;
}

static void destroy_frame(pb_present *p) {
  if (p->staging_map) vkUnmapMemory(p->device, p->staging_mem);
  if (p->staging) vkDestroyBuffer(p->device, p->staging, NULL);
  if (p->staging_mem) vkFreeMemory(p->device, p->staging_mem, NULL);
  if (p->frame) vkDestroyImage(p->device, p->frame, NULL);
  if (p->frame_mem) vkFreeMemory(p->device, p->frame_mem, NULL);
  p->staging_map = NULL, p->staging = VK_NULL_HANDLE, p->staging_mem = VK_NULL_HANDLE;
  p->frame = VK_NULL_HANDLE, p->frame_mem = VK_NULL_HANDLE;
  p->fw = p->fh = 0;
}

static pb_result make_frame(pb_present *p, uint32_t w, uint32_t h) {
  pb_result r = PB_OK;
  destroy_frame(p);
  VkBufferCreateInfo bi = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO, .size = (VkDeviceSize)w * h * 4,
                           .usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT, .sharingMode = VK_SHARING_MODE_EXCLUSIVE};
  VK(vkCreateBuffer(p->device, &bi, NULL, &p->staging), "vkCreateBuffer (staging)");
  VkMemoryRequirements mr;
  vkGetBufferMemoryRequirements(p->device, p->staging, &mr);
  uint32_t type;
  if (!find_memory(p->phys, mr.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                   &type)) {
    r = pb_fail(PB_ERR_VULKAN, "view: the presentation device has no host-visible coherent memory");
    goto fail;
  }
  VkMemoryAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, .allocationSize = mr.size,
                             .memoryTypeIndex = type};
  VK(vkAllocateMemory(p->device, &ai, NULL, &p->staging_mem), "vkAllocateMemory (staging)");
  VK(vkBindBufferMemory(p->device, p->staging, p->staging_mem, 0), "vkBindBufferMemory");
  VK(vkMapMemory(p->device, p->staging_mem, 0, VK_WHOLE_SIZE, 0, &p->staging_map), "vkMapMemory");
  VkImageCreateInfo ii = {.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO, .imageType = VK_IMAGE_TYPE_2D,
                          .format = VK_FORMAT_R8G8B8A8_UNORM, .extent = {w, h, 1}, .mipLevels = 1, .arrayLayers = 1,
                          .samples = VK_SAMPLE_COUNT_1_BIT, .tiling = VK_IMAGE_TILING_OPTIMAL,
                          .usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                          .sharingMode = VK_SHARING_MODE_EXCLUSIVE, .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED};
  VK(vkCreateImage(p->device, &ii, NULL, &p->frame), "vkCreateImage (frame)");
  vkGetImageMemoryRequirements(p->device, p->frame, &mr);
  if (!find_memory(p->phys, mr.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, &type) &&
      !find_memory(p->phys, mr.memoryTypeBits, 0, &type)) {
    r = pb_fail(PB_ERR_VULKAN, "view: no memory type for the frame image");
    goto fail;
  }
  ai.allocationSize = mr.size, ai.memoryTypeIndex = type;
  VK(vkAllocateMemory(p->device, &ai, NULL, &p->frame_mem), "vkAllocateMemory (frame)");
  VK(vkBindImageMemory(p->device, p->frame, p->frame_mem, 0), "vkBindImageMemory");
  p->fw = w, p->fh = h;
  p->frame_fresh = 1;
  return PB_OK;
fail:
  destroy_frame(p);
  return r;
}

static void destroy_images(pb_present *p) {
  for (uint32_t i = 0; p->done && i < p->image_count; ++i)
    if (p->done[i]) vkDestroySemaphore(p->device, p->done[i], NULL);
  free(p->done);
  free(p->images);
  p->done = NULL, p->images = NULL;
  p->image_count = 0;
}

/* (Re)creates the swapchain for the framebuffer's current size. *empty: the
 * framebuffer is 0 x 0 (minimised): no swapchain, nothing to present. */
static pb_result make_swapchain(pb_present *p, int *empty) {
  pb_result r = PB_OK;
  *empty = 0;
  int fbw = 0, fbh = 0;
  glfwGetFramebufferSize(p->window, &fbw, &fbh);
  VkSurfaceCapabilitiesKHR caps;
  VK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(p->phys, p->surface, &caps), "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
  VkExtent2D ext = caps.currentExtent;
  if (ext.width == UINT32_MAX) { /* the surface takes the swapchain's size */
    ext.width = (uint32_t)(fbw > 0 ? fbw : 0), ext.height = (uint32_t)(fbh > 0 ? fbh : 0);
    if (ext.width < caps.minImageExtent.width) ext.width = caps.minImageExtent.width;
    if (ext.height < caps.minImageExtent.height) ext.height = caps.minImageExtent.height;
    if (ext.width > caps.maxImageExtent.width) ext.width = caps.maxImageExtent.width;
    if (ext.height > caps.maxImageExtent.height) ext.height = caps.maxImageExtent.height;
  }
  if (ext.width == 0 || ext.height == 0 || fbw <= 0 || fbh <= 0) {
    *empty = 1;
    return PB_OK;
  }
  if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT)) {
    r = pb_fail(PB_ERR_NOT_AVAILABLE, "view: the window surface cannot be a transfer destination (needed to blit "
                "the frame); use 'photonbridge render'");
    goto fail;
  }
  uint32_t nf = 0;
  VK(vkGetPhysicalDeviceSurfaceFormatsKHR(p->phys, p->surface, &nf, NULL), "vkGetPhysicalDeviceSurfaceFormatsKHR");
  VkSurfaceFormatKHR *fmts = calloc(nf ? nf : 1, sizeof *fmts);
  if (!fmts) return pb_fail(PB_ERR_NOMEM, "view: out of memory");
  VkResult vr = vkGetPhysicalDeviceSurfaceFormatsKHR(p->phys, p->surface, &nf, fmts);
  VkFormat chosen = VK_FORMAT_UNDEFINED;
  VkColorSpaceKHR space = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
  for (uint32_t i = 0; vr == VK_SUCCESS && i < nf && chosen == VK_FORMAT_UNDEFINED; ++i)
    if ((fmts[i].format == VK_FORMAT_B8G8R8A8_UNORM || fmts[i].format == VK_FORMAT_R8G8B8A8_UNORM) &&
        fmts[i].colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR)
      chosen = fmts[i].format, space = fmts[i].colorSpace;
  free(fmts);
  VK(vr, "vkGetPhysicalDeviceSurfaceFormatsKHR");
  if (chosen == VK_FORMAT_UNDEFINED) {
    r = pb_fail(PB_ERR_NOT_AVAILABLE, "view: the window surface offers no 8-bit UNORM sRGB-display format");
    goto fail;
  }
  VkFormatProperties fp;
  vkGetPhysicalDeviceFormatProperties(p->phys, chosen, &fp);
  if (!(fp.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_DST_BIT)) {
    r = pb_fail(PB_ERR_NOT_AVAILABLE, "view: the swapchain format cannot be a blit destination on this device");
    goto fail;
  }
  uint32_t count = caps.minImageCount + 1;
  if (caps.maxImageCount && count > caps.maxImageCount) count = caps.maxImageCount;
  VkSwapchainKHR old = p->swapchain;
  VkSwapchainCreateInfoKHR si = {
      .sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR, .surface = p->surface, .minImageCount = count,
      .imageFormat = chosen, .imageColorSpace = space, .imageExtent = ext, .imageArrayLayers = 1,
      .imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT, .imageSharingMode = VK_SHARING_MODE_EXCLUSIVE,
      .preTransform = (caps.supportedTransforms & VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR)
                          ? VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR : caps.currentTransform,
      .compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                            ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                            : (VkCompositeAlphaFlagBitsKHR)(caps.supportedCompositeAlpha & -caps.supportedCompositeAlpha),
      /* FIFO: always supported, paced by the display; the renderer is the
       * bottleneck, so it costs no frames. */
      .presentMode = VK_PRESENT_MODE_FIFO_KHR, .clipped = VK_TRUE, .oldSwapchain = old};
  VkSwapchainKHR sc;
  VK(vkCreateSwapchainKHR(p->device, &si, NULL, &sc), "vkCreateSwapchainKHR");
  if (old) vkDestroySwapchainKHR(p->device, old, NULL);
  p->swapchain = sc;
  p->format = chosen;
  p->extent = ext;
  destroy_images(p);
  VK(vkGetSwapchainImagesKHR(p->device, sc, &p->image_count, NULL), "vkGetSwapchainImagesKHR");
  p->images = calloc(p->image_count, sizeof *p->images);
  p->done = calloc(p->image_count, sizeof *p->done);
  if (!p->images || !p->done) return pb_fail(PB_ERR_NOMEM, "view: out of memory");
  VK(vkGetSwapchainImagesKHR(p->device, sc, &p->image_count, p->images), "vkGetSwapchainImagesKHR");
  VkSemaphoreCreateInfo sei = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  for (uint32_t i = 0; i < p->image_count; ++i)
    VK(vkCreateSemaphore(p->device, &sei, NULL, &p->done[i]), "vkCreateSemaphore");
  return PB_OK;
fail:
  return r;
}

static pb_result recreate(pb_present *p, int *empty) {
  VkResult vr = vkDeviceWaitIdle(p->device);
  if (vr != VK_SUCCESS) return vk_fail(vr, "vkDeviceWaitIdle");
  p->recreations++;
  return make_swapchain(p, empty);
}

pb_result pb_present_create(const pb_present_desc *d, pb_present **out) {
  *out = NULL;
  pb_result r = PB_OK;
  pb_present *p = calloc(1, sizeof *p);
  if (!p) return pb_fail(PB_ERR_NOMEM, "view: out of memory");
  p->window = d->window;
  const char *why = d->shared ? d->shared->present_reason : "no render device was given";
  const char *own = getenv("PB_PRESENT_OWN_DEVICE"); /* test hook: the fallback */
  if (own && own[0] == '1') why = "PB_PRESENT_OWN_DEVICE=1";
  else if (d->shared && d->shared->can_present) {
    /* The render device: its instance has the surface extensions. */
    const pb_gpu_vk *vk = d->shared;
    VK(glfwCreateWindowSurface(vk->instance, p->window, NULL, &p->surface), "glfwCreateWindowSurface");
    VkBool32 can = VK_FALSE;
    VkFormatProperties fp;
    vkGetPhysicalDeviceFormatProperties(vk->phys, VK_FORMAT_R8G8B8A8_UNORM, &fp);
    if (vkGetPhysicalDeviceSurfaceSupportKHR(vk->phys, vk->family, p->surface, &can) != VK_SUCCESS || !can) {
      why = "the render device's queue family cannot present to this window's surface";
    } else if (!(fp.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_SRC_BIT)) {
      why = "R8G8B8A8_UNORM images cannot be blitted on the render device";
    } else {
      p->borrowed = 1;
      p->instance = vk->instance, p->phys = vk->phys, p->device = vk->device;
      p->queue = vk->queue, p->queue_family = vk->family;
    }
    if (!p->borrowed) {
      vkDestroySurfaceKHR(vk->instance, p->surface, NULL);
      p->surface = VK_NULL_HANDLE;
    }
  }
  if (!p->borrowed) {
  pb_log_info("view: presenting through a second Vulkan device: %s", why);
  uint32_t next = 0;
  const char **glfw_ext = glfwGetRequiredInstanceExtensions(&next);
  if (!glfw_ext) {
    r = pb_fail(PB_ERR_NOT_AVAILABLE, "view: GLFW finds no Vulkan window-system surface here (is a Vulkan loader "
                "with VK_KHR_surface installed?); use 'photonbridge render'");
    goto fail;
  }
  const char *exts[16];
  uint32_t ne = 0;
  for (uint32_t i = 0; i < next && ne < 15; ++i) exts[ne++] = glfw_ext[i];
  const char *layer = "VK_LAYER_KHRONOS_validation";
  int val = d->validation;
  if (val && !has_layer(layer)) {
    r = pb_fail(PB_ERR_NOT_AVAILABLE, "view: validation requested but %s is not installed: apt install "
                "vulkan-validationlayers", layer);
    goto fail;
  }
  if (val) exts[ne++] = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
  VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO, .pApplicationName = "photonbridge view",
                           .apiVersion = VK_API_VERSION_1_1};
  VkInstanceCreateInfo ici = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO, .pApplicationInfo = &app,
                              .enabledLayerCount = val ? 1u : 0u, .ppEnabledLayerNames = &layer,
                              .enabledExtensionCount = ne, .ppEnabledExtensionNames = exts};
  VK(vkCreateInstance(&ici, NULL, &p->instance), "vkCreateInstance (presenter)");
  if (val) {
    PFN_vkCreateDebugUtilsMessengerEXT mk =
        (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(p->instance, "vkCreateDebugUtilsMessengerEXT");
    VkDebugUtilsMessengerCreateInfoEXT mi = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
        .pfnUserCallback = on_message, .pUserData = p};
    if (mk) VK(mk(p->instance, &mi, NULL, &p->messenger), "vkCreateDebugUtilsMessengerEXT");
  }
  VK(glfwCreateWindowSurface(p->instance, p->window, NULL, &p->surface), "glfwCreateWindowSurface");
  /* The physical device: the renderer's (by name) when it can present, else
   * the first that can, with a graphics queue (vkCmdBlitImage needs one). */
  uint32_t np = 0;
  VK(vkEnumeratePhysicalDevices(p->instance, &np, NULL), "vkEnumeratePhysicalDevices");
  VkPhysicalDevice *phys = calloc(np ? np : 1, sizeof *phys);
  if (!phys) {
    r = pb_fail(PB_ERR_NOMEM, "view: out of memory");
    goto fail;
  }
  VkResult vr = vkEnumeratePhysicalDevices(p->instance, &np, phys);
  int best = -1;
  uint32_t best_family = 0;
  for (uint32_t i = 0; vr == VK_SUCCESS && i < np; ++i) {
    uint32_t nq = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(phys[i], &nq, NULL);
    VkQueueFamilyProperties q[32];
    if (nq > 32) nq = 32;
    vkGetPhysicalDeviceQueueFamilyProperties(phys[i], &nq, q);
    for (uint32_t f = 0; f < nq; ++f) {
      VkBool32 can = VK_FALSE;
      if (!(q[f].queueFlags & VK_QUEUE_GRAPHICS_BIT)) continue;
      if (vkGetPhysicalDeviceSurfaceSupportKHR(phys[i], f, p->surface, &can) != VK_SUCCESS || !can) continue;
      VkPhysicalDeviceProperties pr;
      vkGetPhysicalDeviceProperties(phys[i], &pr);
      int named = d->device_name && strcmp(pr.deviceName, d->device_name) == 0;
      if (best < 0 || named) best = (int)i, best_family = f;
      break;
    }
    if (best >= 0 && d->device_name) {
      VkPhysicalDeviceProperties pr;
      vkGetPhysicalDeviceProperties(phys[best], &pr);
      if (strcmp(pr.deviceName, d->device_name) == 0) break;
    }
  }
  if (best >= 0) p->phys = phys[best];
  free(phys);
  VK(vr, "vkEnumeratePhysicalDevices");
  if (best < 0) {
    r = pb_fail(PB_ERR_NO_DEVICE, "view: no Vulkan device can present to this window; use 'photonbridge render'");
    goto fail;
  }
  p->queue_family = best_family;
  VkFormatProperties fp;
  vkGetPhysicalDeviceFormatProperties(p->phys, VK_FORMAT_R8G8B8A8_UNORM, &fp);
  if (!(fp.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_SRC_BIT)) {
    r = pb_fail(PB_ERR_NOT_AVAILABLE, "view: R8G8B8A8_UNORM images cannot be blitted on this device");
    goto fail;
  }
  float prio = 1.0f;
  VkDeviceQueueCreateInfo qi = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO, .queueFamilyIndex = best_family,
                                .queueCount = 1, .pQueuePriorities = &prio};
  const char *dext = VK_KHR_SWAPCHAIN_EXTENSION_NAME;
  VkDeviceCreateInfo di = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, .queueCreateInfoCount = 1,
                           .pQueueCreateInfos = &qi, .enabledExtensionCount = 1, .ppEnabledExtensionNames = &dext};
  VK(vkCreateDevice(p->phys, &di, NULL, &p->device), "vkCreateDevice (presenter)");
  vkGetDeviceQueue(p->device, best_family, 0, &p->queue);
  } /* own device */
  VkCommandPoolCreateInfo pi = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT, .queueFamilyIndex = p->queue_family};
  VK(vkCreateCommandPool(p->device, &pi, NULL, &p->pool), "vkCreateCommandPool");
  VkCommandBufferAllocateInfo cai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO, .commandPool = p->pool,
                                     .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY, .commandBufferCount = 1};
  VK(vkAllocateCommandBuffers(p->device, &cai, &p->cmd), "vkAllocateCommandBuffers");
  VkFenceCreateInfo fi = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO, .flags = VK_FENCE_CREATE_SIGNALED_BIT};
  VK(vkCreateFence(p->device, &fi, NULL, &p->fence), "vkCreateFence");
  VkSemaphoreCreateInfo sei = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  VK(vkCreateSemaphore(p->device, &sei, NULL, &p->acquired), "vkCreateSemaphore");
  int empty;
  if ((r = make_swapchain(p, &empty)) != PB_OK) goto fail;
  *out = p;
  return PB_OK;
fail:
  pb_present_destroy(p);
  return r;
}

void pb_present_destroy(pb_present *p) {
  if (!p) return;
  if (p->device) {
    vkDeviceWaitIdle(p->device);
    destroy_frame(p);
    if (p->swapchain) vkDestroySwapchainKHR(p->device, p->swapchain, NULL);
    if (p->acquired) vkDestroySemaphore(p->device, p->acquired, NULL);
    destroy_images(p);
    if (p->fence) vkDestroyFence(p->device, p->fence, NULL);
    if (p->pool) vkDestroyCommandPool(p->device, p->pool, NULL);
    if (!p->borrowed) vkDestroyDevice(p->device, NULL);
  }
  if (p->surface) vkDestroySurfaceKHR(p->instance, p->surface, NULL);
  if (p->messenger) {
    PFN_vkDestroyDebugUtilsMessengerEXT rm =
        (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(p->instance, "vkDestroyDebugUtilsMessengerEXT");
    if (rm) rm(p->instance, p->messenger, NULL);
  }
  if (p->instance && !p->borrowed) vkDestroyInstance(p->instance, NULL);
  free(p);
}

static void barrier(VkCommandBuffer cmd, VkImage img, VkImageLayout from, VkImageLayout to, VkAccessFlags src_access,
                    VkAccessFlags dst_access, VkPipelineStageFlags src, VkPipelineStageFlags dst) {
  VkImageMemoryBarrier b = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER, .srcAccessMask = src_access,
                            .dstAccessMask = dst_access, .oldLayout = from, .newLayout = to,
                            .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED, .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                            .image = img, .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1}};
  vkCmdPipelineBarrier(cmd, src, dst, 0, 0, NULL, 0, NULL, 1, &b);
}

/* rgba from the host, or src: a buffer of the shared render device that a
 * compute pass wrote (RGBA8 words, present_pass.h). */
static pb_result present(pb_present *p, const uint8_t *rgba, VkBuffer src, uint32_t width, uint32_t height) {
  pb_result r = PB_OK;
  int empty = 0;
  if (!p->swapchain || p->extent.width == 0) {
    if ((r = recreate(p, &empty)) != PB_OK) return r;
    if (empty) return PB_OK;
  }
  int fbw = 0, fbh = 0;
  glfwGetFramebufferSize(p->window, &fbw, &fbh);
  if (fbw <= 0 || fbh <= 0) return PB_OK; /* minimised */
  if ((uint32_t)fbw != p->extent.width || (uint32_t)fbh != p->extent.height) {
    if ((r = recreate(p, &empty)) != PB_OK) return r;
    if (empty) return PB_OK;
  }
  VK(vkWaitForFences(p->device, 1, &p->fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  if ((p->fw != width || p->fh != height) && (r = make_frame(p, width, height)) != PB_OK) return r;
  uint32_t index;
  VkResult vr = vkAcquireNextImageKHR(p->device, p->swapchain, UINT64_MAX, p->acquired, VK_NULL_HANDLE, &index);
  if (vr == VK_ERROR_OUT_OF_DATE_KHR) return recreate(p, &empty); /* shown next time, on the new one */
  int suboptimal = vr == VK_SUBOPTIMAL_KHR;
  if (vr != VK_SUCCESS && !suboptimal) VK(vr, "vkAcquireNextImageKHR");
  VK(vkResetFences(p->device, 1, &p->fence), "vkResetFences");
  if (rgba) memcpy(p->staging_map, rgba, (size_t)width * height * 4);
  VK(vkResetCommandBuffer(p->cmd, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                 .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
  VK(vkBeginCommandBuffer(p->cmd, &bi), "vkBeginCommandBuffer");
  VkImage sw = p->images[index];
  barrier(p->cmd, p->frame, p->frame_fresh ? VK_IMAGE_LAYOUT_UNDEFINED : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
          VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_ACCESS_TRANSFER_READ_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
          VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
  p->frame_fresh = 0;
  VkBufferImageCopy copy = {.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1}, .imageExtent = {width, height, 1}};
  if (src) {
    /* The display pass's writes (an earlier submission on this queue) made
     * visible to the copy. */
    VkBufferMemoryBarrier bb = {.sType = VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER, .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
                                .dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT, .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED, .buffer = src, .offset = 0,
                                .size = VK_WHOLE_SIZE};
    vkCmdPipelineBarrier(p->cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL, 1, &bb,
                         0, NULL);
  }
  vkCmdCopyBufferToImage(p->cmd, src ? src : p->staging, p->frame, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
  barrier(p->cmd, p->frame, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
          VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
          VK_PIPELINE_STAGE_TRANSFER_BIT);
  barrier(p->cmd, sw, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_ACCESS_TRANSFER_WRITE_BIT,
          VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
  VkClearColorValue grey = {.float32 = {0.18f, 0.18f, 0.18f, 1.0f}};
  VkImageSubresourceRange all = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdClearColorImage(p->cmd, sw, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &grey, 1, &all);
  barrier(p->cmd, sw, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
          VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
          VK_PIPELINE_STAGE_TRANSFER_BIT);
  /* Letterbox: the largest rectangle of the frame's aspect that fits. */
  double sx = (double)p->extent.width / width, sy = (double)p->extent.height / height, s = sx < sy ? sx : sy;
  int32_t dw = (int32_t)(width * s + 0.5), dh = (int32_t)(height * s + 0.5);
  if (dw < 1) dw = 1;
  if (dh < 1) dh = 1;
  int32_t x0 = ((int32_t)p->extent.width - dw) / 2, y0 = ((int32_t)p->extent.height - dh) / 2;
  VkImageBlit blit = {.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
                      .srcOffsets = {{0, 0, 0}, {(int32_t)width, (int32_t)height, 1}},
                      .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
                      .dstOffsets = {{x0, y0, 0}, {x0 + dw, y0 + dh, 1}}};
  vkCmdBlitImage(p->cmd, p->frame, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, sw, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                 &blit, VK_FILTER_LINEAR);
  barrier(p->cmd, sw, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_ACCESS_TRANSFER_WRITE_BIT,
          0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
  VK(vkEndCommandBuffer(p->cmd), "vkEndCommandBuffer");
  VkPipelineStageFlags wait = VK_PIPELINE_STAGE_TRANSFER_BIT;
  VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .waitSemaphoreCount = 1, .pWaitSemaphores = &p->acquired,
                     .pWaitDstStageMask = &wait, .commandBufferCount = 1, .pCommandBuffers = &p->cmd,
                     .signalSemaphoreCount = 1, .pSignalSemaphores = &p->done[index]};
  VK(vkQueueSubmit(p->queue, 1, &si, p->fence), "vkQueueSubmit (present)");
  VkPresentInfoKHR pi = {.sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR, .waitSemaphoreCount = 1,
                         .pWaitSemaphores = &p->done[index], .swapchainCount = 1, .pSwapchains = &p->swapchain,
                         .pImageIndices = &index};
  vr = vkQueuePresentKHR(p->queue, &pi);
  if (vr == VK_ERROR_OUT_OF_DATE_KHR || vr == VK_SUBOPTIMAL_KHR || suboptimal) return recreate(p, &empty);
  VK(vr, "vkQueuePresentKHR");
  return PB_OK;
fail:
  return r;
}

pb_result pb_present_frame(pb_present *p, const uint8_t *rgba, uint32_t width, uint32_t height) {
  return present(p, rgba, VK_NULL_HANDLE, width, height);
}

pb_result pb_present_frame_buffer(pb_present *p, VkBuffer src, uint32_t width, uint32_t height) {
  if (!p->borrowed)
    return pb_fail(PB_ERR_USAGE, "view: a render-device buffer given to a presenter on its own device");
  return present(p, NULL, src, width, height);
}

uint32_t pb_present_validation_messages(const pb_present *p) { return p ? p->validation_messages : 0; }
uint32_t pb_present_recreations(const pb_present *p) { return p ? p->recreations : 0; }

int pb_present_shared(const pb_present *p) { return p->borrowed; }
