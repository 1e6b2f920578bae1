// libFuzzer harness: OSM PBF buildings (planning::ReadOsmBuildings on a .osm.pbf file).
#define UASCMA_FUZZ_OSM_SUFFIX ".osm.pbf"
#include "osm_fuzzer.inc"
