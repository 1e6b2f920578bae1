// fuzz_osm_seeds DIR_XML DIR_PBF — writes the seed inputs of the OSM fuzzers: a little city block as
// OSM XML (a building way with a height, a multipolygon building with a courtyard, a building with
// levels only, a road and a tagged node), and the same data as PBF, compressed and uncompressed (the
// uncompressed blob lets the fuzzer reach the PBF decoder without first getting through zlib).
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include <osmium/io/any_input.hpp>
#include <osmium/io/any_output.hpp>

namespace {

constexpr const char* kCityBlock = R"(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6" generator="uascma fuzz seeds">
  <node id="1" version="1" lat="40.7500" lon="-73.9800"/>
  <node id="2" version="1" lat="40.7500" lon="-73.9792"/>
  <node id="3" version="1" lat="40.7506" lon="-73.9792"/>
  <node id="4" version="1" lat="40.7506" lon="-73.9800"/>
  <node id="5" version="1" lat="40.7510" lon="-73.9800"/>
  <node id="6" version="1" lat="40.7510" lon="-73.9785"/>
  <node id="7" version="1" lat="40.7518" lon="-73.9785"/>
  <node id="8" version="1" lat="40.7518" lon="-73.9800"/>
  <node id="9" version="1" lat="40.7512" lon="-73.9795"/>
  <node id="10" version="1" lat="40.7512" lon="-73.9790"/>
  <node id="11" version="1" lat="40.7515" lon="-73.9790"/>
  <node id="12" version="1" lat="40.7515" lon="-73.9795"/>
  <node id="13" version="1" lat="40.7520" lon="-73.9800"/>
  <node id="14" version="1" lat="40.7520" lon="-73.9796"/>
  <node id="15" version="1" lat="40.7523" lon="-73.9796"/>
  <node id="20" version="1" lat="40.7503" lon="-73.9797"><tag k="amenity" v="cafe"/></node>
  <way id="100" version="1"><nd ref="1"/><nd ref="2"/><nd ref="3"/><nd ref="4"/><nd ref="1"/>
    <tag k="building" v="office"/><tag k="height" v="61.5 m"/></way>
  <way id="101" version="1"><nd ref="5"/><nd ref="6"/><nd ref="7"/><nd ref="8"/><nd ref="5"/></way>
  <way id="102" version="1"><nd ref="9"/><nd ref="10"/><nd ref="11"/><nd ref="12"/><nd ref="9"/></way>
  <way id="103" version="1"><nd ref="13"/><nd ref="14"/><nd ref="15"/><nd ref="13"/>
    <tag k="building" v="yes"/><tag k="building:levels" v="6"/></way>
  <way id="104" version="1"><nd ref="4"/><nd ref="5"/><nd ref="13"/><tag k="highway" v="footway"/></way>
  <relation id="200" version="1"><member type="way" ref="101" role="outer"/>
    <member type="way" ref="102" role="inner"/>
    <tag k="type" v="multipolygon"/><tag k="building" v="yes"/><tag k="height" v="33"/></relation>
</osm>
)";

void Convert(const std::filesystem::path& xml, const std::filesystem::path& pbf, const std::string& format) {
  osmium::io::Reader reader{xml.string()};
  osmium::io::Writer writer{osmium::io::File{pbf.string(), format}, reader.header(), osmium::io::overwrite::allow};
  while (osmium::memory::Buffer buffer = reader.read()) writer(std::move(buffer));
  writer.close();
  reader.close();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: fuzz_osm_seeds DIR_XML DIR_PBF\n";
    return 2;
  }
  const std::filesystem::path xml_dir = argv[1], pbf_dir = argv[2];
  std::filesystem::create_directories(xml_dir);
  std::filesystem::create_directories(pbf_dir);
  const std::filesystem::path xml = xml_dir / "city-block.osm";
  std::ofstream(xml) << kCityBlock;
  Convert(xml, pbf_dir / "city-block.osm.pbf", "pbf");
  Convert(xml, pbf_dir / "city-block-uncompressed.osm.pbf", "pbf,pbf_compression=none");
  return 0;
}
