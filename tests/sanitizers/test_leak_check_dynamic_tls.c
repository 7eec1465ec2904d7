/* LeakSanitizer must survive a leak check while a thread holds dynamic TLS. With clang 14's and
 * GCC 12's runtimes and glibc >= 2.34, intercepting __tls_get_addr reads a TLS block that sits
 * 16 bytes past a page boundary as a glibc 2.19 header, takes the allocator's chunk header for
 * its bounds and scans a wild range: "Tracer caught signal 11" (a CI fuzz run of fuzz_film died
 * so). sanitizers.cmake and scripts/fuzz.sh set intercept_tls_get_addr=0; without it this
 * program dies in its first leak check. Expects the options of the sanitized builds. */
#include <dlfcn.h>
#include <pthread.h>
#include <sanitizer/lsan_interface.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

static char *(*touch)(void);
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t changed = PTHREAD_COND_INITIALIZER;
static int touched, released;
/* A heap pointer hidden from LeakSanitizer by a mask, so the check must report it. */
static uintptr_t hidden;
static const uintptr_t mask = (uintptr_t)0xa5a5a5a5a5a5a5a5u;

static void *hold_dynamic_tls(void *unused) {
  (void)unused;
  touch();
  pthread_mutex_lock(&lock);
  touched = 1;
  pthread_cond_broadcast(&changed);
  while (!released) pthread_cond_wait(&changed, &lock);
  pthread_mutex_unlock(&lock);
  return NULL;
}

/* Allocates on another thread, which exits: no stack or register still holds the pointer. */
static void *allocate_hidden(void *unused) {
  (void)unused;
  hidden = (uintptr_t)malloc(48) ^ mask;
  return NULL;
}

static int fail(const char *what) {
  fprintf(stderr, "test_leak_check_dynamic_tls: %s\n", what);
  return 1;
}

int main(void) {
  void *module = dlopen(CLR_DYNAMIC_TLS_MODULE, RTLD_NOW);
  if (!module) return fail(dlerror());
  touch = (char *(*)(void))dlsym(module, "dynamic_tls_touch");
  if (!touch) return fail("dynamic_tls_touch not found");
  enum { threads = 4 };
  pthread_t thread[threads];
  for (int i = 0; i < threads; i++) {
    touched = 0;
    if (pthread_create(&thread[i], NULL, hold_dynamic_tls, NULL) != 0)
      return fail("pthread_create");
    pthread_mutex_lock(&lock);
    while (!touched) pthread_cond_wait(&changed, &lock);
    pthread_mutex_unlock(&lock);
  }
  int clean = __lsan_do_recoverable_leak_check();
  pthread_t allocator;
  if (pthread_create(&allocator, NULL, allocate_hidden, NULL) != 0) return fail("pthread_create");
  pthread_join(allocator, NULL);
  fprintf(stderr, "test_leak_check_dynamic_tls: a leak of 48 bytes is expected next\n");
  int leaked = __lsan_do_recoverable_leak_check();
  free((void *)(hidden ^ mask));
  pthread_mutex_lock(&lock);
  released = 1;
  pthread_cond_broadcast(&changed);
  pthread_mutex_unlock(&lock);
  for (int i = 0; i < threads; i++) pthread_join(thread[i], NULL);
  dlclose(module);
  if (clean != 0) return fail("the first leak check reported a leak");
  if (leaked != 1) return fail("the second leak check missed the hidden allocation");
  printf("test_leak_check_dynamic_tls: ok (clean check 0, hidden allocation found)\n");
  return 0;
}
