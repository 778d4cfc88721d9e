/* The render settings on the command line (settings_opts.h). */
#include "app/settings_opts.h"

#include <string.h>

void pb_settings_opts(pb_settings *s, unsigned surface, pb_opt *out, size_t *n, size_t cap) {
  static const pb_opt_kind kinds[] = {PB_OPT_U32, PB_OPT_FLOAT, PB_OPT_FLAG, PB_OPT_CHOICE};
  for (int i = 0; i < PB_SETTING_COUNT && *n < cap; ++i) {
    const pb_setting_info *t = &pb_setting_table[i];
    if (!(t->surfaces & surface)) continue;
    pb_opt o = {.name = t->cli, .kind = kinds[t->kind], .target = (char *)s + t->offset, .metavar = t->metavar,
                .help = t->help, .choices = t->choices, .min = t->lo, .max = t->hi, .group = t->group,
                .advanced = t->flags & PB_SETTING_ADVANCED ? PB_OPT_ADVANCED : 0};
    if (t->kind == PB_SETTING_BOOL && t->def != 0) o.kind = PB_OPT_FLAG_CLEAR; /* --no-temporal */
    out[(*n)++] = o;
  }
}

void pb_settings_mark_given(pb_settings *s, const pb_opt *opts, const unsigned char *given, size_t n) {
  for (size_t k = 0; k < n; ++k)
    for (int i = 0; given[k] && i < PB_SETTING_COUNT; ++i)
      if (opts[k].target == (char *)s + pb_setting_table[i].offset) s->given |= 1ull << i;
}

void pb_opts_append(pb_opt *out, size_t *n, size_t cap, const pb_opt *rows, size_t count) {
  for (size_t i = 0; i < count && *n < cap; ++i) out[(*n)++] = rows[i];
}

const char *const pb_traversal_names[] = {"auto", "bvh", "ray-query", NULL};

void pb_live_opts_init(pb_live_opts *o) {
  memset(o, 0, sizeof *o);
  pb_settings_init_live(&o->set);
  o->device = UINT32_MAX;
}

pb_result pb_live_sequence_desc(const char *command, const pb_live_opts *o, uint64_t seed, pb_sequence_desc *d) {
  pb_result r = pb_settings_check(command, &o->set, 1);
  if (r != PB_OK) return r;
  memset(d, 0, sizeof *d);
  pb_settings_render_desc(&o->set, 1, &d->render);
  d->render.seed = seed;
  d->render.preview_interval_s = -1.0;
  d->temporal = o->set.temporal;
  d->bvh_update = PB_BVH_UPDATE_AUTO;
  return PB_OK;
}
