# Script mode: writes OUTPUT with the granstack version and the git commit of SOURCE_DIR.
set(commit "unknown")
find_program(GIT git)
if(GIT)
  execute_process(COMMAND ${GIT} -C ${SOURCE_DIR} rev-parse HEAD OUTPUT_VARIABLE head RESULT_VARIABLE rc
                  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(rc EQUAL 0)
    set(commit "${head}")
    execute_process(COMMAND ${GIT} -C ${SOURCE_DIR} status --porcelain --untracked-files=no
                    OUTPUT_VARIABLE dirty ERROR_QUIET)
    if(dirty)
      set(commit "${commit}-dirty")
    endif()
  endif()
endif()
file(WRITE "${OUTPUT}.tmp" "// Generated at build time by cmake/WriteVersion.cmake.\n#include <granstack/model/version.hpp>\nnamespace granstack {\nstd::string_view version() { return \"${VERSION}\"; }\nstd::string_view git_commit() { return \"${commit}\"; }\n}  // namespace granstack\n")
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUTPUT}.tmp")
