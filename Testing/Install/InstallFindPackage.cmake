# Test install_find_package: install this build into a temporary prefix, build an out-of-tree driver
# against it with find_package(PowderDPM), and run that driver briefly.
#   cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DGENERATOR=... -DCXX_COMPILER=...
#         -DBUILD_TYPE=... [-DCXX_FLAGS=...] [-DLINK_FLAGS=...] [-DVTK_DIR=...] [-DEIGEN_DIR=...]
#         -P InstallFindPackage.cmake
# Layout of WORK_DIR: prefix/ (the installation), src/ (the project), build/, out/ (its output).
foreach(v BUILD_DIR SOURCE_DIR WORK_DIR GENERATOR CXX_COMPILER)
  if(NOT DEFINED ${v} OR "${${v}}" STREQUAL "")
    message(FATAL_ERROR "InstallFindPackage.cmake: -D${v}=... is required")
  endif()
endforeach()

# Runs a command; stops the test with its output if it fails.
function(step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install_find_package: ${what} failed (${rc})\n${out}\n${err}")
  endif()
  message(STATUS "install_find_package: ${what}: ok")
endfunction()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/src)

# 1. Install.
step("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(f PowderDPMConfig.cmake PowderDPMConfigVersion.cmake PowderDPMTargets.cmake)
  file(GLOB_RECURSE found ${prefix}/*/${f})
  if(NOT found)
    message(FATAL_ERROR "install_find_package: ${f} was not installed under ${prefix}")
  endif()
endforeach()

# 2. The out-of-tree project: its CMakeLists and a copy of the tutorial driver.
file(COPY ${SOURCE_DIR}/Testing/Install/OutOfTree/CMakeLists.txt
          ${SOURCE_DIR}/Drivers/Tutorial/SettlingColumn.cc
     DESTINATION ${WORK_DIR}/src)

# 3. Configure against the prefix only (no package registry), same compiler and build type.
set(args -S ${WORK_DIR}/src -B ${WORK_DIR}/build -G ${GENERATOR}
    -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
    -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
if(BUILD_TYPE)
  list(APPEND args -DCMAKE_BUILD_TYPE=${BUILD_TYPE})
endif()
if(CXX_FLAGS)
  list(APPEND args "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}")
endif()
if(LINK_FLAGS)
  list(APPEND args "-DCMAKE_EXE_LINKER_FLAGS=${LINK_FLAGS}")
endif()
if(VTK_DIR)
  list(APPEND args -DVTK_DIR=${VTK_DIR})
endif()
if(EIGEN_DIR)
  list(APPEND args -DEigen3_DIR=${EIGEN_DIR})
endif()
step("configure with find_package(PowderDPM)" ${CMAKE_COMMAND} ${args})

# The package must come from the prefix, not from the build tree.
file(STRINGS ${WORK_DIR}/build/CMakeCache.txt dirLine REGEX "^PowderDPM_DIR:")
string(REGEX REPLACE "^PowderDPM_DIR:[A-Z]+=" "" pkgDir "${dirLine}")
file(REAL_PATH "${pkgDir}" pkgDir)
file(REAL_PATH "${prefix}" realPrefix)
string(FIND "${pkgDir}" "${realPrefix}/" pos)
if(NOT pos EQUAL 0)
  message(FATAL_ERROR "install_find_package: PowderDPM_DIR is '${pkgDir}', not inside ${realPrefix}")
endif()

# 4. Build and run briefly.
step("build" ${CMAKE_COMMAND} --build ${WORK_DIR}/build)
file(GLOB_RECURSE exe ${WORK_DIR}/build/SettlingColumn)
if(NOT exe)
  message(FATAL_ERROR "install_find_package: no SettlingColumn executable in ${WORK_DIR}/build")
endif()
list(GET exe 0 exe)
step("run" ${exe} --particles 100 --time_max 0.02 --output ${WORK_DIR}/out --quiet --threads 1)
foreach(f SettlingColumn.ene SettlingColumn.pvd)
  if(NOT EXISTS ${WORK_DIR}/out/${f})
    message(FATAL_ERROR "install_find_package: the installed-package driver did not write ${f}")
  endif()
endforeach()
