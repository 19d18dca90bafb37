// The fuzz corpus replayed (fuzz/corpus/<target>/*: the seeds and every input that once found a
// bug): each input must be read or rejected with the reader's own error, without a crash or
// another exception (fuzz/fuzz_inputs.hpp). The same inputs run under libFuzzer with ASan and UBSan
// in the fuzz build (docs/reliability.md).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <functional>
#include <vector>

#include <unistd.h>

#include "fuzz/fuzz_inputs.hpp"
#include "geometry/mesh.hpp"
#include "geometry/tet_mesh.hpp"
#include "libsph/io/parameters.hpp"

namespace {

namespace fs = std::filesystem;

TEST(FuzzCorpus, EveryInputIsReadOrRejectedCleanly) {
  const fs::path corpus = fs::path(CARDIOSPH_SOURCE_DIR) / "fuzz" / "corpus";
  ASSERT_TRUE(fs::is_directory(corpus)) << corpus;
  for (const auto& target : cardiosph::fuzz::targets()) {
    const fs::path folder = corpus / target.name;
    ASSERT_TRUE(fs::is_directory(folder)) << "no corpus for target " << target.name << " in " << folder;
    std::size_t inputs = 0;
    for (const auto& file : fs::directory_iterator(folder)) {
      std::ifstream in(file.path(), std::ios::binary);
      const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
      SCOPED_TRACE(file.path().string());
      EXPECT_NO_THROW(target.run(bytes));
      ++inputs;
    }
    EXPECT_GT(inputs, 0u) << target.name;
    std::cout << "  " << target.name << ": " << inputs << " inputs replayed\n";
  }
}

}  // namespace

// The bugs the fuzzers found, each fixed at its cause; the inputs are also in the corpus.
namespace {

namespace fs = std::filesystem;

std::string error_of(const std::function<void()>& read) {
  try {
    read();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// A .vtu unstructured grid around `piece` (format version 0.1).
std::string vtu(const std::string& piece) {
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <UnstructuredGrid>\n" + piece + "  </UnstructuredGrid>\n</VTKFile>\n";
}

fs::path write_file(const std::string& name, const std::string& content) {
  const fs::path path = fs::temp_directory_path() / ("cardiosph_fuzz_regression_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

TEST(FuzzRegression, PlyHeaderWithAMalformedLineIsRefusedNotLoopedOn) {
  // assimp's PLY reader looped forever on this header (a count that is not a number, a misspelt
  // "property"); the header is now checked before assimp sees it.
  const auto path = write_file("bad.ply", "ply\nformat ascii 1.0\nelement vertex $mat.shading4\nproperty float x\nend_header\n0\n");
  const auto message = error_of([&] { geometry::read_mesh(path); });
  EXPECT_NE(message.find("not a valid PLY header: line 3"), std::string::npos) << message;
  const auto typo = write_file("typo.ply", "ply\nformat ascii 1.0\nelement vertex 1\nporpelty float x\nend_header\n0\n");
  EXPECT_NE(error_of([&] { geometry::read_mesh(typo); }).find("line 4"), std::string::npos);
  fs::remove(path);
  fs::remove(typo);
}

TEST(FuzzRegression, PlyWithBrokenFacesDoesNotAbortInAssimp) {
  // assimp's triangulation asserted (abort) on faces parsed from garbage after the vertices; the
  // polygons are now split here. Four vertices announced, three given, faces out of step.
  const auto path = write_file("faces.ply",
                               "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                               "element face 4\nproperty list uchar int vertex_indices\nend_header\n1 0 0\n0 1 0\n0 0 1\n"
                               "3 0 2 1\n3 0 1 3\nloat  2\n3 1 2 3\n");
  const auto message = error_of([&] { geometry::read_mesh(path); });
  EXPECT_TRUE(message.empty() || message.find("faces.ply") != std::string::npos) << message;
  // A quad is still read, as two triangles.
  const auto quad = write_file("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  EXPECT_EQ(geometry::read_mesh(quad).faces.size(), 2u);
  fs::remove(path);
  fs::remove(quad);
}

TEST(FuzzRegression, OpenCarpCountsBeyondTheFileAreRefused) {
  // "-inf" and "inf" counts were converted to long (undefined behaviour); a count of 1e12 reserved
  // terabytes. A count must be a whole number of entries that the file can hold.
  const auto elem = write_file("m.elem", "1\nTt 0 1 2 3 1\n");  // beside each m.pts below
  for (const std::string count : {"inf", "-inf", "nan", "1e12"}) {
    const auto pts = write_file("m.pts", count + "\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
    const auto message = error_of([&] { geometry::read_tet_mesh(pts); });
    EXPECT_NE(message.find("line 1"), std::string::npos) << count << ": " << message;
  }
  const auto pts = write_file("m.pts", "4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
  const auto tag = write_file("m.elem", "1\nTt 0 1 2 3 1e300\n");
  EXPECT_NE(error_of([&] { geometry::read_tet_mesh(pts); }).find("the tag 1e300 is not a whole number"), std::string::npos);
  fs::remove(pts);
  fs::remove(elem);
}

TEST(FuzzRegression, VtuCellOfUnknownTypeIsNamed) {
  // VTK returns no cell object for a type it does not know (92 here); it was dereferenced.
  const auto path = write_file("unknown.vtu", vtu(R"(    <Piece NumberOfPoints="4" NumberOfCells="2">
      <Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>
      <Cells>
        <DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 3 0 1 2</DataArray>
        <DataArray type="Int64" Name="offsets" format="ascii">4 7</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">10 92</DataArray>
      </Cells>
    </Piece>
)"));
  const auto message = error_of([&] { geometry::read_tet_mesh(path); });
  EXPECT_NE(message.find("cell 1 has the unknown VTK cell type 92"), std::string::npos) << message;
  fs::remove(path);
}

TEST(FuzzRegression, VtuSizesBeyondTheFileAreRefusedBeforeVtkAllocates) {
  // VTK spent minutes naming the components of NumberOfComponents="4444444444".
  const auto path = write_file("huge.vtu", vtu(R"(    <Piece NumberOfPoints="4" NumberOfCells="1">
      <PointData><DataArray type="Float64" Name="fibre" NumberOfComponents="4444444444" format="ascii">1 0 0</DataArray></PointData>
    </Piece>
)"));
  const auto message = error_of([&] { geometry::read_tet_mesh(path); });
  EXPECT_NE(message.find("NumberOfComponents = 4444444444 is more than the file can hold"), std::string::npos) << message;
  fs::remove(path);
}

TEST(FuzzRegression, VtuOffsetsBeyondMemoryAreABadMeshNotACrash) {
  // An offsets array whose last value is 4e17: VTK's allocation threw std::bad_alloc out of the reader.
  const auto path = write_file("offsets.vtu", vtu(R"(    <Piece NumberOfPoints="4" NumberOfCells="1">
      <Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>
      <Cells>
        <DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 3</DataArray>
        <DataArray type="Int64" Name="offsets" format="ascii">400000002119099905</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">10</DataArray>
      </Cells>
    </Piece>
)"));
  const auto message = error_of([&] { geometry::read_tet_mesh(path); });
  EXPECT_NE(message.find("offsets.vtu"), std::string::npos) << message;
  fs::remove(path);
}

TEST(FuzzRegression, VtuDataArrayOfUnknownFormatIsRefusedBeforeVtk) {
  // VTK dereferenced null reading a cell array whose format was "a>scii".
  const auto path = write_file("format.vtu", vtu(R"(    <Piece NumberOfPoints="4" NumberOfCells="1">
      <CellData><DataArray type="Int16" Name="region" format="a>scii">1</DataArray></CellData>
      <Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>
    </Piece>
)"));
  const auto message = error_of([&] { geometry::read_tet_mesh(path); });
  EXPECT_NE(message.find("a data array has format 'a>scii'"), std::string::npos) << message;
  fs::remove(path);
}

// A piece of two tetrahedra with the cell array `region` as given.
std::string two_tets(const std::string& region) {
  return vtu(R"(    <Piece NumberOfPoints="5" NumberOfCells="2">
      <CellData>)" + region + R"(</CellData>
      <Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1 1 1 1</DataArray></Points>
      <Cells>
        <DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 3 1 2 3 4</DataArray>
        <DataArray type="Int64" Name="offsets" format="ascii">4 8</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">10 10</DataArray>
      </Cells>
    </Piece>
)");
}

TEST(FuzzRegression, VtuShortCellArrayWithoutPointDataIsABadMeshNotACrash) {
  // A piece without PointData whose cell array is too short: VTK named the missing PointData element
  // in its error message and dereferenced null. A binary array (one Int16 value, base64 with its
  // UInt32 byte count) reaches VTK, which now reports it; the same piece with a full array reads.
  const auto short_path =
      write_file("short_cells.vtu", two_tets(R"(<DataArray type="Int16" Name="region" format="binary">AgAAAAEA</DataArray>)"));
  const auto message = error_of([&] { geometry::read_tet_mesh(short_path); });
  EXPECT_NE(message.find("short_cells.vtu"), std::string::npos) << message;
  EXPECT_NE(message.find("VTK cannot read it"), std::string::npos) << message;
  fs::remove(short_path);

  const auto full_path = write_file("full_cells.vtu", two_tets(R"(<DataArray type="Int16" Name="region" format="ascii">7 8</DataArray>)"));
  const auto mesh = geometry::read_tet_mesh(full_path);
  EXPECT_EQ(mesh.tets.size(), 2u);
  EXPECT_EQ(mesh.tet_region, (std::vector<int>{7, 8}));
  fs::remove(full_path);
}

TEST(FuzzRegression, VtuStructureIsCheckedBeforeVtkReadsIt) {
  // Inputs on which VTK's reader crashed (a cell array without a format beside a missing
  // connectivity array) or read past an array: each is refused with what is wrong.
  auto refused = [&](const std::string& content, const std::string& expected) {
    const auto path = write_file("structure.vtu", content);
    const auto message = error_of([&] { geometry::read_tet_mesh(path); });
    EXPECT_NE(message.find(expected), std::string::npos) << message;
    fs::remove(path);
  };
  refused(two_tets(R"(<DataArray type="Int16" Name="region" format="ascii">1</DataArray>)"),
          "the ascii array 'region' in piece 0 CellData holds 1 values, expected 2");
  refused(two_tets(R"(<DataArray type="Int16" Name="region">1 2</DataArray>)"), "a data array in piece 0 CellData has no format");
  refused(two_tets(R"(<DataArray type="Int16" Name="r" format="ascii">1 2</DataArray><DataArray type="Int16" Name="r" format="ascii">1 2</DataArray>)"),
          "piece 0 CellData has two arrays named 'r'");
  refused(two_tets(R"(<DataArray type="Int17" Name="r" format="ascii">1 2</DataArray>)"), "has the unknown type 'Int17'");
  std::string no_connectivity = two_tets("");
  no_connectivity.erase(no_connectivity.find("        <DataArray type=\"Int64\" Name=\"connectivity\""),
                        no_connectivity.find("        <DataArray type=\"Int64\" Name=\"offsets\"") -
                            no_connectivity.find("        <DataArray type=\"Int64\" Name=\"connectivity\""));
  refused(no_connectivity, "piece 0 Cells has no 'connectivity' array");
  std::string short_connectivity = two_tets("");
  short_connectivity.replace(short_connectivity.find("0 1 2 3 1 2 3 4"), 15, "0 1 2 3 1 2 3");
  refused(short_connectivity, "the ascii array 'connectivity' in piece 0 Cells holds 7 values, expected 8");
  refused(vtu("    <Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n    </Piece>\n  </Unstructured"), "malformed XML");
  // Counts spelt otherwise than key="value" (single quotes, spaces around '='), which VTK reads too.
  refused(two_tets(R"(<DataArray type="Int16" Name="r" NumberOfComponents='x' format="ascii">1 2</DataArray>)"),
          "NumberOfComponents = 'x' is not a count");
  refused(two_tets(R"(<DataArray type="Float32" Name="r" NumberOfComponents = '4444444444' format="binary">AAAA</DataArray>)"),
          "at most 64 components are read");
}

TEST(FuzzRegression, VtuCellOfAnotherTypeBeyondThePointsIsNamedBeforeVtkBuildsIt) {
  // A cell of type 79 (neither tetrahedron nor triangle) naming point 6666666666661 of 4: VTK read
  // the coordinates of that point while building the cell (SEGV). Its points are now checked first.
  const auto path = write_file("other_cell.vtu", vtu(R"(    <Piece NumberOfPoints="4" NumberOfCells="2">
      <Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>
      <Cells>
        <DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 3 0 6666666666661 2 3</DataArray>
        <DataArray type="Int64" Name="offsets" format="ascii">4 8</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">10 79</DataArray>
      </Cells>
    </Piece>
)"));
  const auto message = error_of([&] { geometry::read_tet_mesh(path); });
  EXPECT_NE(message.find("cell 1 refers to point 6666666666661 of 4"), std::string::npos) << message;
  fs::remove(path);
}

TEST(FuzzRegression, JsonNumberBeyondDoubleIsABadConfigNotACrash) {
  // nlohmann::json throws out_of_range (not parse_error) for 89e489; it escaped as a crash.
  sph::Parameters p;
  double x = 0;
  p.add("x", x, "1", "x", sph::Range::any());
  const auto message = error_of([&] { p.load_text("{\"x\": 89e489}", "json", "c.json"); });
  EXPECT_NE(message.find("config file 'c.json' is not valid JSON"), std::string::npos) << message;
}

}  // namespace
