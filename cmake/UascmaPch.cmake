# Precompiled headers: the third-party and standard headers that most translation units include are
# parsed once per build instead of once per file. Measured on this tree (g++ 12, -O3, one header per file):
# CLI11 4.7 s, nlohmann/json 1.6 s, Eigen/Dense 1.2 s, yaml-cpp 0.8 s, fmt 0.5 s, <filesystem> 0.5 s.
#
# One precompiled header, built by the object library uascma_pch, is reused by every library (uascma_library,
# UascmaHelpers.cmake: the libraries share the compile flags it is built with); the command-line tool has its
# own (an executable compiles with -fPIE, not -fPIC) that adds CLI11. -DUASCMA_PCH=OFF builds without them,
# which also shows a source file that relies on a header only the precompiled header brings in.
# ccache caches files compiled with a precompiled header given sloppiness = pch_defines,time_macros; clang
# (scripts/fuzz.sh, scripts/check-sanitizers.sh) uses CMake's clang form of the same header.
# Unity builds of the libraries (ours, on by default): each library compiled as files of 8 sources each, which parse
# the shared headers and generate the inline code they use once per 8 files. Measured on the campaign library (22
# files): 93 s of compile CPU one by one, 46 s as 3 unity files. The sources of one library then share their
# anonymous namespaces, so file-local helpers have names unique within their library (two of one name either clash
# or, with other parameter types, silently overload). -DUASCMA_UNITY=OFF compiles each source alone, as
# scripts/check-sanitizers.sh and scripts/fuzz.sh do.
option(UASCMA_UNITY "Compile each library as unity files of 8 sources" ON)
option(UASCMA_PCH "Precompile the heavy third-party headers (Eigen, nlohmann/json, fmt, yaml-cpp; CLI11 for the CLI)" ON)

set(UASCMA_PCH_HEADERS
    <algorithm> <array> <cmath> <cstdint> <filesystem> <functional> <map> <memory> <optional> <set> <sstream>
    <string> <string_view> <utility> <vector>
    <Eigen/Dense> <fmt/format.h> <nlohmann/json.hpp> <yaml-cpp/yaml.h>)

if(UASCMA_PCH)
  file(WRITE ${PROJECT_BINARY_DIR}/uascma_pch.cc "// The translation unit the shared precompiled header is built for.\n")
  add_library(uascma_pch OBJECT ${PROJECT_BINARY_DIR}/uascma_pch.cc)
  # The same third-party targets (and so the same definitions, e.g. FMT_SHARED) as uascma::common, which every
  # library links.
  target_link_libraries(uascma_pch PRIVATE Eigen3::Eigen yaml-cpp nlohmann_json::nlohmann_json fmt::fmt
                        Threads::Threads)
  target_precompile_headers(uascma_pch PRIVATE ${UASCMA_PCH_HEADERS})
endif()

# uascma_use_pch(TARGET [CLI]): TARGET compiles with the shared precompiled header (a library), or, with CLI, with
# a precompiled header of its own that adds CLI11 (an executable).
function(uascma_use_pch target)
  cmake_parse_arguments(ARG "CLI" "" "" ${ARGN})
  if(NOT UASCMA_PCH)
    return()
  endif()
  if(ARG_CLI)
    target_precompile_headers(${target} PRIVATE ${UASCMA_PCH_HEADERS} <CLI/CLI.hpp>)
  else()
    target_precompile_headers(${target} REUSE_FROM uascma_pch)
  endif()
endfunction()

# uascma_use_test_pch(TARGET): the test executables share one precompiled header, the libraries' heavy headers plus
# GoogleTest, built with the first test (an executable: -fPIE, so it cannot reuse the libraries' -fPIC header).
# Without it every test file parses Eigen, nlohmann/json, yaml-cpp, fmt and gtest again.
function(uascma_use_test_pch target)
  if(NOT UASCMA_PCH)
    return()
  endif()
  get_property(owner GLOBAL PROPERTY UASCMA_TEST_PCH_OWNER)
  if(owner)
    target_precompile_headers(${target} REUSE_FROM ${owner})
  else()
    target_precompile_headers(${target} PRIVATE ${UASCMA_PCH_HEADERS} <gtest/gtest.h>)
    set_property(GLOBAL PROPERTY UASCMA_TEST_PCH_OWNER ${target})
  endif()
endfunction()
