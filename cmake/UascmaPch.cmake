# Precompiled headers: the third-party and standard headers that most translation units include are
# parsed once per build instead of once per file. Measured on this tree (g++ 12, -O3, one header per file):
# CLI11 4.7 s, nlohmann/json 1.6 s, Eigen/Dense 1.2 s, yaml-cpp 0.8 s, fmt 0.5 s, <filesystem> 0.5 s.
#
# One precompiled header, built by the object library uascma_pch, is reused by every library (uascma_library,
# UascmaHelpers.cmake: the libraries share the compile flags it is built with) and by the command-line tool's objects
# (compiled position-independent like the libraries, so that they can reuse it; CLI11 is parsed in the tool's one
# unity file). -DUASCMA_PCH=OFF builds without it, which also shows a source file that relies on a header only the
# precompiled header brings in.
# ccache caches files compiled with a precompiled header given sloppiness = pch_defines,time_macros; clang
# (scripts/fuzz.sh, scripts/check-sanitizers.sh) uses CMake's clang form of the same header.
# Unity builds (ours, on by default): each library, the tool and each test executable is compiled as one file that
# includes all its sources (UASCMA_UNITY_BATCH = 0), so the shared headers are loaded and the inline and template
# code they use is generated once per library instead of once per source. Measured from nothing (GCC 12, -O3, the
# demo's libraries, compile by compile, on a shared machine): 516 CPU-s as unity files of 8 sources, 438 as one per
# library; the tool's commands 113 CPU-s as two unity files with a precompiled header of their own, ~63 as one (a
# build folder being worked in recompiles a whole library for a change to one of its files: -DUASCMA_UNITY_BATCH=8
# makes those recompiles smaller, at ~18 % more CPU from nothing). The sources of one library then share their anonymous
# namespaces, so file-local helpers have names unique within their library (two of one name either clash or, with
# other parameter types, silently overload). -DUASCMA_UNITY=OFF compiles each source alone, as
# scripts/check-sanitizers.sh and scripts/fuzz.sh do.
option(UASCMA_UNITY "Compile each library, the tool and each test executable as unity files" ON)
set(UASCMA_UNITY_BATCH 0 CACHE STRING "Sources per unity file (0: all sources of a target in one)")
option(UASCMA_PCH "Precompile the heavy third-party headers (Eigen, nlohmann/json, fmt, yaml-cpp)" ON)

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

# uascma_use_pch(TARGET): TARGET (a library, or the tool's position-independent objects) compiles with the shared
# precompiled header.
function(uascma_use_pch target)
  if(NOT UASCMA_PCH)
    return()
  endif()
  target_precompile_headers(${target} REUSE_FROM uascma_pch)
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
