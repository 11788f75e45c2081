# Shared build settings for granstack's libraries and programs.
function(granstack_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion)
  if(GRANSTACK_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# Embeds a text file (a template or a data table) into a C++ source as
# `std::string_view <symbol>()` in namespace granstack::embedded, so the installed program
# needs no data directory while the file itself stays the single source of truth in the tree.
function(granstack_embed_text target symbol file)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/embedded/${symbol}.cpp)
  add_custom_command(OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DINPUT=${file} -DOUTPUT=${out} -DSYMBOL=${symbol} -P ${PROJECT_SOURCE_DIR}/cmake/EmbedText.cmake
    DEPENDS ${file} ${PROJECT_SOURCE_DIR}/cmake/EmbedText.cmake
    COMMENT "Embedding ${file}")
  target_sources(${target} PRIVATE ${out})
endfunction()

function(granstack_library name)
  add_library(granstack_${name} ${ARGN})
  add_library(granstack::${name} ALIAS granstack_${name})
  target_include_directories(granstack_${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  granstack_warnings(granstack_${name})
endfunction()
