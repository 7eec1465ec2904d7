/* Placeholder until the Sobol generator lands. */
#include <stdio.h>
int main(int argc, char **argv) {
  if (argc < 3) return 1;
  FILE *f = fopen(argv[2], "w");
  if (!f) return 1;
  fputs("const int clr_sobol_placeholder = 0;\n", f);
  return fclose(f) != 0;
}
