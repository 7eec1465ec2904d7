/* Standalone driver for the fuzz targets (any compiler, no libFuzzer): runs every file named on
 * the command line, or found in a directory named there, through LLVMFuzzerTestOneInput. CTest
 * runs each target over its seed corpus and its regression inputs this way. Fails when no input
 * was found, so an empty or misplaced folder cannot pass silently. */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerInitialize(int *argc, char ***argv) __attribute__((weak));

/* libFuzzer reports a target that calls exit() as a crash; so does the replay. */
static int replay_finished;
static void fail_on_early_exit(void) {
  if (replay_finished) return;
  fprintf(stderr,
          "replay: the target exited during an input (libFuzzer: \"fuzz target exited\")\n");
  _exit(1);
}

static int run_file(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) {
    perror(path);
    exit(1);
  }
  size_t capacity = 4096, size = 0;
  uint8_t *data = malloc(capacity);
  for (;;) {
    if (!data) abort();
    size += fread(data + size, 1, capacity - size, f);
    if (size < capacity) break;
    capacity *= 2;
    data = realloc(data, capacity);
  }
  fclose(f);
  /* An exact-size copy, so reads past the end are caught as they are under libFuzzer. */
  uint8_t *exact = malloc(size ? size : 1);
  if (!exact) abort();
  memcpy(exact, data, size);
  free(data);
  printf("replay: %s (%zu bytes)\n", path, size);
  fflush(stdout);
  LLVMFuzzerTestOneInput(exact, size);
  free(exact);
  return 1;
}

static int compare(const void *a, const void *b) {
  return strcmp(*(char *const *)a, *(char *const *)b);
}

static int run_path(const char *path) {
  struct stat st;
  if (stat(path, &st) != 0) {
    perror(path);
    exit(1);
  }
  if (!S_ISDIR(st.st_mode)) return run_file(path);
  DIR *dir = opendir(path);
  if (!dir) {
    perror(path);
    exit(1);
  }
  char **names = NULL;
  size_t count = 0;
  for (struct dirent *e; (e = readdir(dir));) {
    if (e->d_name[0] == '.') continue; /* ., .., .gitkeep */
    names = realloc(names, (count + 1) * sizeof *names);
    size_t n = strlen(path) + strlen(e->d_name) + 2;
    if (!names || !(names[count] = malloc(n))) abort();
    snprintf(names[count++], n, "%s/%s", path, e->d_name);
  }
  closedir(dir);
  if (count > 1) qsort(names, count, sizeof *names, compare);
  int ran = 0;
  for (size_t i = 0; i < count; ++i) {
    ran += run_path(names[i]);
    free(names[i]);
  }
  free(names);
  return ran;
}

int main(int argc, char **argv) {
  if (LLVMFuzzerInitialize) LLVMFuzzerInitialize(&argc, &argv);
  atexit(fail_on_early_exit);
  int ran = 0;
  for (int i = 1; i < argc; ++i) ran += run_path(argv[i]);
  if (ran == 0) {
    fprintf(stderr, "replay: no inputs found\n");
    replay_finished = 1;
    return 1;
  }
  printf("replay: %d inputs ran cleanly\n", ran);
  replay_finished = 1;
  return 0;
}
