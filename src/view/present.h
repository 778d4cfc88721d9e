/* The viewer's window surface: a Vulkan swapchain on a GLFW window showing
 * an 8-bit image the host made (the display-referred picture through the
 * OCIO view, made from the readback's AOVs). The presenter uses the render
 * device (pb_gpu_vk: one VkDevice, its queue, from the viewer's one thread)
 * when the renderer was made for the window (pb_view_gpu_desc: the surface
 * extensions, a family that computes, blits and presents, VK_KHR_swapchain)
 * and its queue family can present to this surface; otherwise it makes its
 * own instance and device (on the physical device named like the
 * renderer's, else the first that can present) and logs why.
 *
 * Each present: the image is copied into a staging buffer, then into an
 * R8G8B8A8_UNORM image of the frame's size, which is blitted (linear
 * filter, aspect kept, the border cleared to grey) into the acquired
 * swapchain image. The swapchain's format is a UNORM one: the pixels are
 * display-encoded already (the OCIO view), an _SRGB format would encode
 * them twice. A 0 x 0 framebuffer (minimised) presents nothing;
 * VK_ERROR_OUT_OF_DATE_KHR and VK_SUBOPTIMAL_KHR recreate the swapchain;
 * VK_ERROR_DEVICE_LOST is PB_ERR_DEVICE_LOST. */
#ifndef PB_VIEW_PRESENT_H
#define PB_VIEW_PRESENT_H

#include <stdint.h>
#include <vulkan/vulkan.h>

#include "core/result.h"

typedef struct GLFWwindow GLFWwindow;
typedef struct pb_present pb_present;

typedef struct pb_present_desc {
  GLFWwindow *window;
  const char *device_name; /* preferred physical device (pb_gpu_device_name), or NULL */
  int validation;          /* 1: VK_LAYER_KHRONOS_validation, every message counted
                              (own device only: a shared one reports through pb_gpu) */
  const struct pb_gpu_vk *shared; /* the render device, or NULL */
} pb_present_desc;

pb_result pb_present_create(const pb_present_desc *d, pb_present **out);
void pb_present_destroy(pb_present *p);

/* Shows `rgba` (width x height, 4 bytes a pixel, top row first). */
pb_result pb_present_frame(pb_present *p, const uint8_t *rgba, uint32_t width, uint32_t height);

/* Shows the RGBA8 words (R in the low byte, width x height, top row
 * first) that a compute pass of the shared render device wrote into `src`
 * (present_pass.h, submitted and waited for): copied into the frame image
 * on the device, nothing through the host. Only when pb_present_shared;
 * PB_ERR_USAGE otherwise. */
pb_result pb_present_frame_buffer(pb_present *p, VkBuffer src, uint32_t width, uint32_t height);

/* Validation messages of the presenter's instance so far; swapchain
 * recreations so far (tests). */
uint32_t pb_present_validation_messages(const pb_present *p);
uint32_t pb_present_recreations(const pb_present *p);
/* 1: presenting through the render device (pb_present_desc.shared). */
int pb_present_shared(const pb_present *p);

#endif
