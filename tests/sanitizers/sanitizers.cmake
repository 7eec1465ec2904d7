# Runtime options of the sanitized builds (CLR_ASAN=ON or CLR_FUZZ=ON), set on every CTest test
# (and inherited by the clrender processes tests start). scripts/test.sh exports the same.
#
# What PoCL needs under ASan (measured with Debian 12: PoCL 3.1 and its LLVM JIT, ocl-icd,
# Embree 3.13, GCC 12 and clang 14 sanitizer runtimes):
#  - Nothing special: the ICD loader dlopen()s libpocl, PoCL runs kernels on its pthread device
#    and JIT-compiles them with LLVM (or loads them from its kernel cache) without ASan reports;
#    protect_shadow_gap, allocator options and the like stay at their defaults.
#  - detect_leaks stays on. lsan.supp names only PoCL's, LLVM's and libstdc++'s modules, whose
#    kernel compiles keep allocations until exit; never clrender's code.
#  - intercept_tls_get_addr=0: with glibc >= 2.34 the runtimes' __tls_get_addr hook takes a
#    dynamic TLS block that starts 16 bytes past a page for a glibc 2.19 header and leak checks
#    then scan a wild range ("Tracer caught signal 11"). PoCL and LLVM are dlopen()ed, so their
#    thread-locals are such blocks: a CI fuzz run died so. tests/sanitizers/
#    test_leak_check_dynamic_tls fails without the option. The cost: a pointer held only in a
#    dlopen()ed module's thread-local is not a root; clrender's own thread-locals are static TLS.
#  - Every report fails its test: UB does not recover (-fno-sanitize-recover=all at build time),
#    ASan and UBSan stop at the first report with a failing status.
set(CLR_SANITIZER_DIR ${CMAKE_CURRENT_LIST_DIR})
set(CLR_SANITIZER_ENV
  "ASAN_OPTIONS=detect_leaks=1:intercept_tls_get_addr=0:halt_on_error=1:abort_on_error=1:suppressions=${CLR_SANITIZER_DIR}/asan.supp"
  "LSAN_OPTIONS=suppressions=${CLR_SANITIZER_DIR}/lsan.supp:print_suppressions=0"
  "UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1:suppressions=${CLR_SANITIZER_DIR}/ubsan.supp")
if(NOT (CLR_ASAN OR CLR_FUZZ))
  set(CLR_SANITIZER_ENV "")
endif()
