# CREX_SANITIZE=ON: every target in the tree is built with ASan + UBSan, and UB aborts.
if(CREX_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined
                      -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()

# CREX_FUZZ=ON (clang): instrument every library for coverage so libFuzzer is guided through
# the code under test, not only through the harness; the harnesses link -fsanitize=fuzzer.
if(CREX_FUZZ)
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
