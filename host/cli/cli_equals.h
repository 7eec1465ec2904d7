/* "--flag=value" -> "--flag" "value" for every subcommand. */
#ifndef CLR_CLI_EQUALS_H
#define CLR_CLI_EQUALS_H

typedef struct cli_args {
  int argc;
  char **argv;  /* NULL-terminated */
  char **owned; /* the split copies */
  int owned_count;
} cli_args;

/* argv[0] kept; each later "--name=value" split in two. 0 when out of memory. */
int cli_split_equals(int argc, char **argv, cli_args *out);
void cli_args_free(cli_args *args);

#endif
