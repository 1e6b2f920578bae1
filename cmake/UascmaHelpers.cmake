# One-line targets for uascma (CONTRIBUTING.md).
#
#   uascma_library(NAME SOURCES a.cc b.cc DEPS other_targets...)
#     builds uascma_NAME with alias uascma::NAME, public headers from include/, and
#     registers it in UASCMA_MODULES (the umbrella target uascma::uascma links them all).
#   uascma_test(NAME SOURCES a_test.cc DEPS ...)   a GoogleTest executable registered with CTest.
#   uascma_bench(NAME SOURCES a_bench.cc DEPS ...) a Google Benchmark executable in build/bench/.

set(UASCMA_MODULES "" CACHE INTERNAL "uascma module libraries")

function(uascma_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  set(target uascma_${name})
  add_library(${target} STATIC ${ARG_SOURCES})
  add_library(uascma::${name} ALIAS ${target})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
    $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/include>
    $<INSTALL_INTERFACE:include>)
  target_link_libraries(${target} PUBLIC ${ARG_DEPS})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  uascma_use_pch(${target})  # UascmaPch.cmake
  if(UASCMA_LTO_ACTIVE AND name IN_LIST UASCMA_LTO_MODULES)  # CMakeLists.txt, UASCMA_LTO
    target_compile_options(${target} PRIVATE -flto=auto -ffat-lto-objects)
  endif()
  if(UASCMA_UNITY)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${UASCMA_UNITY_BATCH})
  endif()
  install(TARGETS ${target} EXPORT uascmaTargets ARCHIVE DESTINATION lib)
  set(UASCMA_MODULES ${UASCMA_MODULES} ${target} CACHE INTERNAL "uascma module libraries")
endfunction()

# Links `target` (an executable) with link-time optimisation when UASCMA_LTO is active (CMakeLists.txt).
function(uascma_link_optimised target)
  if(UASCMA_LTO_ACTIVE)
    target_link_options(${target} PRIVATE -flto=auto)
  endif()
endfunction()

function(uascma_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main)
  uascma_use_test_pch(${name})  # UascmaPch.cmake
  # A test executable of several files compiles them as one unity file, as the libraries do (cmake/UascmaPch.cmake):
  # with the shared precompiled header a test file still costs ~3.4 CPU-s before its first line of its own
  # (GoogleTest's and the header's loading; measured on an empty test). Sources with options of their own (the lanes
  # tests' -ffp-contract=off) are compiled alone by CMake.
  if(UASCMA_UNITY)
    set_target_properties(${name} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${UASCMA_UNITY_BATCH})
  endif()
  target_compile_definitions(${name} PRIVATE
    UASCMA_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    UASCMA_CLI_PATH="$<TARGET_FILE:uascma_cli>")
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60
    PROPERTIES ENVIRONMENT "UASCMA_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
endfunction()

# Benchmarks are built by `make bench` (the target `benchmarks`), not by `make build`/`make test`, and are linked as
# the command-line tool is (link-time optimisation of the hot modules), so they measure the code that the tool runs.
function(uascma_bench name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} EXCLUDE_FROM_ALL ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} benchmark::benchmark)
  uascma_link_optimised(${name})
  if(NOT TARGET benchmarks)
    add_custom_target(benchmarks)
  endif()
  add_dependencies(benchmarks ${name})
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
endfunction()
