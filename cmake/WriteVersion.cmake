# Writes OUTPUT from INPUT with the git description of SOURCE_DIR; touches nothing if unchanged.
execute_process(COMMAND git describe --always --dirty --tags
                WORKING_DIRECTORY ${SOURCE_DIR}
                OUTPUT_VARIABLE _describe OUTPUT_STRIP_TRAILING_WHITESPACE
                ERROR_QUIET RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0 OR _describe STREQUAL "")
  set(_describe "unknown-commit")
endif()
set(GRANFLOW_VERSION_STRING "${PROJECT_VERSION} (${_describe})")
string(LENGTH "${GRANFLOW_VERSION_STRING}" _len)
if(_len GREATER 95)
  string(SUBSTRING "${GRANFLOW_VERSION_STRING}" 0 95 GRANFLOW_VERSION_STRING)
endif()
configure_file(${INPUT} ${OUTPUT} @ONLY)
