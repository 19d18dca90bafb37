// Tetrahedral meshes in VTK XML unstructured grids (.vtu), read and written through VTK.

#include "geometry/tet_mesh_vtk.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iterator>
#include <cstdlib>
#include <fstream>
#include <new>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCell.h>
#include <vtkCellTypes.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "libsph/io/vtk/vtu_writer.hpp"

namespace geometry::detail {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const fs::path& path, const std::string& problem) {
  throw MeshError("tetrahedral mesh '" + path.string() + "': " + problem);
}

// Collects VTK's error messages instead of letting them go to the terminal.
class ErrorCollector : public vtkCommand {
 public:
  static ErrorCollector* New() { return new ErrorCollector; }
  void Execute(vtkObject*, unsigned long, void* data) override {
    if (message.empty() && data) message = static_cast<const char*>(data);
  }
  std::string message;
};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool one_of(const std::string& name, std::initializer_list<const char*> names) {
  const std::string l = lower(name);
  return std::any_of(names.begin(), names.end(), [&](const char* n) { return l == n; });
}
constexpr auto fibre_names = {"fibre", "fiber", "fibres", "fibers", "f0", "fibre_direction", "fiber_direction"};
constexpr auto sheet_names = {"sheet", "sheets", "s0", "sheet_direction"};
constexpr auto region_names = {"region", "regions", "tag", "tags", "elemtag", "material", "gmsh:physical", "cell_region"};

// The first array of `data` whose name is one of `names`, or null.
vtkDataArray* find_array(vtkFieldData* data, std::initializer_list<const char*> names) {
  for (int k = 0; k < data->GetNumberOfArrays(); ++k) {
    vtkDataArray* a = data->GetArray(k);
    if (a && a->GetName() && one_of(a->GetName(), names)) return a;
  }
  return nullptr;
}

std::vector<Vec3> vectors(const fs::path& path, vtkDataArray* a, const std::vector<vtkIdType>& rows, const char* what) {
  if (a->GetNumberOfComponents() != 3)
    fail(path, std::string(what) + " array '" + a->GetName() + "' has " + std::to_string(a->GetNumberOfComponents()) +
                   " components, expected 3");
  std::vector<Vec3> out;
  out.reserve(rows.size());
  for (vtkIdType r : rows) {
    if (r >= a->GetNumberOfTuples())
      fail(path, std::string(what) + " array '" + a->GetName() + "' has " + std::to_string(a->GetNumberOfTuples()) +
                     " values, too few for its points or cells");
    double v[3];
    a->GetTuple(r, v);
    out.emplace_back(v[0], v[1], v[2]);
  }
  return out;
}

// A cell must have `corners` points, each a point of the grid.
void check_cell(const fs::path& path, vtkIdType cell, vtkIdType n, vtkIdType corners, const vtkIdType* ids, vtkIdType n_points) {
  if (n < corners || ids == nullptr)
    fail(path, "cell " + std::to_string(cell) + " has " + std::to_string(n) + " points, expected " + std::to_string(corners));
  for (vtkIdType k = 0; k < corners; ++k)
    if (ids[k] < 0 || ids[k] >= n_points)
      fail(path, "cell " + std::to_string(cell) + " refers to point " + std::to_string(ids[k]) + " of " + std::to_string(n_points));
}

// A cell of another type than tetrahedron or triangle, as VTK makes it (null for a type VTK does not
// know), once its points are checked: VTK reads the coordinates of every point the cell names.
vtkCell* other_cell(const fs::path& path, vtkUnstructuredGrid& grid, vtkIdType c) {
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  grid.GetCellPoints(c, n, ids);
  if (n > 0) check_cell(path, c, n, n, ids, grid.GetNumberOfPoints());
  return grid.GetCell(c);
}

// The formats and sizes a .vtu announces, checked before VTK reads them: VTK 9.1 creates a name for every
// component of an array and spends minutes (and gigabytes) on NumberOfComponents="4444444444".
// Arrays of up to 64 components are read (tensors have 9); the point and cell counts may not exceed
// what the file could hold, 1100 values per byte (zlib's largest compression ratio is about 1032).
void check_vtu_sizes(const fs::path& path, const std::string& text) {
  auto each = [&](const std::string& attribute, double limit) {
    const std::string key = attribute + "=\"";
    for (auto at = text.find(key); at != std::string::npos; at = text.find(key, at + 1)) {
      const auto start = at + key.size(), end = text.find('"', start);
      if (end == std::string::npos || end - start > 15) fail(path, attribute + " is not a count");
      const std::string value = text.substr(start, end - start);
      if (value.empty() || value.find_first_not_of("0123456789") != std::string::npos) fail(path, attribute + " = '" + value + "' is not a count");
      if (std::stod(value) > limit)
        fail(path, attribute + " = " + value + " is more than the file can hold" +
                       (attribute == "NumberOfComponents" ? " (at most 64 components are read)" : ""));
    }
  };
  // VTK 9.1 dereferences null on a DataArray whose format is none of the three it knows.
  const std::string key = "format=\"";
  for (auto at = text.find(key); at != std::string::npos; at = text.find(key, at + 1)) {
    const auto start = at + key.size(), end = text.find('"', start);
    const std::string value = end == std::string::npos ? text.substr(start, 20) : text.substr(start, std::min<std::size_t>(end - start, 20));
    if (value != "ascii" && value != "binary" && value != "appended")
      fail(path, "a data array has format '" + value + "' (ascii, binary or appended)");
  }
  each("NumberOfComponents", 64);
  each("NumberOfPoints", 1100.0 * double(text.size()));
  each("NumberOfCells", 1100.0 * double(text.size()));
}

// The element structure of a .vtu up to its appended data, checked before VTK reads it: VTK 9.1's XML
// reader dereferences null or reads past arrays on files that are well-formed XML but not a sound
// grid (a cell array shorter than the cells, a missing connectivity array, a data array without a
// format, two arrays of one name). Checked: one grid of pieces; in each piece one Points array of 3
// components and the Cells arrays connectivity, offsets and types, each once; every data array of a
// known type and format, its name unique beside it; and each ascii array holding exactly the values
// its piece announces (points x components, cells x components, the last offset for connectivity).
// Arrays in binary or appended form are sized by VTK from their own headers.
struct XmlElement {
  std::string name, text;
  std::vector<std::pair<std::string, std::string>> attributes;
  std::vector<std::size_t> children;
  const std::string* attribute(const std::string& key) const {
    for (const auto& [k, v] : attributes)
      if (k == key) return &v;
    return nullptr;
  }
};

std::vector<XmlElement> parse_elements(const fs::path& path, const std::string& text, std::size_t end) {
  std::vector<XmlElement> elements(1);  // 0: the document
  std::vector<std::size_t> open{0};
  auto malformed = [&](std::size_t at, const std::string& what) {
    fail(path, "malformed XML at byte " + std::to_string(at) + ": " + what);
  };
  std::size_t at = text.find('<');
  while (at < end) {
    if (text.compare(at, 4, "<!--") == 0) {
      const auto close = text.find("-->", at);
      if (close >= end) malformed(at, "unterminated comment");
      at = text.find('<', close);
      continue;
    }
    const auto close = text.find('>', at);
    if (close >= end) malformed(at, "unterminated tag");
    if (text[at + 1] == '?' || text[at + 1] == '!') {
      at = text.find('<', close);
      continue;
    }
    if (text[at + 1] == '/') {
      std::string name = text.substr(at + 2, close - at - 2);
      while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
      if (open.size() < 2 || elements[open.back()].name != name) malformed(at, "</" + name + "> closes nothing open");
      open.pop_back();
      at = text.find('<', close);
      continue;
    }
    const bool empty = text[close - 1] == '/';
    const std::string tag = text.substr(at + 1, close - at - 1 - (empty ? 1 : 0));
    XmlElement e;
    std::size_t k = 0;
    while (k < tag.size() && !std::isspace(static_cast<unsigned char>(tag[k]))) ++k;
    e.name = tag.substr(0, k);
    if (e.name.empty()) malformed(at, "a tag without a name");
    while (true) {
      while (k < tag.size() && std::isspace(static_cast<unsigned char>(tag[k]))) ++k;
      if (k >= tag.size()) break;
      const auto eq = tag.find('=', k);
      auto quote = eq == std::string::npos ? tag.size() : eq + 1;
      while (quote < tag.size() && std::isspace(static_cast<unsigned char>(tag[quote]))) ++quote;
      if (quote >= tag.size() || (tag[quote] != '"' && tag[quote] != '\'')) malformed(at, "an attribute without a quoted value");
      const auto quote_end = tag.find(tag[quote], quote + 1);
      if (quote_end == std::string::npos) malformed(at, "an unterminated attribute value");
      std::string key = tag.substr(k, eq - k);
      while (!key.empty() && std::isspace(static_cast<unsigned char>(key.back()))) key.pop_back();
      e.attributes.emplace_back(key, tag.substr(quote + 1, quote_end - quote - 1));
      k = quote_end + 1;
    }
    const std::size_t next = std::min(text.find('<', close), end);
    if (!empty) e.text = text.substr(close + 1, next - close - 1);
    elements.push_back(std::move(e));
    elements[open.back()].children.push_back(elements.size() - 1);
    if (!empty) open.push_back(elements.size() - 1);
    at = next;
  }
  return elements;
}

void check_vtu_structure(const fs::path& path, const std::string& text) {
  const std::size_t appended = std::min(text.find("<AppendedData"), text.size());
  const auto elements = parse_elements(path, text, appended);
  auto children = [&](const XmlElement& e, const std::string& name) {
    std::vector<const XmlElement*> out;
    for (auto c : e.children)
      if (elements[c].name == name) out.push_back(&elements[c]);
    return out;
  };
  // A count attribute (1 when absent). check_vtu_sizes has bounded the ones written key="value";
  // this parser also reads other spellings (single quotes, spaces around '='), so each is checked here.
  auto count_of = [&](const XmlElement& e, const char* key) -> long long {
    const auto* v = e.attribute(key);
    if (!v) return 1;
    if (v->empty() || v->size() > 15 || v->find_first_not_of("0123456789") != std::string::npos)
      fail(path, std::string(key) + " = '" + v->substr(0, 20) + "' is not a count");
    const long long count = std::stoll(*v);
    if (std::string(key) == "NumberOfComponents" && count > 64) fail(path, "NumberOfComponents = " + *v + " (at most 64 components are read)");
    if (double(count) > 1100.0 * double(text.size())) fail(path, std::string(key) + " = " + *v + " is more than the file can hold");
    return count;
  };
  static const std::initializer_list<const char*> types = {"Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64",
                                                           "UInt64", "Float32", "Float64", "String", "Bit"};
  // A data array: known type and format; an ascii one holds `values` numbers (negative: not checked).
  auto check_array = [&](const XmlElement& a, const std::string& where, long long rows) {
    const auto* type = a.attribute("type");
    if (!type || std::none_of(types.begin(), types.end(), [&](const char* t) { return *type == t; }))
      fail(path, "a data array in " + where + " has " + (type ? "the unknown type '" + *type + "'" : "no type"));
    const auto* format = a.attribute("format");
    if (!format) fail(path, "a data array in " + where + " has no format (ascii, binary or appended)");
    if (*format == "appended" && !a.attribute("offset")) fail(path, "an appended data array in " + where + " has no offset");
    const long long components = count_of(a, "NumberOfComponents");
    if (*format != "ascii" || rows < 0) return;
    const long long expected = rows * components;
    std::istringstream values(a.text);
    long long n = 0;
    for (std::string v; values >> v;) ++n;
    if (n != expected)
      fail(path, "the ascii array " + (a.attribute("Name") ? "'" + *a.attribute("Name") + "' " : std::string()) + "in " + where +
                     " holds " + std::to_string(n) + " values, expected " + std::to_string(expected));
  };
  auto unique_arrays = [&](const XmlElement& parent, const std::string& where, long long rows) {
    std::vector<std::string> names;
    for (const auto* a : children(parent, "DataArray")) {
      check_array(*a, where, rows);
      const std::string name = a->attribute("Name") ? *a->attribute("Name") : "";
      if (std::find(names.begin(), names.end(), name) != names.end()) fail(path, where + " has two arrays named '" + name + "'");
      names.push_back(name);
    }
  };
  const auto files = children(elements[0], "VTKFile");
  if (files.size() != 1) fail(path, "not one VTKFile element");
  const auto grids = children(*files[0], "UnstructuredGrid");
  if (grids.size() != 1) fail(path, "not one UnstructuredGrid element");
  const auto pieces = children(*grids[0], "Piece");
  if (pieces.empty()) fail(path, "no Piece");
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const auto& piece = *pieces[k];
    const std::string name = "piece " + std::to_string(k);
    const long long n_points = count_of(piece, "NumberOfPoints"), n_cells = count_of(piece, "NumberOfCells");
    if (!piece.attribute("NumberOfPoints") || !piece.attribute("NumberOfCells")) fail(path, name + " has no point or cell count");
    for (const char* part : {"PointData", "CellData", "Points", "Cells"})
      if (children(piece, part).size() > 1) fail(path, name + " has more than one " + part);
    for (const auto* d : children(piece, "PointData")) unique_arrays(*d, name + " PointData", n_points);
    for (const auto* d : children(piece, "CellData")) unique_arrays(*d, name + " CellData", n_cells);
    const auto points = children(piece, "Points");
    if (points.size() != 1 || children(*points[0], "DataArray").size() != 1) fail(path, name + " needs one Points array");
    const auto& coordinates = *children(*points[0], "DataArray")[0];
    if (count_of(coordinates, "NumberOfComponents") != 3) fail(path, name + ": the Points array needs 3 components");
    check_array(coordinates, name + " Points", n_points);
    const auto cells = children(piece, "Cells");
    if (cells.size() != 1) fail(path, name + " has no Cells");
    long long connectivity_length = -1;  // the last offset, when the offsets are ascii
    const XmlElement* connectivity = nullptr;
    std::vector<std::string> seen;
    for (const auto* a : children(*cells[0], "DataArray")) {
      const std::string array = a->attribute("Name") ? *a->attribute("Name") : "";
      if (std::find(seen.begin(), seen.end(), array) != seen.end()) fail(path, name + " Cells has two arrays named '" + array + "'");
      seen.push_back(array);
      if (array == "connectivity") {
        connectivity = a;
        check_array(*a, name + " Cells", -1);
      } else if (array == "offsets" || array == "types") {
        check_array(*a, name + " Cells", n_cells);
        if (array == "offsets" && *a->attribute("format") == "ascii" && n_cells > 0) {
          std::istringstream values(a->text);
          std::string last;
          for (std::string v; values >> v;) last = v;
          char* rest = nullptr;
          connectivity_length = std::strtoll(last.c_str(), &rest, 10);
          if (*rest != '\0' || connectivity_length < 0) fail(path, name + ": the last offset '" + last + "' is not a count");
        }
      }
    }
    for (const char* needed : {"connectivity", "offsets", "types"})
      if (std::find(seen.begin(), seen.end(), needed) == seen.end()) fail(path, name + " Cells has no '" + needed + "' array");
    if (connectivity && connectivity_length >= 0) check_array(*connectivity, name + " Cells", connectivity_length);
  }
}

// The text VTK is given: the file, with an empty <PointData/> added to every piece that has none.
// A piece may leave PointData out, but when one of its cell arrays then fails to read (too short),
// VTK 9.1 names the missing PointData element in its error message and dereferences null. With the
// empty element the same file gives VTK's own error ("the data array may be too short"). Raw appended
// data is not touched: the search stops at <AppendedData, and its offsets count from its own start.
std::string text_for_vtk(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  check_vtu_sizes(path, text);
  check_vtu_structure(path, text);
  const std::size_t appended = std::min(text.find("<AppendedData"), text.size());
  for (auto at = text.find("<Piece"); at < appended; at = text.find("<Piece", at + 1)) {
    const auto open_end = text.find('>', at);
    if (open_end >= appended) break;
    if (text[open_end - 1] == '/') continue;  // <Piece .../> holds nothing
    const auto close = std::min(text.find("</Piece", open_end), appended);
    const auto point_data = text.find("<PointData", open_end);
    if (point_data < close) continue;
    text.insert(open_end + 1, "<PointData/>");
  }
  return text;
}

}  // namespace

TetMesh read_vtu_tets(const fs::path& path, double scale) {
  const std::string text = text_for_vtk(path);
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  vtkNew<ErrorCollector> errors;
  reader->AddObserver(vtkCommand::ErrorEvent, errors);
  if (!reader->CanReadFile(path.string().c_str())) fail(path, "not a VTK XML unstructured grid");
  reader->ReadFromInputStringOn();
  reader->SetInputString(text);
  try {
    reader->Update();
  } catch (const std::bad_alloc&) {  // e.g. an offsets array announcing 4e17 connectivity entries
    fail(path, "VTK could not allocate what the file announces (a size beyond what it holds)");
  }
  if (!errors->message.empty() || reader->GetErrorCode() != 0) {
    std::string m = errors->message;
    m.erase(std::remove(m.begin(), m.end(), '\n'), m.end());
    fail(path, "VTK cannot read it" + (m.empty() ? std::string() : ": " + m));
  }
  vtkUnstructuredGrid* grid = reader->GetOutput();
  if (!grid || grid->GetNumberOfPoints() == 0) fail(path, "no points");

  TetMesh mesh;
  const vtkIdType n_points = grid->GetNumberOfPoints();
  mesh.vertices.reserve(std::size_t(n_points));
  for (vtkIdType i = 0; i < n_points; ++i) {
    double x[3];
    grid->GetPoint(i, x);
    const Vec3 p(x[0], x[1], x[2]);
    if (!p.allFinite()) fail(path, "point " + std::to_string(i) + " is not finite");
    mesh.vertices.push_back(scale * p);
  }
  // Tetrahedra (linear, or the corner nodes of quadratic ones); surface and line cells are skipped,
  // other volume cells refused.
  std::vector<vtkIdType> tet_cells, triangle_cells;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    const int type = grid->GetCellType(c);
    if (type == VTK_TETRA || type == VTK_QUADRATIC_TETRA) {
      vtkIdType n = 0;
      const vtkIdType* ids = nullptr;
      grid->GetCellPoints(c, n, ids);
      check_cell(path, c, n, 4, ids, n_points);
      std::array<std::uint32_t, 4> t{};
      for (int k = 0; k < 4; ++k) t[std::size_t(k)] = std::uint32_t(ids[k]);
      mesh.tets.push_back(t);
      tet_cells.push_back(c);
    } else if (type == VTK_TRIANGLE) {
      vtkIdType n = 0;
      const vtkIdType* ids = nullptr;
      grid->GetCellPoints(c, n, ids);
      check_cell(path, c, n, 3, ids, n_points);
      mesh.tagged_faces.push_back({std::uint32_t(ids[0]), std::uint32_t(ids[1]), std::uint32_t(ids[2])});
      triangle_cells.push_back(c);
    } else if (vtkCell* cell = other_cell(path, *grid, c); cell == nullptr) {
      fail(path, "cell " + std::to_string(c) + " has the unknown VTK cell type " + std::to_string(type));
    } else if (cell->GetCellDimension() == 3) {
      fail(path, "cell " + std::to_string(c) + " is a " + vtkCellTypes::GetClassNameFromTypeId(type) +
                     ": only tetrahedra are read");
    }
  }
  if (mesh.tets.empty()) fail(path, "no tetrahedra");

  std::vector<vtkIdType> all_points(static_cast<std::size_t>(n_points));
  for (vtkIdType i = 0; i < n_points; ++i) all_points[std::size_t(i)] = i;
  if (vtkDataArray* pf = find_array(grid->GetPointData(), fibre_names)) {
    mesh.fibre_location = TetMesh::FibreLocation::points;
    mesh.fibre = vectors(path, pf, all_points, "fibre");
    if (vtkDataArray* s = find_array(grid->GetPointData(), sheet_names)) mesh.sheet = vectors(path, s, all_points, "sheet");
  } else if (vtkDataArray* cf = find_array(grid->GetCellData(), fibre_names)) {
    mesh.fibre_location = TetMesh::FibreLocation::cells;
    mesh.fibre = vectors(path, cf, tet_cells, "fibre");
    if (vtkDataArray* s = find_array(grid->GetCellData(), sheet_names)) mesh.sheet = vectors(path, s, tet_cells, "sheet");
  }
  if (vtkDataArray* r = find_array(grid->GetCellData(), region_names)) {
    if (r->GetNumberOfComponents() != 1)
      fail(path, std::string("region array '") + r->GetName() + "' has " + std::to_string(r->GetNumberOfComponents()) +
                     " components, expected 1");
    if (r->GetNumberOfTuples() != grid->GetNumberOfCells())
      fail(path, std::string("region array '") + r->GetName() + "' has " + std::to_string(r->GetNumberOfTuples()) +
                     " values for " + std::to_string(grid->GetNumberOfCells()) + " cells");
    auto tag = [&](vtkIdType c) {
      const double value = r->GetComponent(c, 0);
      if (!(std::abs(value) < 1e9) || value != std::floor(value))
        fail(path, "cell " + std::to_string(c) + " has the region tag " + std::to_string(value) + ", not a whole number");
      return int(value);
    };
    for (vtkIdType c : tet_cells) mesh.tet_region.push_back(tag(c));
    for (vtkIdType c : triangle_cells) mesh.tagged_face_region.push_back(tag(c));
  }
  if (mesh.tagged_face_region.size() != mesh.tagged_faces.size()) mesh.tagged_faces.clear();  // untagged triangles
  for (const auto& f : mesh.tagged_faces)
    for (auto k : f)
      if (k >= mesh.vertices.size()) fail(path, "a triangle refers to point " + std::to_string(k) + " beyond the points");
  return mesh;
}

void write_vtu_tets(const TetMesh& mesh, const fs::path& path, double scale) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(vtkIdType(mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3 x = mesh.vertices[i] / scale;
    points->SetPoint(vtkIdType(i), x.x(), x.y(), x.z());
  }
  // Tetrahedra first, then the tagged triangles; cell arrays hold zeros for the triangles.
  const std::size_t n_triangles = mesh.tagged_faces.size(), n_cells = mesh.tets.size() + n_triangles;
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  grid->Allocate(vtkIdType(n_cells));
  for (const auto& t : mesh.tets) {
    const vtkIdType ids[4] = {t[0], t[1], t[2], t[3]};
    grid->InsertNextCell(VTK_TETRA, 4, ids);
  }
  for (const auto& f : mesh.tagged_faces) {
    const vtkIdType ids[3] = {f[0], f[1], f[2]};
    grid->InsertNextCell(VTK_TRIANGLE, 3, ids);
  }
  if (mesh.tet_region.size() == mesh.tets.size()) {
    vtkNew<vtkIntArray> region;
    region->SetName("region");
    region->SetNumberOfTuples(vtkIdType(n_cells));
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) region->SetValue(vtkIdType(t), mesh.tet_region[t]);
    for (std::size_t f = 0; f < n_triangles; ++f)
      region->SetValue(vtkIdType(mesh.tets.size() + f), f < mesh.tagged_face_region.size() ? mesh.tagged_face_region[f] : 0);
    grid->GetCellData()->AddArray(region);
  }
  const bool on_points = mesh.fibre_location == TetMesh::FibreLocation::points;
  auto add_vectors = [&](const std::vector<Vec3>& v, const char* name) {
    if (v.empty()) return;
    const std::size_t rows = on_points ? v.size() : n_cells;
    vtkNew<vtkDoubleArray> a;
    a->SetName(name);
    a->SetNumberOfComponents(3);
    a->SetNumberOfTuples(vtkIdType(rows));
    for (std::size_t i = 0; i < rows; ++i) {
      const Vec3 x = i < v.size() ? v[i] : Vec3::Zero();
      a->SetTuple3(vtkIdType(i), x.x(), x.y(), x.z());
    }
    if (on_points)
      grid->GetPointData()->AddArray(a);
    else
      grid->GetCellData()->AddArray(a);
  };
  add_vectors(mesh.fibre, "fibre");
  add_vectors(mesh.sheet, "sheet");

  try {
    sph::write_unstructured_grid(*grid, path);
  } catch (const std::runtime_error& error) {
    throw MeshError(std::string("write_tet_mesh: ") + error.what());
  }
}

}  // namespace geometry::detail
