# crex_set_warnings(target): the project's warning set. Generated code does not use it.
function(crex_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow -Wnon-virtual-dtor
                                           -Wold-style-cast -Wpedantic)
  # GCC 12 warns -Wrestrict inside std::string's operator+ at -O2 where nothing overlaps
  # (GCC bugs 105329 and 105651, fixed in 13): off for that compiler only.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_GREATER_EQUAL 12
     AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    target_compile_options(${target} PRIVATE -Wno-restrict)
  endif()
endfunction()
