// libFuzzer harness: OSM XML buildings (planning::ReadOsmBuildings on a .osm file).
#define UASCMA_FUZZ_OSM_SUFFIX ".osm"
#include "osm_fuzzer.inc"
