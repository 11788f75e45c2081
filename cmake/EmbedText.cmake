# Script mode: writes OUTPUT, a C++ source defining granstack::embedded::SYMBOL() with INPUT's text.
file(READ "${INPUT}" content)
string(FIND "${content}" ")granstack_embed\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${INPUT} contains the raw-string delimiter used for embedding")
endif()
file(WRITE "${OUTPUT}.tmp" "// Generated from ${INPUT}; edit that file, not this one.\n#include <string_view>\nnamespace granstack::embedded {\nstd::string_view ${SYMBOL}() {\n  static constexpr std::string_view text = R\"granstack_embed(${content})granstack_embed\";\n  return text;\n}\n}  // namespace granstack::embedded\n")
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUTPUT}.tmp")
