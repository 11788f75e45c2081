# The libraries' floors, lowest first: a library links only libraries on lower floors, never one
# on its own floor or above. The build checks the graph its CMake files link (granstack_check_layers,
# at configure time); run as a script it checks the links given, so that a test can show an
# upward link is refused:
#   cmake -DLINKS="formats>runner" -P cmake/CheckLayers.cmake
if(CMAKE_SCRIPT_MODE_FILE)
  cmake_policy(SET CMP0057 NEW)  # if(... IN_LIST ...)
endif()
set(GRANSTACK_FLOORS "os,model" "formats" "generator,refsim,postproc" "runner" "cluster" "study,design" "app")

# The floor of a library (its short name: formats, not granstack::formats), or -1 when it has none.
function(granstack_floor_of name out)
  set(floor 0)
  foreach(libraries IN LISTS GRANSTACK_FLOORS)
    string(REPLACE "," ";" libraries "${libraries}")
    if(name IN_LIST libraries)
      set(${out} ${floor} PARENT_SCOPE)
      return()
    endif()
    math(EXPR floor "${floor} + 1")
  endforeach()
  set(${out} -1 PARENT_SCOPE)
endfunction()

# LINKS: a list of "from>to" (short names). Stops with every link that goes sideways or up, and
# every library on no floor.
function(granstack_check_links links)
  set(problems "")
  foreach(link IN LISTS links)
    string(REPLACE ">" ";" ends "${link}")
    list(GET ends 0 from)
    list(GET ends 1 to)
    granstack_floor_of(${from} from_floor)
    granstack_floor_of(${to} to_floor)
    if(from_floor EQUAL -1 OR to_floor EQUAL -1)
      list(APPEND problems "  ${from} links ${to}: a library on no floor; give it one in cmake/CheckLayers.cmake")
    elseif(NOT to_floor LESS from_floor)
      list(APPEND problems "  ${from} (floor ${from_floor}) links ${to} (floor ${to_floor}): a library links only lower floors")
    endif()
  endforeach()
  if(problems)
    string(REPLACE ";" "\n" problems "${problems}")
    message(FATAL_ERROR "granstack's layering is broken:\n${problems}\nFloors, lowest first: ${GRANSTACK_FLOORS}")
  endif()
endfunction()

# Every granstack library and the program's commands (granstack_app, app/): the granstack libraries
# they link, public or private.
function(granstack_check_layers)
  set(links "")
  foreach(name os model formats generator refsim postproc runner cluster study design app)
    set(target granstack_${name})
    foreach(property LINK_LIBRARIES INTERFACE_LINK_LIBRARIES)
      get_target_property(deps ${target} ${property})
      foreach(dep IN LISTS deps)
        if(dep MATCHES "^granstack(::|_)([a-z]+)$")
          list(APPEND links "${name}>${CMAKE_MATCH_2}")
        endif()
      endforeach()
    endforeach()
  endforeach()
  list(REMOVE_DUPLICATES links)
  granstack_check_links("${links}")
  list(LENGTH links count)
  message(STATUS "granstack's layering: ${count} links between its libraries, every one down a floor")
endfunction()

if(CMAKE_SCRIPT_MODE_FILE AND DEFINED LINKS)
  granstack_check_links("${LINKS}")
  message(STATUS "layering kept: ${LINKS}")
endif()
