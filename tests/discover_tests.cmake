# Registers every Catch2 test case of one test executable with ctest, one
# ctest test per case, run in its own process. Called after each build of
# the executable (see tests/CMakeLists.txt) with:
#   EXE      the test executable
#   PREFIX   prefix of the ctest names ("test_part1: ")
#   LABELS   labels, separated by commas
#   WORKDIR  working directory of the tests
#   OUT      the ctest include file to write
# Tests exit with 77 to report "skipped" (e.g. course files absent).
execute_process(COMMAND "${EXE}" --list-test-names-only
                OUTPUT_VARIABLE listing RESULT_VARIABLE rc)
# Catch2 v2 returns the number of tests listed as its exit code.
if(rc MATCHES "^[^0-9]")
  message(FATAL_ERROR "${EXE} --list-test-names-only failed: ${rc}")
endif()
string(REPLACE "," ";" labels "${LABELS}")
set(labels_value "${labels}")
set(script "")
string(REPLACE "\n" ";" names "${listing}")
foreach(name IN LISTS names)
  if(name STREQUAL "")
    continue()
  endif()
  # Characters that Catch's test-spec syntax would misread.
  if(name MATCHES "[][;\\\\*\"]" OR name MATCHES "^[ -]" OR name MATCHES "^~")
    message(FATAL_ERROR "${EXE}: test name '${name}' contains a character Catch's name filter misreads "
                        "([, ], ;, \\, *, \", or a leading -, ~ or space); rename the test")
  endif()
  string(REPLACE "," "\\," filter "${name}")
  string(APPEND script
    "add_test([=[${PREFIX}${name}]=] \"${EXE}\" [=[${filter}]=] --warn NoTests)\n"
    "set_tests_properties([=[${PREFIX}${name}]=] PROPERTIES LABELS \"${labels_value}\" "
    "SKIP_RETURN_CODE 77 WORKING_DIRECTORY \"${WORKDIR}\")\n")
endforeach()
file(WRITE "${OUT}.new" "${script}")
file(RENAME "${OUT}.new" "${OUT}")
