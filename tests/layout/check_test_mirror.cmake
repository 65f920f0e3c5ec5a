# tests/ mirrors the code (tests/CMakeLists.txt, docs/architecture.md): every folder of tests with
# a CMakeLists.txt is tests/X/ for a code folder X/ of the tree, or one of the folders of tests
# that belong to no one code folder (below). Data folders (no CMakeLists.txt) are not tests.
#
# Usage: cmake -DROOT=<source tree> -P check_test_mirror.cmake. Prints every test folder with no
# code folder and fails; prints "test mirror: N folders, each a code folder's" otherwise.
cmake_minimum_required(VERSION 3.25)
if(NOT ROOT)
  message(FATAL_ERROR "usage: cmake -DROOT=<source tree> -P check_test_mirror.cmake")
endif()
set(of_no_folder system speed memory fuzz docs layout support)

file(GLOB_RECURSE lists LIST_DIRECTORIES false "${ROOT}/tests/*/CMakeLists.txt")
# The fixtures of tests/layout are trees of their own.
list(FILTER lists EXCLUDE REGEX "^${ROOT}/tests/layout/fixtures/")
list(SORT lists)
set(folders 0)
set(bad 0)
foreach(l IN LISTS lists)
  get_filename_component(dir "${l}" DIRECTORY)
  file(RELATIVE_PATH rel "${ROOT}/tests" "${dir}")
  math(EXPR folders "${folders} + 1")
  string(REGEX REPLACE "/.*" "" top "${rel}")
  if(top IN_LIST of_no_folder OR IS_DIRECTORY "${ROOT}/${rel}")
    continue()
  endif()
  message("tests/${rel}/: tests of no code folder (there is no ${rel}/; tests/ mirrors the code)")
  math(EXPR bad "${bad} + 1")
endforeach()
if(folders EQUAL 0)
  message(FATAL_ERROR "test mirror: no test folders under ${ROOT}/tests: nothing was checked")
endif()
if(bad GREATER 0)
  message(FATAL_ERROR "test mirror: ${bad} test folder(s) mirror no code folder")
endif()
message("test mirror: ${folders} folders, each a code folder's")
