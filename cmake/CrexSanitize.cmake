# CREX_SANITIZE=ON: every target in the tree is built with ASan + UBSan, and UB aborts.
if(CREX_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined
                      -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
  # Executables not position-independent: a PIE crex under the sanitizers carried 1.1 million
  # relative relocations (27 MB), and applying them at every start was 0.1 s of each process's
  # 0.25 s; the sanitizer stage starts a few thousand processes (every test is one, and the CLI
  # tests start crex). The image plugin, a shared library, stays PIC.
  add_link_options($<$<STREQUAL:$<TARGET_PROPERTY:TYPE>,EXECUTABLE>:-no-pie>)
endif()

# CREX_FUZZ=ON (clang): instrument every library for coverage so libFuzzer is guided through
# the code under test, not only through the harness; the harnesses link -fsanitize=fuzzer.
if(CREX_FUZZ)
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
