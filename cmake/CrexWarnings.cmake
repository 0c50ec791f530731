# crex_set_warnings(target): the project's warning set. Generated code does not use it.
function(crex_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow -Wnon-virtual-dtor
                                           -Wold-style-cast -Wpedantic)
endfunction()
