# crex_add_grammar(NAME grammar.g4): generate the C++ lexer/parser/visitor at build time.
#
# Debian's antlr4_generate() runs `java -jar antlr4.jar` and fails with NoClassDefFoundError,
# so we call the /usr/bin/antlr4 wrapper (it sets the classpath) directly. Generated code is
# never committed; it lands in the build tree under generated/<NAME>/.
find_program(ANTLR4_TOOL antlr4 REQUIRED)

function(crex_add_grammar name grammar_file)
  set(out_dir "${CMAKE_CURRENT_BINARY_DIR}/generated/${name}")
  set(outputs
      "${out_dir}/${name}Lexer.cpp" "${out_dir}/${name}Lexer.h"
      "${out_dir}/${name}Parser.cpp" "${out_dir}/${name}Parser.h"
      "${out_dir}/${name}Visitor.cpp" "${out_dir}/${name}Visitor.h"
      "${out_dir}/${name}BaseVisitor.cpp" "${out_dir}/${name}BaseVisitor.h")
  add_custom_command(
    OUTPUT ${outputs}
    COMMAND ${ANTLR4_TOOL} -Dlanguage=Cpp -visitor -no-listener -package crex::grammar
            -Xexact-output-dir -o "${out_dir}" "${grammar_file}"
    DEPENDS "${grammar_file}"
    COMMENT "ANTLR: generating the ${name} parser"
    VERBATIM)
  set(${name}_GENERATED_SOURCES ${outputs} PARENT_SCOPE)
  set(${name}_GENERATED_DIR "${out_dir}" PARENT_SCOPE)
endfunction()
