/* One entry point per subcommand, one file each (cmd_*.c). */
#ifndef PB_COMMANDS_H
#define PB_COMMANDS_H

#include "core/result.h"

int pb_cmd_info(int argc, char **argv);
int pb_cmd_render(int argc, char **argv);

struct pb_core_opts;
/* `info --devices`: the Vulkan devices, text or --json (info_devices.c). */
pb_result pb_info_devices(const struct pb_core_opts *c);
int pb_cmd_display(int argc, char **argv);
int pb_cmd_export_pov(int argc, char **argv);
int pb_cmd_export_peer(int argc, char **argv);
int pb_cmd_reference(int argc, char **argv);
int pb_cmd_compare(int argc, char **argv);
int pb_cmd_validate(int argc, char **argv);
int pb_cmd_view(int argc, char **argv);
int pb_cmd_serve(int argc, char **argv);
int pb_cmd_settings(int argc, char **argv);
int pb_cmd_batch(int argc, char **argv);

#endif
