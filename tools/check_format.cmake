# ctest helper: fails when a tracked C++ source is not clang-formatted, or when clang-format
# itself is missing.
if(NOT CLANG_FORMAT OR NOT EXISTS "${CLANG_FORMAT}")
  message(FATAL_ERROR "clang-format not found: install it (Debian package clang-format; `make "
                      "test` does) to check the sources' format")
endif()
file(GLOB_RECURSE files ${ROOT}/src/*.cpp ${ROOT}/include/*.hpp ${ROOT}/tests/*.cpp ${ROOT}/bench/*.cpp)
set(bad "")
foreach(f ${files})
  execute_process(COMMAND ${CLANG_FORMAT} --dry-run -Werror ${f} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
  if(NOT rc EQUAL 0)
    list(APPEND bad ${f})
  endif()
endforeach()
if(bad)
  message(FATAL_ERROR "not clang-formatted (run `make format`):\n${bad}")
endif()
message(STATUS "all sources clang-formatted")
