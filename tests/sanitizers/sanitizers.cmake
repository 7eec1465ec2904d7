# Runtime options of the sanitized builds (CLR_ASAN=ON or CLR_FUZZ=ON), set on every CTest test
# (and inherited by the clrender processes tests start). scripts/test.sh exports the same.
#
# What PoCL needs under ASan (PoCL 3.1 with its LLVM 15 JIT, ocl-icd, Debian 12):
#  - detect_leaks stays on, but the ICD loader, PoCL, LLVM and Embree/TBB keep allocations
#    alive until exit (registries, caches, worker pools): lsan.supp suppresses leaks whose
#    stack contains those libraries, never clrender frames.
#  - PoCL dlopen()s its device drivers and the ICD loader dlopen()s PoCL; fast_unwind_on_malloc
#    stays on (frame pointers are kept, -fno-omit-frame-pointer).
#  - Kernels run on PoCL's pthread device, whose worker threads are not instrumented; no
#    other option is needed (protect_shadow_gap can stay on: PoCL's JIT maps its code with
#    mmap and never touches the shadow gap).
#  - halt_on_error/abort_on_error: every report fails the test; UBSan prints the stack.
set(CLR_SANITIZER_DIR ${CMAKE_CURRENT_LIST_DIR})
set(CLR_SANITIZER_ENV
  "ASAN_OPTIONS=detect_leaks=1:halt_on_error=1:abort_on_error=1:detect_stack_use_after_return=0:suppressions=${CLR_SANITIZER_DIR}/asan.supp"
  "LSAN_OPTIONS=suppressions=${CLR_SANITIZER_DIR}/lsan.supp:print_suppressions=0"
  "UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1:suppressions=${CLR_SANITIZER_DIR}/ubsan.supp")
if(NOT (CLR_ASAN OR CLR_FUZZ))
  set(CLR_SANITIZER_ENV "")
endif()
