# Test tutorial_settling_column: run the tutorial driver with a small system for a short time and
# check that it succeeds and writes its energy file and ParaView collection. With -DSOURCE and -DDOC
# it also checks that the documentation still shows the tutorial source verbatim.
#   cmake -DPROGRAM=path/to/SettlingColumn -DWORK_DIR=dir [-DSOURCE=file.cc -DDOC=file.md] -P RunTutorial.cmake
foreach(v PROGRAM WORK_DIR)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "RunTutorial.cmake: -D${v}=... is required")
  endif()
endforeach()

file(REMOVE_RECURSE ${WORK_DIR})
execute_process(
  COMMAND ${PROGRAM} --particles 200 --time_max 0.05 --output ${WORK_DIR} --quiet --threads 1
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "SettlingColumn exited with '${rc}' (expected 0)")
endif()
foreach(f SettlingColumn.ene SettlingColumn.pvd SettlingColumn.restart)
  if(NOT EXISTS ${WORK_DIR}/${f})
    message(FATAL_ERROR "SettlingColumn did not write ${WORK_DIR}/${f}")
  endif()
endforeach()
message(STATUS "tutorial_settling_column: exit 0, output in ${WORK_DIR}")

if(DEFINED SOURCE AND DEFINED DOC)
  file(READ "${SOURCE}" src)
  file(READ "${DOC}" doc)
  string(FIND "${doc}" "${src}" pos)
  if(pos EQUAL -1)
    message(FATAL_ERROR "${DOC} no longer shows ${SOURCE} verbatim: update the listing in the document")
  endif()
endif()
