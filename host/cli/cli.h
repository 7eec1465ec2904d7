/* clrender subcommands; each returns the process exit status (0 ok, 1 failure, 2 usage). */
#ifndef CLR_CLI_H
#define CLR_CLI_H

int cli_devices(int argc, char **argv);
int cli_render(int argc, char **argv);
int cli_samples(int argc, char **argv);
int cli_merge(int argc, char **argv);

#endif
