# CREX_SANITIZE=ON: every target in the tree is built with ASan + UBSan, and UB aborts.
if(CREX_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined
                      -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
