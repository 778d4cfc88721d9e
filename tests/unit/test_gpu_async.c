/* Frames in flight at the GPU API (gpu.h): pb_gpu_submit_async
 * leaves a submission pending, and the host cannot race it: a download sees
 * what the pending copy wrote, an upload does not overwrite what the pending
 * copy has yet to read (a large one waits, a small one is recorded after
 * it), a begin records into another context of the ring without waiting
 * while the queue keeps the order, a destroy does not free what it uses
 * (validation layers on: a destroyed in-use buffer is a message). Exit 77
 * without a device. */
#include <stdlib.h>
#include <string.h>

#include "gpu/gpu.h"
#include "pbtest.h"
#include "gpu_test.h"

enum { N = 1u << 20 }; /* 4 MiB a buffer: a copy lavapipe does not finish at once */

static void fill(uint32_t *p, uint32_t seed) {
  for (uint32_t i = 0; i < N; ++i) p[i] = seed * 2654435761u + i;
}

static int same(const uint32_t *a, const uint32_t *b) { return memcmp(a, b, (size_t)N * sizeof *a) == 0; }

int main(void) {
  PBT_GPU_OPEN(g);
  uint32_t *old = malloc((size_t)N * 4), *fresh = malloc((size_t)N * 4), *got = malloc((size_t)N * 4);
  CHECK(old && fresh && got);
  if (!old || !fresh || !got) return pbt_done();
  fill(old, 1);
  fill(fresh, 2);
  pb_gpu_buffer a, b;
  pb_gpu_buffer_desc ad = {.name = "test.async.src", .size = (uint64_t)N * 4, .host_visible = 1};
  pb_gpu_buffer_desc bd = {.name = "test.async.dst", .size = (uint64_t)N * 4, .host_visible = 1, .readback = 1};
  CHECK_EQ_INT(pb_gpu_buffer_create(g, &ad, &a), PB_OK);
  CHECK_EQ_INT(pb_gpu_buffer_create(g, &bd, &b), PB_OK);
  CHECK_EQ_INT(pb_gpu_buffer_upload(g, &a, 0, old, (uint64_t)N * 4), PB_OK);
  CHECK_EQ_INT(pb_gpu_pending(g), 0);

  /* A download after an asynchronous copy waits for it. */
  CHECK_EQ_INT(pb_gpu_begin(g), PB_OK);
  pb_gpu_copy(g, &a, 0, &b, 0, (uint64_t)N * 4);
  CHECK_EQ_INT(pb_gpu_submit_async(g), PB_OK);
  CHECK_EQ_INT(pb_gpu_pending(g), 1);
  CHECK_EQ_INT(pb_gpu_buffer_download(g, &b, 0, got, (uint64_t)N * 4), PB_OK);
  CHECK_EQ_INT(pb_gpu_pending(g), 0);
  CHECK(same(got, old));

  /* An upload into the copy's source waits until the copy has read it. */
  CHECK_EQ_INT(pb_gpu_buffer_fill_zero(g, &b), PB_OK);
  CHECK_EQ_INT(pb_gpu_begin(g), PB_OK);
  pb_gpu_copy(g, &a, 0, &b, 0, (uint64_t)N * 4);
  CHECK_EQ_INT(pb_gpu_submit_async(g), PB_OK);
  CHECK_EQ_INT(pb_gpu_buffer_upload(g, &a, 0, fresh, (uint64_t)N * 4), PB_OK);
  CHECK_EQ_INT(pb_gpu_buffer_download(g, &b, 0, got, (uint64_t)N * 4), PB_OK);
  CHECK(same(got, old)); /* the copy read the old contents, all of them */

  /* pb_gpu_wait: waits once; a second call and a call with nothing pending
   * do nothing. */
  CHECK_EQ_INT(pb_gpu_begin(g), PB_OK);
  pb_gpu_copy(g, &a, 0, &b, 0, (uint64_t)N * 4);
  CHECK_EQ_INT(pb_gpu_submit_async(g), PB_OK);
  CHECK_EQ_INT(pb_gpu_wait(g), PB_OK);
  CHECK_EQ_INT(pb_gpu_pending(g), 0);
  CHECK_EQ_INT(pb_gpu_wait(g), PB_OK);
  CHECK_EQ_INT(pb_gpu_buffer_download(g, &b, 0, got, (uint64_t)N * 4), PB_OK);
  CHECK(same(got, fresh));

  /* The submission ring (gpu.h PB_GPU_FRAMES): a begin after an asynchronous
   * submission records into another context without waiting for it, and
   * the queue still runs the two in order: the second copy reads what the
   * first wrote (run the other way round, c would hold zeros). */
  pb_gpu_buffer c;
  pb_gpu_buffer_desc cd = {.name = "test.async.third", .size = (uint64_t)N * 4, .host_visible = 1, .readback = 1};
  CHECK_EQ_INT(pb_gpu_buffer_create(g, &cd, &c), PB_OK);
  CHECK_EQ_INT(pb_gpu_buffer_upload(g, &a, 0, old, (uint64_t)N * 4), PB_OK);
  CHECK_EQ_INT(pb_gpu_buffer_fill_zero(g, &b), PB_OK);
  CHECK_EQ_INT(pb_gpu_buffer_fill_zero(g, &c), PB_OK);
  pb_gpu_ring_stats r0 = pb_gpu_ring_stats_get(g);
  CHECK_EQ_INT(pb_gpu_begin(g), PB_OK);
  pb_gpu_copy(g, &a, 0, &b, 0, (uint64_t)N * 4);
  CHECK_EQ_INT(pb_gpu_submit_async(g), PB_OK);
  uint64_t first = pb_gpu_last_submission(g);
  CHECK_EQ_INT(pb_gpu_begin(g), PB_OK);
  CHECK_EQ_INT(pb_gpu_pending(g), 1);      /* not waited for */
  CHECK(pb_gpu_outstanding(g, first));
  pb_gpu_copy(g, &b, 0, &c, 0, (uint64_t)N * 4);
  CHECK_EQ_INT(pb_gpu_submit_async(g), PB_OK);
  CHECK_EQ_INT(pb_gpu_ring_stats_get(g).begin_waits, r0.begin_waits);
  /* A small upload while they are pending is recorded for the next command
   * buffer instead of waiting: the copies read a's old contents. */
  CHECK_EQ_INT(pb_gpu_buffer_upload(g, &a, 0, fresh, 4096), PB_OK);
  CHECK_EQ_INT(pb_gpu_pending(g), 1);
  CHECK_EQ_INT(pb_gpu_ring_stats_get(g).deferred_writes, r0.deferred_writes + 1);
  CHECK_EQ_INT(pb_gpu_buffer_download(g, &c, 0, got, (uint64_t)N * 4), PB_OK); /* waits for both, then writes a */
  CHECK_EQ_INT(pb_gpu_pending(g), 0);
  CHECK(same(got, old));
  CHECK_EQ_INT(pb_gpu_buffer_download(g, &a, 0, got, (uint64_t)N * 4), PB_OK);
  CHECK(memcmp(got, fresh, 4096) == 0 && memcmp(got + 1024, old + 1024, (size_t)(N - 1024) * 4) == 0);
  pb_gpu_release(g, first);
  pb_gpu_release(g, pb_gpu_last_submission(g));
  pb_gpu_buffer_destroy(g, &c);

  /* Destroying a buffer a pending submission uses waits for it
   * (validation would report vkDestroyBuffer on a buffer in use). */
  CHECK_EQ_INT(pb_gpu_begin(g), PB_OK);
  pb_gpu_copy(g, &a, 0, &b, 0, (uint64_t)N * 4);
  CHECK_EQ_INT(pb_gpu_submit_async(g), PB_OK);
  pb_gpu_buffer_destroy(g, &a);
  CHECK_EQ_INT(pb_gpu_pending(g), 0);
  pb_gpu_buffer_destroy(g, &b);
  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  pb_gpu_destroy(g);
  free(old);
  free(fresh);
  free(got);
  return pbt_done();
}
