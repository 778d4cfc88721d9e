/* One entry point per subcommand, one file each (cmd_*.c). */
#ifndef PB_COMMANDS_H
#define PB_COMMANDS_H

int pb_cmd_info(int argc, char **argv);
int pb_cmd_display(int argc, char **argv);
int pb_cmd_export_pov(int argc, char **argv);

#endif
