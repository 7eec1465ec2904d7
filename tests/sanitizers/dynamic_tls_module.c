/* A dlopen()ed module with thread-local storage, as libpocl and libLLVM are under the ICD loader:
 * glibc gives each thread that touches it a malloc()ed block (dynamic TLS). */
__attribute__((visibility("default"))) char *dynamic_tls_touch(void);

static _Thread_local char block[8];

char *dynamic_tls_touch(void) {
  block[0] = 1;
  return block;
}
