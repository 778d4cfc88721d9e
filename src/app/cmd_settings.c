/* photonbridge settings: the render settings table (render/settings.h) as a
 * user reads it (each setting's option, serve's key, range, default and
 * where it is offered), or as the Blender add-on's Python module
 * (--python). */
#include <stdio.h>
#include <string.h>

#include "app/cli.h"
#include "app/commands.h"
#include "render/settings.h"

static const pb_command *self(void) {
  for (size_t i = 0; i < pb_command_count; ++i)
    if (pb_commands[i].run == pb_cmd_settings) return &pb_commands[i];
  return NULL;
}

static void print_value(const pb_setting_info *t, double v) {
  if (t->kind == PB_SETTING_CHOICE) printf("%s", t->choices[(int)v]);
  else if (t->kind == PB_SETTING_BOOL) printf("%s", v != 0 ? "on" : "off");
  else printf("%.10g", v);
}

int pb_cmd_settings(int argc, char **argv) {
  const pb_command *cmd = self();
  int python = 0;
  const pb_opt opts[] = {
      {"python", 0, PB_OPT_FLAG, &python, NULL, "write the table as the Blender add-on's Python module "
       "(settings_table.py)", NULL, 0, 0, "Output", 0},
  };
  const char *pos[1];
  size_t npos;
  int help;
  pb_result r = pb_cli_parse(cmd, argc, argv, opts, sizeof opts / sizeof *opts, pos, 0, &npos, &help);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  if (help) {
    pb_cli_print_help(stdout, help, cmd, opts, sizeof opts / sizeof *opts,
                      "Every render setting once: its option (render, view, serve), its key in serve's\n"
                      "\"settings\" request, its range and default, and where it is offered.");
    return 0;
  }
  if (python) {
    pb_settings_write_python(stdout);
    return fflush(stdout) == 0 ? 0 : pb_cli_exit(cmd, pb_fail(PB_ERR_IO, "settings: stdout could not be written"));
  }
  static const char *const where[] = {"render", "view/serve", "serve requests", "Blender"};
  const char *group = "";
  for (int i = 0; i < PB_SETTING_COUNT; ++i) {
    const pb_setting_info *t = &pb_setting_table[i];
    if (strcmp(group, t->group) != 0) printf("%s%s:\n", i ? "\n" : "", group = t->group);
    printf("  --%s%s%s  (serve: \"%s\"", t->cli, t->metavar ? " " : "", t->metavar ? t->metavar : "", t->id);
    if (t->lo != 0 || t->hi != 0) printf(", %.10g to %.10g", t->lo, t->hi);
    if ((t->lo != 0 || t->hi != 0) && (t->def < t->lo || t->def > t->hi))
      printf(", default: automatic");  /* the help says what it resolves to */
    else {
      printf(", default ");
      print_value(t, t->def);
      if (t->flags & PB_SETTING_LIVE_OFF) printf("; view/serve: 0");
    }
    printf(")\n    offered in:");
    for (int b = 0, n = 0; b < 4; ++b)
      if (t->surfaces & (1u << b)) printf("%s %s", n++ ? "," : "", where[b]);
    printf("%s\n    ", t->flags & PB_SETTING_ADVANCED ? " (advanced)" : "");
    pb_cli_wrap(stdout, t->help, 4, 4, 80);
    printf("\n");
  }
  return fflush(stdout) == 0 ? 0 : pb_cli_exit(cmd, pb_fail(PB_ERR_IO, "settings: stdout could not be written"));
}
