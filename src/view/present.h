/* The viewer's window surface: a Vulkan swapchain on a GLFW window showing
 * an 8-bit image the host made (the frame API hands its pixels to the host
 * today: render.h's pb_render_result). The presenter owns its own instance
 * and device (on the physical device named like the renderer's, else the
 * first that can present), because pb_gpu is the headless compute runtime
 * and is being reworked by the GPU-resident frame (issue 17 item 1); once
 * frames stay on the GPU, the presenter should share that device and blit
 * from the frame's target instead of uploading.
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

#include "core/result.h"

typedef struct GLFWwindow GLFWwindow;
typedef struct pb_present pb_present;

typedef struct pb_present_desc {
  GLFWwindow *window;
  const char *device_name; /* preferred physical device (pb_gpu_device_name), or NULL */
  int validation;          /* 1: VK_LAYER_KHRONOS_validation, every message counted */
} pb_present_desc;

pb_result pb_present_create(const pb_present_desc *d, pb_present **out);
void pb_present_destroy(pb_present *p);

/* Shows `rgba` (width x height, 4 bytes a pixel, top row first). */
pb_result pb_present_frame(pb_present *p, const uint8_t *rgba, uint32_t width, uint32_t height);

/* Validation messages of the presenter's instance so far; swapchain
 * recreations so far (tests). */
uint32_t pb_present_validation_messages(const pb_present *p);
uint32_t pb_present_recreations(const pb_present *p);

#endif
